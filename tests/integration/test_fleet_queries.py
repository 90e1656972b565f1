"""Questions across bags in both ways of running, over HTTP: ``bagmcp serve`` over the drive bags and the
stack with them uploaded. query_bags and find_bags agree with the per-bag tools; GET /api/v1/query answers
JSON, CSV and Parquet under the same rules; a limited token sees only what its tools would (its own
``x-bagmcp-tools`` header changes nothing); deleting a bag removes its Parquet files."""

from __future__ import annotations

import contextlib
import io
import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import anyio
import httpx
import pyarrow.parquet as pq
import pytest

from bagmcp_bag_store.settings import DEFAULT_QUERY_LIMITS
from bagmcp_cli.main import main as cli_main
from bagmcp_kit.identity import TOOLS_HEADER
from tests.checks.fleet_checks import check_fleet, check_refusals, long, query
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.mcp_client import call, call_error, http_client
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port
from tests.integration.stack import TOKEN, Stack, new_token

pytestmark = pytest.mark.anyio
ADMIN = "fleet-admin-token"
SPEEDS = "SELECT bag, max(speed) AS top FROM poses WHERE topic = '/odom' GROUP BY bag ORDER BY bag"
LIMITED = ("--allow", "query_bags", "--allow", "analyze_trajectory", "--allow", "get_job")
GLOBBED = ("--allow", "*_bags", "--allow", "analyze_*", "--allow", "get_job", "--deny", "analyze_l*")
PROFILED = ("--profile", "core")  # the small models' tools: no query_bags nor find_bags
REST_ROWS = DEFAULT_QUERY_LIMITS.rest_max_rows


@dataclass(frozen=True)
class Tokens:
    """Limited tokens: tools by exact names, by allow and deny globs, by profile; one without query_bags."""

    limited: str
    globbed: str
    profiled: str
    lister: str


