"""The stack's cold rows (issue 21): every tool's first call on a bag its service has never read, with the
bytes it fetched from S3; the same with 20 ms added to every S3 request; and every tool on a bag four
times larger than the block cache, answers checked against the cold pass's and the caches' disk use
watched.

Cold, as measured here: before each tool's cold call the three services and their workers are restarted
with new, empty data directories (no block cache, whole copy, local index or opened bag left), reading
S3 through the bench's proxy; then the same tool is called once on a small warm-up bag of the same
format, so the process has imported its code, compiled the type's decoders and the gateway has its
session to the new process: the cold call pays for this bag's bytes, not for starting Python. The
timed cold call follows, then ``repeats`` warm calls."""

from __future__ import annotations

import json
import time
import traceback
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import anyio

from bench.calls import CALLS, BenchCall, service_of
from bench.client import Endpoint, call, timed_call
from bench.delay_proxy import DelayProxy, ProxyCounts
from bench.profile import Profile, recording, summarize
from bench.restarts import FreshServices, disk_peaks
from bench.stats import Timing
from tests.fixtures.mcp_client import http_client

RECONNECT_TIMEOUT_S = 60.0
COLD_MIN_SAMPLES = 5  # a first call is short and mostly waits for S3 (idle, left out)
# first repetition numbers: other times than the warm rows' (plots end 0.01 s earlier per repetition, so a
# 5 s bag takes up to about 490)
COLD_REP, DELAYED_REP = 20, 40
# bag_id and created: filter_bag's output (a cut it made before under another name is found, not made again)
VOLATILE_KEYS = {"job", "elapsed_s", "url", "expires_at", "created_at", "bag_id", "created"}
NOT_COMPARED = {"list_bags"}  # lists every bag, and the passes add filter_bag's outputs


@dataclass
class ColdResult:
    call: BenchCall
    cold: Timing = field(default_factory=Timing)
    warm: Timing = field(default_factory=Timing)
    cold_fetched: int = 0  # the services' /metrics: block-cache bytes from S3
    cold_s3: ProxyCounts = field(default_factory=ProxyCounts)  # every process, through the proxy
    warm_fetched: int = 0  # over all warm calls
    warm_s3: ProxyCounts = field(default_factory=ProxyCounts)
    differs: str | None = None  # quarter pass: None when every answer equals the cold pass's
    cold_lines: list[str] = field(default_factory=list)  # the cold call's S3 requests (method, path, Range)


@dataclass
class ColdPass:
    key: str  # "cold", "delayed", "quarter"
    delay_ms: float
    block_cache_bytes: int | None = None  # the bound set for the pass (None: the default)
    bags: dict[str, list[ColdResult]] = field(default_factory=dict)  # by bag kind
    peaks: dict[str, tuple[int, int]] = field(default_factory=dict)  # process -> (blocks, other) bytes
    error: str | None = None
    profiles: list[Profile] = field(default_factory=list)  # with --cold-profile


@dataclass(frozen=True)
class ColdSetup:
    """What every pass needs: the gateway, the restarter, the proxy, the bags by kind (name, duration s)
    and the warm-up bags the same way."""

    endpoint: Endpoint
    fresh: FreshServices
    proxy: DelayProxy
    bags: dict[str, tuple[str, float]]
    warmups: dict[str, tuple[str, float]]
    calls: tuple[BenchCall, ...] = CALLS
    profile_dir: Path | None = None  # py-spy on the tool's service and worker during each cold call


Answers = dict[tuple[str, str], list[str]]  # (kind, label) -> comparable answers, cold first


def comparable(content: dict[str, Any], arguments: dict[str, Any]) -> str:
    """An answer as JSON without what legitimately differs between two runs of the same call: job ids,
    timings, links, and the name a filter_bag call gave its output."""
    own_name = arguments.get("name")

    def clean(value: Any) -> Any:
        if isinstance(value, dict):
            return {k: clean(v) for k, v in sorted(value.items()) if k not in VOLATILE_KEYS}
        if isinstance(value, list):
            return [clean(v) for v in value]
        if isinstance(value, str) and own_name and own_name in value:
            return value.replace(own_name, "<name>")
        return value

    return json.dumps(clean(content), sort_keys=True)


async def _warm_process(setup: ColdSetup, kind: str, bench_call: BenchCall) -> None:
    """The tool once on the warm-up bag, retried while the gateway reconnects to the restarted service."""
    name, duration_s = setup.warmups[kind]
    arguments = _arguments(bench_call, name, duration_s, 0, suffix="-warmup")
    deadline = time.monotonic() + RECONNECT_TIMEOUT_S
    while True:
        try:
            async with http_client(setup.endpoint.url, setup.endpoint.token) as client:
                await call(client, bench_call.tool, arguments)
            return
        except Exception as err:  # the gateway may not have reconnected yet: try again
            if time.monotonic() > deadline:
                raise RuntimeError(f"the warm-up call failed for {RECONNECT_TIMEOUT_S:g} s: {err}") from err
            await anyio.sleep(0.5)


def _arguments(bench_call: BenchCall, bag: str, duration_s: float, rep: int, *, suffix: str = "") -> dict[str, Any]:
    arguments = bench_call.arguments(bag, duration_s, rep)
    if "name" in arguments:
        arguments["name"] += suffix
    return arguments


