"""``python -m bench.index_formats``: why the per-bag index stays NumPy ``.npz`` while the views are Parquet.

Times loading four of a topic's twelve columns (the index's hot path: a trajectory, a plot) from an
uncompressed ``.npz`` and with pyarrow from Parquet (zstd, and uncompressed), at three topic sizes, medians
of 15 warm reads in one run (ratios hold better than absolute times on a shared machine)."""

from __future__ import annotations

import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import cast

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

COLUMNS = ("x", "y", "z", "yaw", "vx", "vy", "vz", "wx", "wy", "wz")
READ = ["t_ns", "x", "y", "yaw"]


def _median_ms(read: Callable[[Path], object], path: Path, repeats: int = 15) -> float:
    read(path)
    samples = []
    for _ in range(repeats):
        began = time.perf_counter()
        read(path)
        samples.append((time.perf_counter() - began) * 1000)
    return sorted(samples)[len(samples) // 2]


def _files(directory: Path, rows: int) -> tuple[Path, Path, Path]:
    t_ns = np.arange(rows, dtype=np.int64) * 50_000_000
    columns = {name: np.random.default_rng(rows).random(rows) for name in COLUMNS}
    npz = directory / f"topic-{rows}.npz"
    arrays = {"t_ns": t_ns, "header_ns": t_ns, **{f"c:{k}": v for k, v in columns.items()}}
    cast(Callable[..., None], np.savez)(npz, **arrays)
    table = pa.table({"t_ns": t_ns, "header_ns": t_ns, **columns})
    zstd, plain = directory / f"topic-{rows}.zstd.parquet", directory / f"topic-{rows}.parquet"
    pq.write_table(table, zstd, compression="zstd")
    pq.write_table(table, plain, compression="none")
    return npz, zstd, plain


def _npz(path: Path) -> list[np.ndarray]:
    with np.load(path) as data:
        return [data["t_ns" if c == "t_ns" else f"c:{c}"] for c in READ]


def _parquet(path: Path) -> list[np.ndarray]:
    return [column.to_numpy() for column in pq.read_table(path, columns=READ).columns]


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for rows in (1_200, 100_000, 1_000_000):
            npz, zstd, plain = _files(Path(tmp), rows)
            times = {
                "npz": _median_ms(_npz, npz),
                "parquet zstd": _median_ms(_parquet, zstd),
                "parquet plain": _median_ms(_parquet, plain),
            }
            shown = ", ".join(f"{k} {v:.2f} ms" for k, v in times.items())
            print(f"{rows:>9,} rows: {shown} (zstd Parquet / npz = {times['parquet zstd'] / times['npz']:.1f})")


if __name__ == "__main__":
    main()
