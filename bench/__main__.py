"""``python -m bench [--quick]``: generate the bags (cached), measure the floors, serve them embedded and
on the local stack, time every tool as MCP calls over HTTP, and write BENCHMARKS.md."""

from __future__ import annotations

import argparse
import pickle
import tempfile
import time
import traceback
from contextlib import AbstractContextManager
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import anyio

from bench.bags import bench_bags
from bench.cold import ColdPass
from bench.cold_run import ColdPlan, measure_cold
from bench.floors import measure_floors
from bench.machine import LoadWatch, Machine
from bench.report import render
from bench.results import ModeResult, RunResult
from bench.run import Plan, measure_mode
from bench.servers import Served, embedded, stack
from bench.stats import Timing
from bench.uploads import cache_use
from tests.fixtures.bagfactory import BAG_KINDS


@dataclass(frozen=True)
class Preset:
    size_gb: float
    repeats: int
    overhead_repeats: int
    loads: tuple[tuple[int, int], ...]  # (clients, calls each)
    floor_repeats: int
    cold_repeats: int  # warm calls after each cold one in the cold and quarter passes
    delayed_repeats: int  # the same with 20 ms per S3 request, and in the quarter pass


FULL = Preset(2.0, 9, 60, ((20, 30), (50, 20)), floor_repeats=5, cold_repeats=3, delayed_repeats=1)
QUICK = Preset(0.05, 3, 10, ((20, 5), (50, 2)), floor_repeats=2, cold_repeats=2, delayed_repeats=1)
# the quick run's cold passes: only the calls with an issue 21 target (each costs a restart of six processes)
QUICK_COLD_CALLS = ("get_message_at_time", "analyze_trajectory", "plot_timeseries", "get_image_at_time")
WARMUP_GB = 0.06  # the cold passes' warm-up bags: 6 s of drive (every window fits), not the measured bags' size
NOTES = Path(__file__).parent / "notes.md"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="small bags and few repetitions (about a minute)")
    parser.add_argument("--size-gb", type=float, default=None, help="bag size (default 2, quick 0.05)")
    parser.add_argument("--repeat", type=int, default=None, help="warm calls per tool (default 9, quick 3)")
    parser.add_argument(
        "--modes",
        default="embedded,stack,cold",
        help="of embedded, stack, cold (the stack's cold passes), uploads (only the stack's timed uploads, which "
        "every stack run makes)",
    )
    parser.add_argument("--formats", default=",".join(BAG_KINDS), help="bag formats measured")
    parser.add_argument("--cold-passes", default="cold,delayed,quarter", help="of cold, delayed, quarter")
    parser.add_argument(
        "--cold-calls",
        default=None,
        help="cold passes: only calls whose label holds one of these (quick: the targeted ones)",
    )
    parser.add_argument("--cold-profile", action="store_true", help="cold passes: py-spy during each first call")
    parser.add_argument("--no-profile", action="store_true", help="skip py-spy (default: profile unless quick)")
    parser.add_argument("--dir", type=Path, default=Path(".bench"), help="where bags are cached and runs work")
    parser.add_argument("--out", type=Path, default=None, help="default BENCHMARKS.md (quick: in --dir)")
    parser.add_argument("--render", action="store_true", help="only rewrite the page from the last run's figures")
    return parser


def _notes() -> str:
    """Why targets are missed, written by hand after a run (bench/notes.md), shown under the targets."""
    return NOTES.read_text() if NOTES.exists() else ""


def _write(run: RunResult, args: argparse.Namespace) -> None:
    out = args.out or (args.dir / "BENCHMARKS.quick.md" if run.quick else Path("BENCHMARKS.md"))
    out.write_text(render(run, notes=_notes()))
    print(f"[bench] wrote {out}", flush=True)


