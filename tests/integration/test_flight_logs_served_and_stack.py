"""Every tool on a PX4 ULog, an ArduPilot DataFlash log, JSON and protobuf MCAP in both ways of running:
`bagmcp serve` over a folder (with a firmware .bin it must not list) and the distributed stack (uploads,
ingest and long work in Celery workers)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import anyio
import pytest

from tests.checks.flight_checks import check_cancelled_filter, check_flight_logs, ended, one_line_refusal
from tests.fixtures.corpus_expectations import READABLE, pymavlink_times, pyulog_counts
from tests.fixtures.flight_files import NAMES, write_firmware, write_flight_files
from tests.fixtures.mcp_client import call, http_client, text_of
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port
from tests.integration.stack import TOKEN, Stack
from tests.integration.test_tools_on_recorded_corpus import PER_BAG

pytestmark = pytest.mark.anyio
DATA_TAMER = "edge_cases/mcap_non_ros_profile_data_tamer.mcap"
EKF = "flight_review_ekf_failure_manual_flight"


@pytest.fixture(scope="module")
def flight_files(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    return write_flight_files(tmp_path_factory.mktemp("flights"))


@pytest.fixture(scope="module")
def served(flight_files: list[Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    folder = flight_files[0].parent
    write_firmware(folder)
    port = free_port()
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port)]
    # no time budget: every long call answers with its job (followed with get_job; cancel_job needs one)
    env = {"BAGMCP_DATA_DIR": str(tmp_path_factory.mktemp("data")), "BAGMCP_JOB_BUDGET_S": "0"}
    url = f"http://127.0.0.1:{port}"
    with service(
        "serve-flights", command, env=env, log_dir=tmp_path_factory.mktemp("logs"), ready=http_ok(f"{url}/healthz")
    ):
        yield url


async def test_every_tool_answers_on_flight_logs_through_the_embedded_server(served: str) -> None:
    async with http_client(f"{served}/mcp", None) as client:
        with anyio.fail_after(120):
            while any(b["status"] == "ingesting" for b in (await call(client, "list_bags"))["bags"]):
                await anyio.sleep(0.2)
        listed = {b["name"] for b in (await call(client, "list_bags"))["bags"]}
        assert listed == set(NAMES)  # the firmware .bin is no recording
        await check_flight_logs(client)


async def test_every_tool_answers_on_uploaded_flight_logs_through_the_stack(
    stack: Stack, flight_files: list[Path]
) -> None:
    names = [str(stack.upload_ok(path)["name"]) for path in flight_files]
    assert names == list(NAMES)
    await stack.wait_ready(names)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_flight_logs(client, cancel=False)


def _library_counts(corpus: Path, path: Path) -> tuple[dict[str, int], float | None]:
    """Topics and counts as the in-process corpus tests expect them (pyulog's, pymavlink's, SOURCES.md's), and
    the duration pyulog gives a ULog."""
    if path.suffix == ".ulg":
        return pyulog_counts(path)
    if path.suffix == ".bin":
        return {topic: len(times) for topic, times in pymavlink_times(path).items()}, None
    return READABLE[str(path.relative_to(corpus))], None


@pytest.mark.corpus
async def test_the_corpus_flight_logs_and_data_tamer_mcap_read_the_same_through_the_stack(
    stack: Stack, corpus: Path
) -> None:
    paths = [*sorted((corpus / "px4_ulog").glob("*.ulg")), *sorted((corpus / "ardupilot").glob("*.bin"))]
    paths.append(corpus / DATA_TAMER)
    names = [str(stack.upload_ok(path)["name"]) for path in paths]
    await stack.wait_ready(names, timeout_s=300)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        for path, name in zip(paths, names, strict=True):
            counts, duration_s = _library_counts(corpus, path)
            info = await call(client, "bag_info", bag=name)
            assert {t["name"]: t["count"] for t in info["topics"]} == counts, name
            if duration_s is not None:
                assert info["duration_s"] == pytest.approx(duration_s, abs=1e-6), name
            for tool, extra in PER_BAG:  # an answer (followed to the job's end) or a one-line reason
                answer = await client.call_tool(tool, {"bag": name, **extra})
                if answer.is_error:
                    one_line_refusal(text_of(answer), tool)
                elif answer.structured_content and "job" in answer.structured_content:
                    job = await ended(client, answer.structured_content["job"]["job_id"])
                    assert job["state"] == "succeeded" or (job["state"], "\n" in job["error"]) == ("failed", False), job
        # the stack's time budget (1 s) is shorter than copying the EKF flight's 49,829 messages here
        await check_cancelled_filter(client, EKF, topic=None, need_job=False)
