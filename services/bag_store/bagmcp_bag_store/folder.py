"""Embedded mode: catalog every bag found under a served folder (read-only) at start-up."""

from __future__ import annotations

import contextlib
import json
import logging
import time
from pathlib import Path

from bagmcp_bag_store.catalog import Catalog
from bagmcp_bag_store.content import content_id
from bagmcp_bag_store.errors import NameTakenError, UploadError
from bagmcp_bag_store.models import BagRecord
from bagmcp_bag_store.upload import sanitize_name
from bagmcp_shared.bags.detect import sniff_file
from bagmcp_shared.bags.ros2_dir import storage_files
from bagmcp_shared.errors import BagError, BagmcpError
from bagmcp_shared.storage import ObjectStore

log = logging.getLogger(__name__)
_BAG_SUFFIXES = (".bag", ".mcap", ".db3")


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
        elif entry.suffix in _BAG_SUFFIXES:
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

    def content_id(self, members: list[Path], *, directory: bool) -> str:
        key = "|".join(f"{m.resolve()}:{m.stat().st_size}:{m.stat().st_mtime_ns}" for m in members)
        if key not in self._known:
            self._known[key] = content_id(members, directory=directory)
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


def _record(root: Path, bag: Path, ids: IdCache) -> BagRecord:
    """A catalog record; a file that is not a readable bag is listed as failed, with the reason."""
    members, problem = _members(bag)
    sha = ids.content_id(members, directory=bag.is_dir())
    return BagRecord(
        id=sha[:16],
        name=sanitize_name(bag.name),
        layout="directory" if bag.is_dir() else "file",
        files=[m.name for m in members],
        source=str(bag.relative_to(root)),
        in_store=False,
        sha256=sha,
        size_bytes=sum(m.stat().st_size for m in members),
        created_at=time.time(),
        status="failed" if problem else "ingesting",
        error=problem,
    )


def catalog_folder(catalog: Catalog, root: Path, *, id_cache: Path | None = None) -> list[str]:
    """Add every readable-looking bag under ``root``; returns their ids (skips with a log line)."""
    ids: list[str] = []
    known = IdCache(id_cache)
    for bag in find_bags(root):
        try:
            record = _record(root, bag, known)
            if catalog.get(record.id) is not None:
                continue
            name = record.name
            for n in range(2, 100):
                try:
                    catalog.claim_name(name, record.id)
                    break
                except NameTakenError:
                    name = f"{record.name}-{n}"
            catalog.add(record.model_copy(update={"name": name}))
            if record.status == "ingesting":
                ids.append(record.id)
        except (BagmcpError, UploadError, OSError) as err:
            log.warning("skipping %s: %s", bag, err)
    known.save()
    return ids


def catalog_stored(catalog: Catalog, store: ObjectStore) -> list[str]:
    """List again the bags an embedded server made earlier (filter_bag) from their registrations."""
    ids: list[str] = []
    for info in store.list("catalog/"):
        try:
            with store.open_read(info.key) as stream:
                record = BagRecord.model_validate_json(stream.read())
            catalog.claim_name(record.name, record.id)
        except (BagmcpError, ValueError) as err:
            log.warning("not listing %s again: %s", info.key, err)
            continue
        if catalog.add(record.model_copy(update={"status": "ingesting", "summary": None})):
            ids.append(record.id)
    return ids