def _serve_and_measure(run: RunResult, args: argparse.Namespace, preset: Preset, watch: LoadWatch) -> None:
    """Each way of serving in turn (the stack also for the cold passes when asked), into ``run``."""
    modes = args.modes.split(",")
    kinds = tuple(b.kind for b in run.bags)
    with tempfile.TemporaryDirectory(dir=args.dir, prefix="run-") as tmp:
        stack_too = "cold" in modes or "uploads" in modes  # the stack is started for them without its calls
        for mode in [m for m in ("embedded", "stack") if m in modes or (m == "stack" and stack_too)]:
            work = Path(tmp) / mode
            work.mkdir()
            plan = Plan(
                repeats=run.repeats,
                overhead_repeats=preset.overhead_repeats,
                loads=preset.loads,
                profile=not args.no_profile and not args.quick,
                work=work,
            )
            warmups = bench_bags(args.dir, size_gb=WARMUP_GB, kinds=kinds) if "cold" in modes else []
            extra = sum(b.size_bytes for b in warmups)
            server: AbstractContextManager[Served] = (
                embedded(run.bags[0].path.parent, work)
                if mode == "embedded"
                else stack(run.bags, work, extra_bytes=extra)
            )
            watch.phase = mode
            try:
                with server as served:
                    run.uploads += served.uploads
                    _caches(run, served, "after the uploads")
                    if mode in modes:
                        measured = partial(measure_mode, served, run.bags, plan, began=time.monotonic())
                        run.modes.append(anyio.run(measured))
                        _caches(run, served, "after the warm calls and loads")
                    if mode == "stack" and "cold" in modes:
                        passes = tuple(args.cold_passes.split(","))
                        chosen = QUICK_COLD_CALLS if args.quick else ()
                        only = tuple(p for p in args.cold_calls.split(",") if p) if args.cold_calls else chosen
                        cold = ColdPlan(
                            preset.cold_repeats,
                            preset.delayed_repeats,
                            passes,
                            work,
                            only,
                            watch,
                            partial(_keep, run, args),
                            profile=args.cold_profile,
                        )
                        run.cold = anyio.run(measure_cold, served, run.bags, warmups, cold)
            except Exception as err:  # the other mode is still worth its figures; the page says what failed
                traceback.print_exc()
                run.modes.append(ModeResult(mode, error=f"{type(err).__name__}: {err}"[:500]))
            _save(run, args)


def _caches(run: RunResult, served: Served, when: str) -> None:
    """The stack's caches on disk at one moment, beside their bounds (issue 21: never above them)."""
    if served.running is not None:
        run.caches.append((when, cache_use(served.running)))


def _saved_path(args: argparse.Namespace) -> Path:
    directory: Path = args.dir
    return directory / ("last-run-quick.pickle" if args.quick else "last-run.pickle")


def _save(run: RunResult, args: argparse.Namespace) -> None:
    """The figures so far (``--render`` writes a page from them if the run stops before its end)."""
    _saved_path(args).write_bytes(pickle.dumps(run))


def _keep(run: RunResult, args: argparse.Namespace, passes: list[ColdPass]) -> None:
    run.cold = passes
    _save(run, args)


def main() -> None:
    args = _parser().parse_args()
    if args.render:  # figures of the last run, with bench/notes.md as it is now
        _write(pickle.loads(_saved_path(args).read_bytes()), args)
        return
    preset = QUICK if args.quick else FULL
    began = time.monotonic()
    kinds = tuple(k for k in BAG_KINDS if k in args.formats.split(","))
    bags = bench_bags(args.dir, size_gb=args.size_gb or preset.size_gb, kinds=kinds)
    print(f"[bench] bags: {', '.join(f'{b.path} ({b.size_bytes:,} B)' for b in bags)}", flush=True)
    with LoadWatch() as watch:
        watch.phase = "floors"
        floors: dict[str, dict[str, Timing]] = {
            b.kind: measure_floors(b.path, b.duration_s, repeats=preset.floor_repeats) for b in bags
        }
        run = RunResult(Machine.here(), args.quick, args.repeat or preset.repeats, bags, floors)
        args.dir.mkdir(parents=True, exist_ok=True)
        _serve_and_measure(run, args, preset, watch)
    run.load = watch.samples
    run.wall_s = time.monotonic() - began
    _save(run, args)
    _write(run, args)


if __name__ == "__main__":
    main()
