"""CPU a bag of writing the views' Parquet files at ingest (``write_views``) against the CPU of building the
bag's index (summary, ``build_index``, loading it), on ``bench/fleet_bags.py``'s 10 s drives, in one process:
the part of issue 22's "ingest adds under 10 %" that the views' code decides, without the object store's
writes (their cost depends on the store, not on this code). Light enough for a shared machine (30 bags:
about 30 s); the medians of rounds over the same bags, each round into fresh directories as ingest's are.

    PYTHONPATH=. .venv/bin/python -m bench.fleet_views_cost --count 30 --rounds 5
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from bagmcp_bag_store.fleet.extract import IngestedBag
from bagmcp_bag_store.fleet.files import write_views
from bagmcp_shared.bags import open_bag
from bagmcp_shared.catalog import BagRecord, CatalogSummary
from bagmcp_shared.index import ColumnIndex, build_index
from bench.fleet_bags import fleet_bags


def _ingested(path: Path, work: Path, number: int) -> tuple[IngestedBag, float]:
    """The bag as ingest knows it before writing its views, and the CPU ms its index took."""
    started = time.process_time()
    with open_bag(path) as reader:
        found = reader.summary()
        build_index(reader, work / str(number))
    built = ColumnIndex.load(work / str(number))
    assert built is not None
    summary = CatalogSummary.of(found, header_rates=built.header_rates())
    spent = (time.process_time() - started) * 1000
    record = BagRecord(
        id=f"{number:016x}",
        name=path.stem,
        layout="file",
        files=[path.name],
        source=str(path),
        in_store=False,
        sha256="0",
        size_bytes=1,
        created_at=0.0,
        status="ready",
        summary=summary,
    )
    return IngestedBag(record, summary, built), spent


def _round(bags: list[IngestedBag], work: Path) -> float:
    """The median CPU ms of one bag's ``write_views``, each into a fresh directory."""
    spent = []
    for bag in bags:
        directory = Path(tempfile.mkdtemp(dir=work))
        started = time.process_time()
        write_views(bag, directory)
        spent.append((time.process_time() - started) * 1000)
    return statistics.median(spent)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--count", type=int, default=30)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--bags", type=Path, default=Path(tempfile.gettempdir()) / "bagmcp-fleet-views")
    args = parser.parse_args()
    folder, _ = fleet_bags(args.bags, args.count)
    with tempfile.TemporaryDirectory(prefix="bagmcp-views-cost-") as tmp:
        work = Path(tmp)
        ingested = [_ingested(path, work, n) for n, path in enumerate(sorted(folder.iterdir()))]
        bags = [bag for bag, _ in ingested]
        _round(bags, work)  # warm: imports and pyarrow's first calls
        rounds = [_round(bags, work) for _ in range(args.rounds)]
    views, index = statistics.median(rounds), statistics.median(spent for _, spent in ingested)
    print(
        f"{len(bags)} bags, {args.rounds} rounds: write_views {views:.2f} ms CPU a bag (round medians "
        f"{', '.join(f'{r:.2f}' for r in rounds)}); index {index:.1f} ms CPU a bag; views/index {views / index:.1%}"
    )


if __name__ == "__main__":
    main()
