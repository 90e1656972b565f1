"""Uploads: streamed to a temp file with a checksum, validated by opening, deduplicated, atomic."""

from __future__ import annotations

import hashlib
import re
import shutil
import time
import uuid
from collections.abc import AsyncIterator
from dataclasses import dataclass
from pathlib import Path

from bagmcp_bag_store.archives import extract, is_archive
from bagmcp_bag_store.content import content_id
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import ReadOnlyError, UploadError, UploadTooLargeError
from bagmcp_bag_store.models import BagRecord
from bagmcp_shared.bags import BagFormat, open_bag
from bagmcp_shared.bags.detect import sniff_file
from bagmcp_shared.errors import BagError, StorageError
from bagmcp_shared.storage import ObjectStore

_SUFFIXES = {
    BagFormat.ROS1: ".bag",
    BagFormat.MCAP: ".mcap",
    BagFormat.ROS2_SQLITE3: ".db3",
    BagFormat.ROS2_MCAP: ".mcap",
}
_ARCHIVE_SUFFIXES = (".tar.gz", ".tgz", ".tar", ".zip")


@dataclass(frozen=True)
class Received:
    path: Path
    size: int
    sha256: str


async def receive(chunks: AsyncIterator[bytes], directory: Path, *, max_bytes: int) -> Received:
    """Write a request body to a new temp file under ``directory``, hashing as it goes."""
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"body-{uuid.uuid4().hex}"
    digest, size = hashlib.sha256(), 0
    try:
        with path.open("wb") as out:
            async for chunk in chunks:
                size += len(chunk)
                if size > max_bytes:
                    raise UploadTooLargeError(f"the upload exceeds the limit of {max_bytes} bytes")
                digest.update(chunk)
                out.write(chunk)
    except BaseException:
        path.unlink(missing_ok=True)
        raise
    if size == 0:
        path.unlink(missing_ok=True)
        raise UploadError("the upload is empty (0 bytes); send the bag file's bytes as the request body")
    return Received(path, size, digest.hexdigest())


def sanitize_name(text: str) -> str:
    """A bag name safe in URLs, object keys and shells: [A-Za-z0-9._-], at most 100 characters."""
    base = text.strip()
    for suffix in (*_ARCHIVE_SUFFIXES, ".bag", ".mcap", ".db3"):
        base = base.removesuffix(suffix)
    clean = re.sub(r"[^A-Za-z0-9._-]+", "_", Path(base).name).strip("._-")[:100]
    if not clean:
        raise UploadError(f"{text!r} gives an empty name; pass a name made of letters, digits, '.', '_' or '-'")
    return clean


def _layout(received: Received, staging: Path, filename: str, max_bytes: int) -> tuple[Path, list[str], str]:
    """The bag's local root, its files, and its content hash."""
    if is_archive(received.path):
        root = extract(received.path, staging / "unpacked", max_bytes=max_bytes)
    else:
        root = staging / (sanitize_name(filename) + _SUFFIXES[sniff_file(received.path)])
        shutil.move(received.path, root)
        return root, [root.name], received.sha256
    if root.is_file():
        return root, [root.name], content_id([root], directory=False)
    members = sorted(p for p in root.iterdir() if p.is_file())
    return root, [p.name for p in members], content_id(members, directory=True)


def _record_key(bag_id: str) -> str:
    """Where a stored bag's registration is kept next to its files (lets a catalog be rebuilt)."""
    return f"catalog/{bag_id}.json"


def _put_all(store: ObjectStore, root: Path, files: list[str], prefix: str) -> None:
    for name in files:
        store.put_file(f"{prefix}/{name}", root if root.is_file() else root / name)


def _remove_unlisted(deps: BagStoreDeps, bag_id: str, files: list[str]) -> None:
    """After a failed registration, remove its objects unless another registration of the same
    content (same keys) got listed meanwhile."""
    if deps.store is not None and deps.catalog.get(bag_id) is None:
        for name in files:
            deps.store.delete(f"bags/{bag_id}/{name}")


def register_bag(
    deps: BagStoreDeps, root: Path, files: list[str], sha: str, *, name: str, tags: list[str]
) -> tuple[BagRecord, bool]:
    """Store a validated bag's files and list it; returns (record, created). Same content = same bag.

    The catalog entry appears only after every object is stored; a failure removes what was stored.
    """
    if deps.store is None:
        raise ReadOnlyError("this server serves a read-only folder of bags; it cannot store new bags")
    bag_id = sha[:16]
    if (existing := deps.catalog.get(bag_id)) is not None:
        return existing, False
    deps.catalog.claim_name(name, bag_id)
    try:
        _put_all(deps.store, root, files, f"bags/{bag_id}")
        size = sum((root if root.is_file() else root / f).stat().st_size for f in files)
        record = BagRecord(
            id=bag_id,
            name=name,
            layout="file" if root.is_file() else "directory",
            files=files,
            source=f"bags/{bag_id}",
            in_store=True,
            sha256=sha,
            size_bytes=size,
            created_at=time.time(),
            tags=tags,
        )
        if not deps.catalog.add(record):  # the same content was registered concurrently
            deps.catalog.release_name(name, bag_id)
            return deps.catalog.get(bag_id) or record, False
        deps.store.put_bytes(_record_key(bag_id), record.model_dump_json().encode())
    except BaseException:
        deps.catalog.release_name(name, bag_id)
        _remove_unlisted(deps, bag_id, files)
        raise
    return record, True


def store_upload(
    deps: BagStoreDeps,
    received: Received,
    *,
    filename: str,
    name: str | None,
    tags: list[str],
    staging_root: Path,
    max_bytes: int,
) -> tuple[BagRecord, bool]:
    """Validate and store an upload; returns the record and whether it is new (False = duplicate)."""
    if deps.store is None or not deps.uploads:
        raise ReadOnlyError("this server serves a read-only folder of bags; uploads are disabled")
    staging = staging_root / f"staging-{uuid.uuid4().hex}"
    staging.mkdir(parents=True)
    try:
        try:
            root, files, sha = _layout(received, staging, filename, max_bytes)
            with open_bag(root) as bag:
                bag.summary()
        except BagError as err:  # name the upload, not the server's temporary paths
            raise type(err)(re.sub(rf"{re.escape(str(staging_root))}[^\s:]*", filename, str(err))) from err
        record, created = register_bag(deps, root, files, sha, name=sanitize_name(name or filename), tags=tags)
        if created:
            try:
                deps.submit_ingest(record.id)
            except Exception as err:
                delete_bag(deps, record)
                raise StorageError(f"the ingest task could not be queued ({err}); nothing was stored") from err
        return record, created
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        received.path.unlink(missing_ok=True)


def delete_bag(deps: BagStoreDeps, record: BagRecord) -> None:
    """Remove a bag's catalog entry, objects and index (catalog first, so it vanishes at once)."""
    if deps.store is None or not record.in_store:
        raise ReadOnlyError(f"bag {record.name} is part of the served folder; remove it there, not through bagmcp")
    deps.catalog.delete(record.id)
    deps.store.delete(_record_key(record.id))
    for name in record.files:
        deps.store.delete(f"{record.source}/{name}")
    deps.store.delete(f"indexes/{record.id}/summary.json")
    for name in record.index_files:
        deps.store.delete(f"indexes/{record.id}/columns/{name}")
