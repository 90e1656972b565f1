"""What the fleet benchmark measures: the three questions across bags as MCP calls (answers checked against
the drives' known values first, then timed warm), and what feeding the columnar store adds to ingest."""

from __future__ import annotations

import math
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from mcp import Client

from bagmcp_bag_store.fleet.extract import IngestedBag
from bagmcp_bag_store.fleet.files import write_views
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_shared import keys
from bagmcp_shared.access import CachedBagFiles
from bagmcp_shared.catalog import BagRecord, MemoryCatalog
from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.storage import LocalStore
from bench.client import Endpoint, call
from bench.fleet_bags import NEAR_M, POINT, ShortDrive
from bench.stats import Timing
from tests.fixtures.mcp_client import http_client

Check = Callable[[dict[str, object], list[ShortDrive]], None]


def _rows(answer: dict[str, object]) -> tuple[list[list[object]], int]:
    result = answer["result"]
    assert isinstance(result, dict)
    return result["rows"], int(result["total_rows"])


def _speeds(answer: dict[str, object], drives: list[ShortDrive]) -> None:
    rows, total = _rows(answer)
    truth = {d.name: d.speed_mps for d in drives}
    assert total == len(drives), total
    for bag, top in rows:
        assert math.isclose(float(top), truth[str(bag)], rel_tol=0.02), (bag, top, truth[str(bag)])  # type: ignore[arg-type]


def _errors(answer: dict[str, object], drives: list[ShortDrive]) -> None:
    assert _rows(answer)[1] == sum(d.error for d in drives)


def _near(answer: dict[str, object], drives: list[ShortDrive]) -> None:
    assert _rows(answer)[1] == sum(d.passes_near() for d in drives)


QUESTIONS: dict[str, tuple[str, Check]] = {
    "max speed per bag": ("SELECT bag, max(speed) AS top FROM poses GROUP BY bag ORDER BY bag", _speeds),
    "bags with an ERROR log": ("SELECT DISTINCT bag FROM logs WHERE level_rank >= 3", _errors),
    f"bags within {NEAR_M} m of {POINT}": (
        f"SELECT bag, min(sqrt((x - {POINT[0]}) ^ 2 + (y - {POINT[1]}) ^ 2)) AS d FROM poses GROUP BY bag "
        f"HAVING d <= {NEAR_M}",
        _near,
    ),
}


@dataclass
class Asked:
    cold_ms: float
    warm: Timing = field(default_factory=Timing)


async def ask(endpoint: Endpoint, drives: list[ShortDrive], *, repeats: int) -> dict[str, Asked]:
    """Each question once cold (its answer checked), then ``repeats`` times warm."""
    found: dict[str, Asked] = {}
    async with http_client(endpoint.url, endpoint.token) as client:
        for label, (sql, check) in QUESTIONS.items():
            found[label] = await _asked(client, sql, check, drives, repeats)
            print(f"[fleet] {label}: cold {found[label].cold_ms:.0f} ms, warm {found[label].warm.median_ms:.1f} ms")
    return found


async def _asked(client: Client, sql: str, check: Check, drives: list[ShortDrive], repeats: int) -> Asked:
    began = time.perf_counter()
    check(await call(client, "query_bags", {"sql": sql}), drives)
    asked = Asked(cold_ms=(time.perf_counter() - began) * 1000)
    for _ in range(repeats):
        began = time.perf_counter()
        await call(client, "query_bags", {"sql": sql})
        asked.warm.add_s(time.perf_counter() - began)
    return asked


@dataclass
class IngestCost:
    bags: int
    ingest_s: float = 0.0  # today's ingest (summary, columnar index, its files stored), without the fleet
    fleet_s: float = 0.0  # the views' rows taken from that index, written as Parquet beside it

    @property
    def ratio(self) -> float:
        return self.fleet_s / self.ingest_s if self.ingest_s else math.nan


def _stored(store: LocalStore, path: Path, number: int) -> BagRecord:
    """The bag put in ``store`` as an upload leaves it (its files under its id), not yet ingested."""
    members = sorted(p for p in path.iterdir() if p.is_file()) if path.is_dir() else [path]
    bag_id = f"bench{number:04d}"
    for member in members:
        store.put_file(keys.bag_file(bag_id, member.name), member)
    return BagRecord(
        id=bag_id,
        name=path.name,
        layout="directory" if path.is_dir() else "file",
        files=[m.name for m in members],
        source=keys.bag_prefix(bag_id),
        in_store=True,
        sha256="",
        created_at=time.time(),
        size_bytes=sum(m.stat().st_size for m in members),
    )


def ingest_cost(paths: list[Path], *, warmup: int = 3) -> IngestCost:
    """Team-mode ingest of each bag (a local store in place of S3), then what writing its views' files takes
    on its own (ingest wrote them into the index before publishing it), timed in one process, bag after
    bag; the first ``warmup`` bags are not counted."""
    cost = IngestCost(max(len(paths) - warmup, 0))
    with tempfile.TemporaryDirectory(prefix="bench-fleet-") as tmp:
        store, catalog = LocalStore(Path(tmp) / "store"), MemoryCatalog()
        files = CachedBagFiles(store, Path(tmp) / "cache", max_bytes=2**34)
        ingestor = Ingestor(catalog, files, files, store)
        for number, path in enumerate(paths):
            record = _stored(store, path, number)
            catalog.add(record)
            began = time.perf_counter()
            assert ingestor.ingest(record.id) == "ready"
            ingested = time.perf_counter()
            ready = catalog.get(record.id)
            assert ready is not None
            assert ready.summary is not None
            bag = IngestedBag(ready, ready.summary, ColumnIndex.load(files.index_dir(ready)))
            again = Path(tmp) / f"views-{number}"
            again.mkdir()
            fed = time.perf_counter()
            write_views(bag, again)
            if number >= warmup:
                fleet_s = time.perf_counter() - fed
                cost.fleet_s += fleet_s
                cost.ingest_s += ingested - began - fleet_s  # the ingest above fed the store once already
    return cost