@contextmanager
def _profiled(setup: ColdSetup, label: str, tool: str, profiles: list[Profile], *, on: bool) -> Iterator[None]:
    """py-spy on the service that answers the call and its worker while the block runs (when asked)."""
    if not on or setup.profile_dir is None:
        yield
        return
    service = service_of(tool)
    slug = "".join(c if c.isalnum() else "-" for c in label)[:80]
    names = (service, f"{service} worker")
    outputs = {name: setup.profile_dir / f"cold-{slug}-{name.replace(' ', '-')}.txt" for name in names}
    with ExitStack() as exits:
        for name, out in outputs.items():
            exits.enter_context(recording(setup.fresh.pid(name), out))
        yield
    summaries = [summarize(out, label=label, process=name) for name, out in outputs.items()]
    print(f"[bench] py-spy, {label}: " + ", ".join(f"{p.process} {p.samples} samples" for p in summaries), flush=True)
    profiles.extend(p for p in summaries if p.samples >= COLD_MIN_SAMPLES)


async def _measure(
    setup: ColdSetup,
    kind: str,
    bench_call: BenchCall,
    *,
    rep: int,
    repeats: int,
    suffix: str,
    answers: Answers,
    profiles: list[Profile],
) -> ColdResult:
    """The cold call (the first on this bag in these processes), then ``repeats`` warm ones; their bytes."""
    result = ColdResult(bench_call)
    name, duration_s = setup.bags[kind]
    found = answers.setdefault((kind, bench_call.label), [])
    async with http_client(setup.endpoint.url, setup.endpoint.token) as client:
        for number in range(repeats + 1):
            arguments = _arguments(bench_call, name, duration_s, rep + number, suffix=suffix)
            fetched, s3 = await anyio.to_thread.run_sync(setup.fresh.fetched_bytes), setup.proxy.counts()
            label = f"stack {suffix[1:]} {kind}: {bench_call.label} (first call)"
            with _profiled(setup, label, bench_call.tool, profiles, on=not number):
                content = await timed_call(client, bench_call.tool, arguments, result.warm if number else result.cold)
            fetched = await anyio.to_thread.run_sync(setup.fresh.fetched_bytes) - fetched
            s3 = setup.proxy.counts() - s3
            if number:
                result.warm_fetched += fetched
                result.warm_s3 = result.warm_s3 + s3
            else:
                result.cold_fetched, result.cold_s3 = fetched, s3
                result.cold_lines = list(setup.proxy.recent)[-s3.requests :] if s3.requests else []
            found.append(comparable(content, arguments))
    return result


async def per_tool_pass(
    setup: ColdSetup, key: str, *, delay_ms: float, repeats: int, rep: int, answers: Answers
) -> ColdPass:
    """Each tool of each bag cold in freshly started services (see the module's docstring)."""
    found = ColdPass(key, delay_ms)
    setup.proxy.delay_s = delay_ms / 1000
    try:
        for kind in setup.bags:
            found.bags[kind] = []
            for bench_call in setup.calls:
                began = time.monotonic()
                await anyio.to_thread.run_sync(lambda: setup.fresh.restart(s3_endpoint=setup.proxy.endpoint))
                await _warm_process(setup, kind, bench_call)
                print(f"[bench] stack {key}: {kind} {bench_call.label} ({time.monotonic() - began:.1f} s to restart)")
                measured = await _measure(
                    setup,
                    kind,
                    bench_call,
                    rep=rep,
                    repeats=repeats,
                    suffix=f"-{key}",
                    answers=answers,
                    profiles=found.profiles,
                )
                found.bags[kind].append(measured)
    except Exception as err:  # the rows measured so far are still shown, with the error
        found.error = failure(err)
    finally:
        setup.proxy.delay_s = 0.0
    return found


async def quarter_pass(
    setup: ColdSetup, *, cache_bytes: int, env: dict[str, str], repeats: int, answers: Answers
) -> ColdPass:
    """Every tool of every bag in services started once with a block cache of ``cache_bytes``; each answer
    compared with the cold pass's for the same arguments, the caches' disk use sampled throughout."""
    found = ColdPass("quarter", 0.0, block_cache_bytes=cache_bytes)
    reference: Answers = {}
    try:
        await anyio.to_thread.run_sync(lambda: setup.fresh.restart(s3_endpoint=setup.proxy.endpoint, env=env))
        with disk_peaks(setup.fresh) as found.peaks:
            for kind in setup.bags:
                found.bags[kind] = []
                for bench_call in setup.calls:
                    print(f"[bench] stack quarter cache: {kind} {bench_call.label}", flush=True)
                    await _warm_process(setup, kind, bench_call)
                    measured = await _measure(
                        setup,
                        kind,
                        bench_call,
                        rep=COLD_REP,
                        repeats=repeats,
                        suffix="-quarter",
                        answers=reference,
                        profiles=found.profiles,
                    )
                    pair = (kind, bench_call.label)
                    if bench_call.tool not in NOT_COMPARED:
                        measured.differs = _difference(answers.get(pair, []), reference[pair])
                    found.bags[kind].append(measured)
    except Exception as err:  # the rows measured so far are still shown, with the error
        found.error = failure(err)
    return found


def failure(err: BaseException) -> str:
    """The error for the page (the first leaf of an exception group), its traceback printed."""
    traceback.print_exception(err)
    while isinstance(err, BaseExceptionGroup) and err.exceptions:
        err = err.exceptions[0]
    return f"{type(err).__name__}: {err}"[:500]


def _difference(expected: list[str], got: list[str]) -> str | None:
    """None when each answer equals the one for the same arguments in the cold pass, else what differs."""
    pairs = list(zip(expected, got, strict=False))
    if not pairs:
        return "no cold-pass answer to compare with"
    for number, (want, have) in enumerate(pairs):
        if want != have:
            same = (i for i, (a, b) in enumerate(zip(want, have, strict=False)) if a != b)
            at = next(same, min(len(want), len(have)))
            near = slice(max(at - 40, 0), at + 40)
            return f"call {number}: at character {at}, {want[near]!r} in the cold pass, {have[near]!r} here"
    return None
