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
from bench.floors import measure_floors
from bench.machine import Machine
from bench.report import render
from bench.results import ModeResult, RunResult
from bench.run import Plan, measure_mode
from bench.servers import Served, embedded, stack
from bench.stats import Timing


@dataclass(frozen=True)
class Preset:
    size_gb: float
    repeats: int
    overhead_repeats: int
    loads: tuple[tuple[int, int], ...]  # (clients, calls each)
    floor_repeats: int


FULL = Preset(size_gb=2.0, repeats=9, overhead_repeats=60, loads=((20, 30), (50, 20)), floor_repeats=5)
QUICK = Preset(size_gb=0.05, repeats=3, overhead_repeats=10, loads=((20, 5), (50, 2)), floor_repeats=2)
NOTES = Path(__file__).parent / "notes.md"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="small bags and few repetitions (about a minute)")
    parser.add_argument("--size-gb", type=float, default=None, help="bag size (default 2, quick 0.05)")
    parser.add_argument("--repeat", type=int, default=None, help="warm calls per tool (default 9, quick 3)")
    parser.add_argument("--modes", default="embedded,stack", help="embedded, stack or both")
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


def main() -> None:
    args = _parser().parse_args()
    saved = args.dir / ("last-run-quick.pickle" if args.quick else "last-run.pickle")
    if args.render:  # figures of the last run, with bench/notes.md as it is now
        _write(pickle.loads(saved.read_bytes()), args)
        return
    preset = QUICK if args.quick else FULL
    began = time.monotonic()
    bags = bench_bags(args.dir, size_gb=args.size_gb or preset.size_gb)
    print(f"[bench] bags: {', '.join(f'{b.path} ({b.size_bytes:,} B)' for b in bags)}", flush=True)
    floors: dict[str, dict[str, Timing]] = {
        b.kind: measure_floors(b.path, b.duration_s, repeats=preset.floor_repeats) for b in bags
    }
    repeats = args.repeat or preset.repeats
    run = RunResult(Machine.here(), args.quick, repeats, bags, floors)
    args.dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=args.dir, prefix="run-") as tmp:
        for mode in args.modes.split(","):
            work = Path(tmp) / mode
            work.mkdir()
            plan = Plan(
                repeats=repeats,
                overhead_repeats=preset.overhead_repeats,
                loads=preset.loads,
                profile=not args.no_profile and not args.quick,
                work=work,
            )
            server: AbstractContextManager[Served] = (
                embedded(bags[0].path.parent, work) if mode == "embedded" else stack(bags, work)
            )
            try:
                with server as served:
                    run.modes.append(anyio.run(partial(measure_mode, served, bags, plan, began=time.monotonic())))
            except Exception as err:  # the other mode is still worth its figures; the page says what failed
                traceback.print_exc()
                run.modes.append(ModeResult(mode, error=f"{type(err).__name__}: {err}"[:500]))
    run.wall_s = time.monotonic() - began
    saved.write_bytes(pickle.dumps(run))
    _write(run, args)


if __name__ == "__main__":
    main()
