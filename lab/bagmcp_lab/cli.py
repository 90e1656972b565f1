"""``bagmcp lab run`` and ``bagmcp lab report``: the benchmark from a shell (the ``bagmcp`` command parses the
arguments and imports this module only when a lab command runs)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import anyio

from bagmcp_lab.errors import LabError
from bagmcp_lab.providers import ProviderChoice
from bagmcp_lab.providers.factory import key_from_env
from bagmcp_lab.report import write_report, write_tasks
from bagmcp_lab.results import RunRecord, read_results, write_results
from bagmcp_lab.runner import BenchmarkPlan, run_benchmark
from bagmcp_lab.tasks.suites import Suite, check_suite_name


def _say(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


async def _run(plan: BenchmarkPlan, out: Path) -> list[RunRecord]:
    records: list[RunRecord] = []

    async def on_suite(suite: Suite) -> None:
        write_tasks(out, suite.tasks)
        for name, why in suite.skipped.items():
            _say(f"bagmcp lab: skipped {name}: {why}")
        _say(f"bagmcp lab: {len(suite.tasks)} tasks x {plan.repeat} on {plan.bag} with {plan.choice.model}")

    async def on_record(record: RunRecord, done: int, planned: int) -> None:
        records.append(record)
        write_results(out, records)
        mark = "ok  " if record.success else "FAIL"
        _say(
            f"[{done}/{planned}] {mark} {record.task} ({record.n_tool_calls} calls, {record.latency_s:.1f} s): "
            + record.reason
        )

    await run_benchmark(plan, on_record=on_record, on_suite=on_suite)
    return records


def run_command(
    *,
    url: str,
    token: str | None,
    provider: str,
    model: str,
    base_url: str | None,
    api_key_env: str | None,
    bag: str,
    tasks: str,
    repeat: int,
    max_turns: int,
    out: Path,
    images: bool = True,
) -> int:
    if repeat < 1 or max_turns < 1:
        raise LabError("--repeat and --max-turns must be at least 1")
    check_suite_name(tasks)
    key = key_from_env(provider, os.environ, variable=api_key_env, base_url=base_url)
    choice = ProviderChoice(provider, model, key, base_url, images)
    plan = BenchmarkPlan(url, token, choice, bag, tasks, repeat, max_turns)
    records = anyio.run(_run, plan, out)
    write_results(out, records)
    report = write_report(out, records)
    wins = sum(r.success for r in records)
    print(f"{wins}/{len(records)} runs succeeded; {out / 'results.json'} and {report}")
    return 0


def report_command(*, directories: list[Path], out: Path | None) -> int:
    records = [record for directory in directories for record in read_results(directory)]
    if not records:
        raise LabError("the result directories hold no runs")
    target = out or directories[0]
    report = write_report(target, records, sources=directories)
    print(f"{len(records)} runs from {len(directories)} directories; {report}")
    return 0
