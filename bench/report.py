"""BENCHMARKS.md from a run: the machine, the bags, the targets met or not, every call per mode and format
next to its rosbags floor, the gateway, the load tests, and the profiles of what missed."""

from __future__ import annotations

import time
from collections.abc import Iterator

from bench.calls import CALLS, BenchCall
from bench.floors import FLOORS
from bench.machine import load_by_phase
from bench.measure import CallResult
from bench.profile import Profile
from bench.report_cold import sections as cold_sections
from bench.report_cold import target_rows as cold_target_rows
from bench.report_parts import FLOOR_LABELS, ms, table, yes
from bench.report_upload import sections as upload_sections
from bench.report_upload import target_rows as upload_target_rows
from bench.results import (
    CHEAP_CALLS_PER_S,
    CHEAP_P99_MS,
    GATEWAY_MEDIAN_MS,
    GATEWAY_P95_MS,
    THROUGHPUT_CLIENTS,
    ModeResult,
    RunResult,
    cold_limit_ms,
    cold_met,
    gateway_met,
    throughput_met,
    warm_met,
)
from bench.stats import Timing

TARGET_MODE = "embedded"  # the issues state the per-call targets for the embedded server
_ms, _yes, _table = ms, yes, table


def _floor(run: RunResult, kind: str, key: str | None) -> Timing | None:
    return run.floors.get(kind, {}).get(key) if key else None


def _target_text(result: CallResult, floor: Timing | None) -> str:
    target = result.call.target
    parts = []
    if target is not None and target.warm_ms is not None:
        parts.append(f"warm < {target.warm_ms:g}")
    limit = cold_limit_ms(result, floor)
    if limit is not None and target is not None:
        parts.append(
            f"cold < {_ms(limit)} ({target.cold_floor_factor:g}x floor{' + warm' if target.cold_plus_warm else ''})"
        )
    return "; ".join(parts)


def _call_rows(run: RunResult, kind: str, results: list[CallResult]) -> list[list[str]]:
    rows = []
    for result in results:
        floor = _floor(run, kind, result.call.floor)
        met = [m for m in (warm_met(result), cold_met(result, floor)) if m is not None]
        ratio = (
            f"{result.warm.median_ms / floor.median_ms:.2f} / {result.cold.median_ms / floor.median_ms:.2f}"
            if floor
            else ""
        )
        rows.append(
            [
                result.call.label,
                _ms(result.cold.median_ms),
                _ms(result.warm.median_ms),
                _ms(result.warm.p95_ms),
                _target_text(result, floor),
                _yes(all(met) if met else None),
                f"{_ms(floor.median_ms)} ({FLOOR_LABELS[result.call.floor or '']})" if floor else "",
                ratio,
            ]
        )
    return rows


def _worst(run: RunResult, mode: ModeResult, call: BenchCall, *, cold: bool) -> tuple[str, bool | None]:
    """The worst format's figure for one target in one mode, and whether every format met it."""
    found = [(kind, r) for kind, results in mode.bags.items() for r in results if r.call is call]
    if not found:
        return "", None
    if cold:
        limits = [(r.cold.median_ms, cold_limit_ms(r, _floor(run, kind, call.floor))) for kind, r in found]
        value, limit = max(limits, key=lambda pair: pair[0] / (pair[1] or 1))
        mets = [cold_met(r, _floor(run, kind, call.floor)) for kind, r in found]
        return f"{_ms(value)} (limit {_ms(limit or 0)})", all(m for m in mets if m is not None)
    value = max(r.warm.median_ms for _, r in found)
    return _ms(value), all(warm_met(r) for _, r in found)


def _target_rows(run: RunResult) -> list[list[str]]:
    rows = []
    for call in CALLS:
        target = call.target
        if target is None:
            continue
        checks = [(False, f"warm {call.label} < {target.warm_ms:g} ms")] if target.warm_ms is not None else []
        if target.cold_floor_factor is not None:
            extra = " + its warm time" if target.cold_plus_warm else ""
            checks.append((True, f"cold {call.label} < {target.cold_floor_factor:g}x floor{extra}"))
        for cold, text in checks:
            cells = [_worst(run, mode, call, cold=cold) for mode in run.modes]
            judged = [m for mode, (_, m) in zip(run.modes, cells, strict=True) if mode.mode == TARGET_MODE]
            met = judged[0] if judged else None
            rows.append([text, str(target.issue), *(v for v, _ in cells), _yes(met)])
    for mode in run.modes:
        rows.extend(_mode_target_rows(run, mode))
    return rows


