"""Uploads: streamed to a temp file with a checksum, validated by opening, deduplicated, atomic."""

from __future__ import annotations

import hashlib
import re
import shutil
import uuid
from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass
from pathlib import Path

from bagmcp_bag_store.errors import UploadError, UploadTooLargeError
from bagmcp_bag_store.ingest.archives import extract, is_archive
from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_shared.bags import BagFormat, open_bag
from bagmcp_shared.bags.detect import sniff_file
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.errors import BagError, StorageError

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
    for suffix in (*_ARCHIVE_SUFFIXES, ".bag", ".mcap", ".db3", ".ulg", ".ulog"):
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


def store_upload(
    shelf: Shelf,
    queue_ingest: Callable[[str], None],
    received: Received,
    *,
    filename: str,
    name: str | None,
    tags: list[str],
    staging_root: Path,
    max_bytes: int,
) -> tuple[BagRecord, bool]:
    """Validate and store an upload, then queue its ingest; returns the record and whether it is
    new (False = duplicate)."""
    staging = staging_root / f"staging-{uuid.uuid4().hex}"
    staging.mkdir(parents=True)
    try:
        try:
            root, files, sha = _layout(received, staging, filename, max_bytes)
            with open_bag(root) as bag:
                bag.summary()
        except BagError as err:  # name the upload, not the server's temporary paths
            raise type(err)(re.sub(rf"{re.escape(str(staging_root))}[^\s:]*", filename, str(err))) from err
        record, created = shelf.register(root, files, sha, name=sanitize_name(name or filename), tags=tags)
        if created:
            try:
                queue_ingest(record.id)
            except Exception as err:
                shelf.remove(record)
                raise StorageError(f"the ingest task could not be queued ({err}); nothing was stored") from err
        return record, created
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        received.path.unlink(missing_ok=True)