@pytest.fixture(scope="module")
def served(drive_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    folder = copy_bags(list(drive_bags.values()), tmp_path_factory.mktemp("fleet-serve") / "bags")
    data, port = tmp_path_factory.mktemp("fleet-data"), free_port()
    url = f"http://127.0.0.1:{port}"
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--token", ADMIN]
    command += ["--data", str(data)]
    logs = tmp_path_factory.mktemp("logs")
    with service("fleet-serve", command, env={}, log_dir=logs, ready=http_ok(f"{url}/healthz")):
        yield url, data


@pytest.fixture(scope="module")
def stack_drive(stack: Stack, drive_bags: dict[BagKind, Path]) -> list[str]:
    names = [str(stack.upload_ok(path)["name"]) for path in drive_bags.values()]
    anyio.run(stack.wait_ready, names)
    return names


async def _ready(url: str, token: str, count: int) -> None:
    async with http_client(f"{url}/mcp", token) as client:
        with anyio.fail_after(120):
            while (await query(client, "SELECT count(*) FROM bags"))["rows"][0][0] < count:
                await anyio.sleep(0.3)


def _rest(url: str, token: str, sql: str, form: str = "json", **headers: str) -> httpx.Response:
    auth = {"Authorization": f"Bearer {token}", **headers}
    return httpx.get(f"{url}/api/v1/query", params={"sql": sql, "format": form}, headers=auth, timeout=60)


def _check_rest(url: str, token: str, expected: dict[str, float]) -> None:
    answer = _rest(url, token, SPEEDS).json()
    speeds = {row[0]: row[1] for row in answer["rows"]}
    assert {name: speeds[name] for name in expected} == pytest.approx(expected)
    csv = _rest(url, token, SPEEDS, "csv")
    assert csv.headers["content-type"].startswith("text/csv")
    assert csv.text.splitlines()[0] == '"bag","top"'
    parquet = _rest(url, token, SPEEDS, "parquet")
    table = pq.read_table(io.BytesIO(parquet.content))
    assert dict(zip(table.column("bag").to_pylist(), table.column("top").to_pylist(), strict=True)) == pytest.approx(
        speeds
    )
    assert parquet.headers["x-total-rows"] == str(len(speeds))
    refused = _rest(url, token, "COPY poses TO '/tmp/x.csv'")
    assert refused.status_code == 400
    assert "only SELECT" in refused.json()["error"]["message"]
    _check_rest_limit(url, token)


def _check_rest_limit(url: str, token: str) -> None:
    """A download stops at the REST row limit and says so; one of exactly that many rows is whole."""
    pairs = "SELECT a.t FROM poses a, poses b LIMIT"
    over = _rest(url, token, f"{pairs} {REST_ROWS + 1}", "csv")
    assert (over.headers["x-total-rows"], over.headers["x-truncated"]) == (str(REST_ROWS + 1), "true")
    assert len(over.text.splitlines()) == 1 + REST_ROWS  # the header line, then the first rows only
    whole = _rest(url, token, f"{pairs} {REST_ROWS}", "parquet")
    assert (whole.headers["x-total-rows"], whole.headers["x-truncated"]) == (str(REST_ROWS), "false")
    assert pq.read_table(io.BytesIO(whole.content)).num_rows == REST_ROWS


async def _check_limited(url: str, tokens: Tokens, names: list[str]) -> None:
    async with http_client(f"{url}/mcp", tokens.limited) as client:
        await query(client, SPEEDS)
        assert "may not read the logs view" in await call_error(client, "query_bags", sql="SELECT * FROM logs")
    forged = _rest(url, tokens.limited, "SELECT count(*) FROM logs", **{TOOLS_HEADER: "query_bags,analyze_logs"})
    assert forged.status_code == 403
    assert _rest(url, tokens.limited, SPEEDS).status_code == 200
    assert _rest(url, tokens.lister, SPEEDS).status_code == 403
    await _check_globbed(url, tokens.globbed, names)
    await _check_profiled(url, tokens.profiled)


async def _check_globbed(url: str, token: str, names: list[str]) -> None:
    """``--allow '*_bags' --allow 'analyze_*' --deny 'analyze_l*'``: poses (analyze_trajectory) and the bag list
    (list_bags), not logs (analyze_logs) nor scans (analyze_lidar_scan), in query_bags, find_bags and REST. The
    server may hold other bags than ``names`` (the session's stack serves other tests too)."""
    async with http_client(f"{url}/mcp", token) as client:
        tools = {t.name for t in (await client.list_tools()).tools}
        assert {"query_bags", "find_bags", "list_bags", "analyze_trajectory"} <= tools
        assert not tools & {"analyze_logs", "analyze_lidar_scan", "search_messages", "bag_info"}
        wanted = ", ".join(f"'{n}'" for n in names)
        listed = await query(client, f"SELECT bag FROM bags WHERE bag IN ({wanted}) ORDER BY bag")
        assert listed["rows"] == [[n] for n in sorted(names)]
        for view in ("logs", "scans", "topics"):
            refused = await call_error(client, "query_bags", sql=f"SELECT count(*) FROM {view}")
            assert f"may not read the {view} view" in refused, (view, refused)
        found = await long(client, "find_bags", speed_above=0.4)
        assert set(names) <= {m["bag"] for m in found["matches"]}  # the drives reach 0.5 m/s
        assert "logs" in await call_error(client, "find_bags", log_level="ERROR")
        assert "scans" in await call_error(client, "find_bags", scan_below=0.5)
    assert _rest(url, token, SPEEDS).status_code == 200
    for sql in ("SELECT count(*) FROM logs", "SELECT min(min_range) FROM scans"):
        forbidden = _rest(url, token, sql)
        assert forbidden.status_code == 403, sql
        assert "may not read" in forbidden.json()["error"]["message"]


async def _check_profiled(url: str, token: str) -> None:
    """A ``core`` profile token: the per-bag tools of its profile, no questions across bags at all."""
    async with http_client(f"{url}/mcp", token) as client:
        names = {t.name for t in (await client.list_tools()).tools}
        assert "analyze_trajectory" in names
        assert not names & {"query_bags", "find_bags"}
        assert "not enabled" in await call_error(client, "query_bags", sql="SELECT 1")
        assert "not enabled" in await call_error(client, "find_bags", speed_above=0.4)
        await call(client, "list_bags")
    assert _rest(url, token, SPEEDS).status_code == 403


async def test_serve_answers_across_bags_like_the_per_bag_tools(served: tuple[str, Path]) -> None:
    url, data = served
    await _ready(url, ADMIN, 3)
    names = ["drive", "drive_db3", "drive_mcap"]
    async with http_client(f"{url}/mcp", ADMIN) as client:
        await check_fleet(client, names)
        await check_refusals(client)
        speeds = {row[0]: row[1] for row in (await query(client, SPEEDS))["rows"]}
    _check_rest(url, ADMIN, speeds)

    def made(name: str, *options: str) -> str:
        """`bagmcp token create NAME ... --data D` (the command's code in this process: each run of the command
        is a Python start, seconds on a busy machine); the running server reads the tokens file there."""
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            assert cli_main(["token", "create", name, *options, "--data", str(data), "--json"]) == 0
        return str(json.loads(printed.getvalue())["token"])

    tokens = Tokens(
        made("traj", *LIMITED),
        made("globbed", *GLOBBED),
        made("core", *PROFILED),
        made("lister", "--allow", "list_bags"),
    )
    await _check_limited(url, tokens, names)


async def test_the_stack_answers_across_bags_like_the_per_bag_tools(stack: Stack, stack_drive: list[str]) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_fleet(client, stack_drive)
        speeds = {row[0]: row[1] for row in (await query(client, SPEEDS))["rows"]}
    _check_rest(stack.url, TOKEN, {name: speeds[name] for name in stack_drive})
    tokens = Tokens(
        new_token(stack, "traj", *LIMITED),
        new_token(stack, "globbed", *GLOBBED),
        new_token(stack, "core", *PROFILED),
        new_token(stack, "lister", "--allow", "list_bags"),
    )
    await _check_limited(stack.url, tokens, stack_drive)


async def test_deleting_a_bag_removes_its_parquet_files_and_its_rows(stack: Stack, stack_drive: list[str]) -> None:
    bag = stack.bags()[stack_drive[1]]
    views = f"indexes/{bag['id']}/columns/fleet."
    assert len([key for key in stack.objects() if key.startswith(views)]) == 9  # every view but battery
    assert stack.rest("DELETE", f"bags/{bag['id']}").status_code == 204
    assert not [key for key in stack.objects() if bag["id"] in key]
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        names = {row[0] for row in (await query(client, "SELECT bag FROM bags"))["rows"]}
    assert stack_drive[1] not in names