def _mode_target_rows(run: RunResult, mode: ModeResult) -> list[list[str]]:
    blanks = ["" for _ in run.modes]
    column = [m.mode for m in run.modes].index(mode.mode)
    rows = []

    def row(text: str, issue: str, value: str, met: bool) -> list[str]:
        cells = list(blanks)
        cells[column] = value
        return [text, issue, *cells, _yes(met)]

    if mode.overhead:
        worst = max(mode.overhead, key=lambda o: o.added_median_ms)
        text = f"gateway adds < {GATEWAY_MEDIAN_MS:g} ms median, < {GATEWAY_P95_MS:g} ms p95"
        value = f"{_ms(worst.added_median_ms)} / {_ms(max(o.added_p95_ms for o in mode.overhead))} ms"
        rows.append(row(text, "11, 13", value, all(gateway_met(o) for o in mode.overhead)))
    for load in mode.loads:
        value = f"{load.calls_per_s:,.0f} calls/s, p99 {_ms(load.timing.p99_ms)} ms, {len(load.errors)} errors"
        if load.clients == THROUGHPUT_CLIENTS:
            text = f"{load.clients} clients: >= {CHEAP_CALLS_PER_S:g} cheap calls/s, p99 < {CHEAP_P99_MS:g} ms"
            rows.append(row(text, "11, 14", value, throughput_met(load)))
        else:
            text = f"{load.clients} clients x {load.calls_each} calls: no errors"
            rows.append(row(text, "13, 14", value, not load.errors))
    return rows


def _mode_section(run: RunResult, mode: ModeResult) -> Iterator[str]:
    yield f"## {mode.mode}"
    yield ""
    if mode.error:
        yield f"**Not measured to the end**: {mode.error} (the run's output has the traceback)."
        yield ""
    if mode.mode == "embedded":
        yield f"Every bag ready {mode.ready_s:.1f} s after start."
    else:  # each upload waited until its bag was ready
        yield 'Every bag uploaded and ready before the first call (see "stack, upload to ready").'
    yield ""
    header = ["call", "cold ms", "warm median ms", "warm p95 ms", "target", "", "floor ms", "warm / cold vs floor"]
    for kind, results in mode.bags.items():
        yield f"### {mode.mode}, {kind}"
        yield ""
        yield from _table(header, _call_rows(run, kind, results))
    if mode.overhead:
        yield f"### {mode.mode}: the gateway next to the bag-store called directly (warm, interleaved)"
        yield ""
        rows = [
            [
                o.label,
                f"{_ms(o.gateway.median_ms)} / {_ms(o.gateway.p95_ms)}",
                f"{_ms(o.direct.median_ms)} / {_ms(o.direct.p95_ms)}",
                f"{_ms(o.added_median_ms)} / {_ms(o.added_p95_ms)}",
                str(len(o.gateway)),
            ]
            for o in mode.overhead
        ]
        yield from _table(["call", "gateway median / p95 ms", "direct", "added", "calls"], rows)
    if mode.loads:
        yield f"### {mode.mode}: concurrent clients (bag_info and get_message_at_time in turn)"
        yield ""
        rows = [
            [
                f"{load.clients} x {load.calls_each}",
                f"{load.calls_per_s:,.0f}",
                _ms(load.timing.median_ms),
                _ms(load.timing.p99_ms),
                str(len(load.errors)),
                ", ".join(f"{name} {ms:.1f}" for name, ms in load.cpu_ms_per_call.items() if ms >= 0.05),
                (load.errors[0][:120] if load.errors else ""),
            ]
            for load in mode.loads
        ]
        header = ["clients x calls", "calls/s", "p50 ms", "p99 ms", "errors", "CPU ms per call", "first error"]
        yield from _table(header, rows)


