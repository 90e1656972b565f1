"""``python -m bench.fleet [--count 500]``: questions across many short bags (issue 22's targets).

Writes the short drives (cached), times what feeding the columnar store adds to ingest (in one process,
as a ratio), then serves the bags embedded (``bagmcp serve``) and on the local stack (uploaded over REST)
and times "max speed per bag", "bags with an ERROR log" and "bags within 0.5 m of (3, 0)" as MCP calls
over HTTP, warm (after one cold call, whose answer is checked against the drives' known values). Prints
the rows and writes them to ``--out`` (default BENCHMARKS.fleet.md)."""

from __future__ import annotations

import argparse
import io
import tarfile
import tempfile
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path

import anyio
import httpx

from bench.client import Endpoint
from bench.fleet_bags import ShortDrive, fleet_bags
from bench.fleet_measure import Asked, IngestCost, ask, ingest_cost
from bench.machine import Machine
from bench.servers import wait_ready
from tests.fixtures.drive_bags import write_drive_bags
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import _redis_process, _weed_process, free_port
from tests.integration.stack import TOKEN, start_stack

TARGET_MS, INGEST_TARGET = 500.0, 0.10
ENV = {"BAGMCP_JOB_BUDGET_S": "120"}


@contextmanager
def _embedded(folder: Path, work: Path) -> Iterator[Endpoint]:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(work / "data")]
    with service("fleet-serve", command, env=ENV, log_dir=work, ready=http_ok(f"{url}/healthz")):
        yield Endpoint(f"{url}/mcp", None)


def _body(path: Path) -> bytes:
    if path.is_file():
        return path.read_bytes()
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as archive:
        archive.add(path, arcname=path.name)
    return buffer.getvalue()


@contextmanager
def _stack(folder: Path, work: Path) -> Iterator[Endpoint]:
    with ExitStack() as exits:
        redis_url = exits.enter_context(_redis_process())
        running = start_stack(redis_url, exits.enter_context(_weed_process()), work, exits, env=ENV)
        running.start_worker()  # two bag-store workers share the ingest
        with httpx.Client(base_url=f"{running.url}/api/v1", headers={"Authorization": f"Bearer {TOKEN}"}) as rest:
            for path in sorted(folder.iterdir()):
                name = path.name.removesuffix(".bag")
                sent = rest.post(
                    "/bags",
                    params={"filename": f"{name}.tar" if path.is_dir() else path.name, "name": name},
                    content=_body(path),
                    timeout=120,
                )
                sent.raise_for_status()
        yield Endpoint(f"{running.url}/mcp", TOKEN)


def _mode(
    mode: str, folder: Path, drives: list[ShortDrive], work: Path, repeats: int
) -> tuple[float, dict[str, Asked]]:
    began = time.monotonic()
    server = _embedded(folder, work) if mode == "embedded" else _stack(folder, work)
    with server as endpoint:
        anyio.run(lambda: wait_ready(endpoint, len(drives)))
        ready_s = time.monotonic() - began
        print(f"[fleet] {mode}: {len(drives)} bags ready in {ready_s:.0f} s", flush=True)
        return ready_s, anyio.run(lambda: ask(endpoint, drives, repeats=repeats))


def _report(
    machine: Machine, count: int, costs: dict[str, IngestCost], modes: dict[str, tuple[float, dict[str, Asked]]]
) -> str:
    lines = [
        f"# Questions across bags: {count} short bags (`python -m bench.fleet --count {count}`)",
        "",
        f"Machine: {machine.cores} cores ({machine.cpu}), {machine.memory_gib} GiB, Python {machine.python}, commit "
        f"{machine.commit}, shared with other work (ratios in one run hold better than absolute times). Warm = median "
        "of the repeated calls after one cold call (MCP over HTTP).",
        "",
        "| mode | question | cold ms | warm median ms | warm p95 ms | target | met |",
        "|---|---|---|---|---|---|---|",
    ]
    for mode, (_, asked) in modes.items():
        for label, one in asked.items():
            met = "yes" if one.warm.median_ms < TARGET_MS else "no"
            lines.append(
                f"| {mode} | {label} | {one.cold_ms:.0f} | {one.warm.median_ms:.1f} | {one.warm.p95_ms:.1f} "
                f"| < {TARGET_MS:.0f} ms | {met} |"
            )
    lines += ["", "| ingest | figure |", "|---|---|"]
    for label, cost in costs.items():
        lines.append(
            f"| writing the views vs the rest of ingest, {label} ({cost.bags} bags, one process) | "
            f"{cost.fleet_s:.2f} s vs {cost.ingest_s:.2f} s = {cost.ratio:.1%} (target < {INGEST_TARGET:.0%}: "
            f"{'met' if cost.ratio < INGEST_TARGET else 'missed'}) |"
        )
    lines.extend(f"| {mode}: every bag ready after start | {ready_s:.0f} s |" for mode, (ready_s, _) in modes.items())
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m bench.fleet", description=__doc__)
    parser.add_argument("--count", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--modes", default="embedded,stack")
    parser.add_argument("--dir", type=Path, default=Path(".bench"))
    parser.add_argument("--out", type=Path, default=Path("BENCHMARKS.fleet.md"))
    args = parser.parse_args()
    folder, drives = fleet_bags(args.dir, args.count)
    with tempfile.TemporaryDirectory(prefix="bench-drives-") as tmp:
        drives_60s = sorted(write_drive_bags(Path(tmp)).values()) * 3
        costs = {
            "10 s short drives": ingest_cost(sorted(folder.iterdir())[:33]),
            "60 s drives of tests/fixtures": ingest_cost(drives_60s),
        }
    for label, cost in costs.items():
        print(
            f"[fleet] ingest, {label}: views {cost.fleet_s:.2f} s vs the rest {cost.ingest_s:.2f} s ({cost.ratio:.1%})"
        )
    modes = {}
    for mode in [m for m in args.modes.split(",") if m]:  # --modes "": the ingest rows only
        work = args.dir / f"fleet-run-{mode}-{int(time.time())}"
        work.mkdir(parents=True)
        modes[mode] = _mode(mode, folder, drives, work, args.repeat)
    report = _report(Machine.here(), args.count, costs, modes)
    args.out.write_text(report)
    print(report)


if __name__ == "__main__":
    main()
