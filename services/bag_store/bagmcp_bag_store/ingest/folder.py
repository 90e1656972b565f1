"""Embedded mode: catalog every bag found under a served folder (read-only) at start-up."""

from __future__ import annotations

import contextlib
import json
import logging
import time
from collections.abc import Iterator
from pathlib import Path

from bagmcp_bag_store.ingest.content import Hashed, content_id, quick_content_id
from bagmcp_bag_store.ingest.ingest import progress_recorder
from bagmcp_bag_store.ingest.upload import sanitize_name
from bagmcp_shared.bags.detect import is_dataflash, sniff_file
from bagmcp_shared.bags.ros2_dir import storage_files
from bagmcp_shared.catalog import BagRecord, Catalog
from bagmcp_shared.errors import BagError, BagmcpError, NameTakenError

log = logging.getLogger(__name__)
_RECORDING_SUFFIXES = (".bag", ".mcap", ".db3", ".ulg", ".ulog")  # recordings, read or refused with a reason
_DATAFLASH_SUFFIX = ".bin"  # any case (flight controllers write 00000042.BIN); kept when it starts like one


def _is_bag_dir(path: Path) -> bool:
    return (path / "metadata.yaml").is_file()


def find_bags(root: Path) -> list[Path]:
    """Bag files and ROS 2 bag directories under ``root`` (a bag directory is not searched further)."""
    found: list[Path] = []
    for entry in sorted(root.iterdir()):
        if entry.name.startswith("."):
            continue
        if entry.is_dir():
            found.extend([entry] if _is_bag_dir(entry) else find_bags(entry))
        elif entry.suffix in _RECORDING_SUFFIXES or (entry.suffix.lower() == _DATAFLASH_SUFFIX and is_dataflash(entry)):
            found.append(entry)
    return found


class IdCache:
    """Content ids of files already hashed, keyed by (path, size, mtime): restarts skip re-hashing."""

    def __init__(self, path: Path | None) -> None:
        self._path = path
        self._known: dict[str, str] = {}
        if path is not None and path.is_file():
            with contextlib.suppress(ValueError, OSError):
                self._known = dict(json.loads(path.read_text()))

    def content_id(self, members: list[Path], *, directory: bool, hashed: Hashed = lambda _bytes: None) -> str:
        key = "|".join(f"{m.resolve()}:{m.stat().st_size}:{m.stat().st_mtime_ns}" for m in members)
        if key not in self._known:
            self._known[key] = content_id(members, directory=directory, hashed=hashed)
        return self._known[key]

    def save(self) -> None:
        if self._path is not None:
            with contextlib.suppress(OSError):
                self._path.parent.mkdir(parents=True, exist_ok=True)
                self._path.write_text(json.dumps(self._known))


def _members(bag: Path) -> tuple[list[Path], str | None]:
    """The files a bag consists of, and why it cannot be read (None when it looks readable)."""
    try:
        if bag.is_dir():
            files, _, _ = storage_files(bag)
            return sorted({*files, *(p for p in bag.iterdir() if p.name == "metadata.yaml")}), None
        sniff_file(bag)
    except BagError as err:
        everything = sorted(p for p in bag.iterdir() if p.is_file()) if bag.is_dir() else [bag]
        return everything, str(err).replace(str(bag), bag.name)
    return [bag], None


def _record(root: Path, bag: Path) -> BagRecord:
    """A catalog record, made without reading the whole bag (the full sha256 is filled in by ingest);
    a file that is not a readable bag is listed as failed, with the reason."""
    members, problem = _members(bag)
    return BagRecord(
        id=quick_content_id(members, directory=bag.is_dir())[:16],
        name=sanitize_name(bag.name),
        layout="directory" if bag.is_dir() else "file",
        files=[m.name for m in members],
        source=str(bag.relative_to(root)),
        in_store=False,
        sha256="",
        size_bytes=sum(m.stat().st_size for m in members),
        created_at=time.time(),
        status="failed" if problem else "ingesting",
        error=problem,
    )


def twin_names(record: BagRecord, bag: Path) -> Iterator[str]:
    """Names for a bag, in the order they are tried: its own, then (another bag has it) with its format, then
    with its folder, then numbered. ``rosbag2_talker`` in ros2_db3/ and ros2_mcap/ become ``rosbag2_talker`` and
    ``rosbag2_talker_mcap``: a person reads "the MCAP copy", not a range as in ``rosbag2_talker-2``."""
    yield record.name
    kinds = [Path(f).suffix.lstrip(".") for f in record.files if f != "metadata.yaml"]
    if kinds and kinds[0]:
        yield f"{record.name}_{kinds[0]}"
    yield f"{record.name}_{sanitize_name(bag.parent.name)}"
    for n in range(2, 100):
        yield f"{record.name}_copy{n}"


def _claim_name(catalog: Catalog, record: BagRecord, bag: Path) -> str:
    for name in twin_names(record, bag):
        try:
            catalog.claim_name(name, record.id)
            return name
        except NameTakenError:
            continue
    raise NameTakenError(f"{bag.name}: a hundred bags have its name already; rename it")


def catalog_folder(catalog: Catalog, root: Path) -> list[str]:
    """Add every readable-looking bag under ``root`` at once (no bag is read through); returns the ids to
    ingest, smallest bag first, so small bags are usable while large ones are still being hashed."""
    queued: list[tuple[int, str]] = []
    for bag in find_bags(root):
        try:
            record = _record(root, bag)
            if catalog.get(record.id) is not None:
                continue
            catalog.add(record.model_copy(update={"name": _claim_name(catalog, record, bag)}))
            if record.status == "ingesting":
                queued.append((record.size_bytes, record.id))
        except (BagmcpError, OSError) as err:
            log.warning("skipping %s: %s", bag, err)
    return [bag_id for _, bag_id in sorted(queued)]


HASHING_SHARE = 0.5  # of a served bag's ingest progress, before its index is built


class FolderHashes:
    """Fills in the full sha256 of served bags in the background (cached by path, size and mtime),
    recording the hashing as the first half of the bag's ingest progress."""

    def __init__(self, catalog: Catalog, root: Path, cache: Path) -> None:
        self._catalog = catalog
        self._root = root
        self._ids = IdCache(cache)

    def fill(self, bag_id: str) -> None:
        record = self._catalog.get(bag_id)
        if record is None or record.in_store or record.sha256:
            return
        base = self._root / record.source
        members = [base] if record.layout == "file" else [base / name for name in record.files]
        report = progress_recorder(self._catalog, bag_id, start=0.0, end=HASHING_SHARE)
        size = max(record.size_bytes, 1)
        sha = self._ids.content_id(
            members, directory=record.layout == "directory", hashed=lambda done: report(done / size, "hashing")
        )
        self._ids.save()
        current = self._catalog.get(bag_id)
        if current is not None:
            self._catalog.replace(current.model_copy(update={"sha256": sha}))