def _profile_section(profile: Profile) -> Iterator[str]:
    yield f"### {profile.label} ({profile.process}, {profile.samples} samples)"
    yield ""
    rows = [[f"`{h.frame}`", f"{h.self_pct:.1f}", f"{h.total_pct:.1f}"] for h in profile.top_self]
    yield from _table(["own time: frame", "own %", "inside %"], rows)
    rows = [[f"`{h.frame}`", f"{h.total_pct:.1f}", f"{h.self_pct:.1f}"] for h in profile.top_project]
    yield from _table(["project frames: frame", "inside %", "own %"], rows)


def _load_lines(run: RunResult) -> list[str]:
    """The machine's load while each phase ran (other work shares the cores: say so beside the figures)."""
    if not run.load:
        return []
    phases = "; ".join(f"{phase} {median:.1f} (max {peak:.1f})" for phase, median, peak in load_by_phase(run.load))
    return [
        f"1-minute load average while the run went, median by phase, sampled every 10 s ({run.machine.cores} "
        f"cores; the benchmark's own servers and client count too): {phases}.",
        "",
    ]


def render(run: RunResult, *, notes: str) -> str:
    """The whole page; ``notes`` (markdown written by hand after looking at a run) says why targets are missed."""
    machine = run.machine
    lines = [
        "# Benchmarks",
        "",
        "Written by `make bench` (`python -m bench`"
        + (" --quick, a small smoke run: its figures say nothing about the targets" if run.quick else "")
        + f") on {time.strftime('%Y-%m-%d')} at commit {machine.commit}, in {run.wall_s / 60:.1f} minutes. "
        "Every figure in the tables is an MCP call as a client makes it: the official `mcp` client over "
        "streamable HTTP on loopback, timed from the call to its answer. *Cold* is the first call of that "
        "tool on that bag after ingest (in the order of the tables, so earlier rows may have opened the "
        f"bag); *warm* is the median (and p95) of {run.repeats} further calls with varying times. The "
        "*floor* is the same work done by a script with rosbags (`AnyReader`: open the bag, decode the "
        "messages), median of the same count. The notes after the targets quote one-off measurements "
        "(CPU, profiles, in-process timings) named as such.",
        "",
        "## Machine",
        "",
        f"{machine.cores} cores ({machine.cpu}), {machine.memory_gib} GiB RAM, Python {machine.python}, "
        f"{machine.system}. The bench client runs on the same cores as the servers.",
        "",
        *_load_lines(run),
        "## Bags",
        "",
    ]
    rows = [[b.kind, b.path.name, f"{b.size_bytes:,}", f"{b.duration_s:g}"] for b in run.bags]
    lines += _table(["format", "bag", "bytes", "duration s"], rows)
    lines += [
        "A drive (bench/drive.py): /odom and /tf at 100 Hz, /cmd_vel at 20 Hz, /scan (720 beams) and 1 MB mono8 "
        "images at 10 Hz, /rosout at 1 Hz, /tf_static.",
        "",
        "## Targets",
        "",
    ]
    if run.modes:  # a run of only the cold passes or the uploads made no call in either mode
        lines += [
            "Per-call targets are judged on the embedded server, as the issues state them (the worst of the three "
            "formats is shown); the stack's figures stand beside them for comparison. The gateway and load targets "
            "are judged where they were measured.",
            "",
        ]
        lines += _table(["target", "issue", *(m.mode for m in run.modes), ""], _target_rows(run))
    cold_rows = cold_target_rows(run) + upload_target_rows(run)
    if cold_rows:
        lines += ["### The stack (issue 21): cold reads from S3, upload to ready, caches on disk", ""]
        lines += _table(["target", "format", "figure", "limit", ""], cold_rows)
    lines += [notes.strip(), ""] if notes.strip() else []
    lines += ["", "## rosbags floors (median ms)", ""]
    kinds = [b.kind for b in run.bags]
    rows = [[f.label, *(_ms(run.floors[k][f.key].median_ms) for k in kinds)] for f in FLOORS]
    lines += _table(["floor", *kinds], rows)
    for mode in run.modes:
        lines += list(_mode_section(run, mode))
    lines += list(upload_sections(run))
    lines += list(cold_sections(run))
    profiles = [p for m in run.modes for p in m.profiles] + [p for c in run.cold for p in c.profiles]
    if profiles:
        lines += ["## Profiles", "", "py-spy on the serving process while the work ran (idle threads left out).", ""]
        for profile in profiles:
            lines += list(_profile_section(profile))
    return "\n".join(lines) + "\n"
