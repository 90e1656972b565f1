"""Uploads: streamed to a temp file with a checksum, validated by opening, deduplicated, atomic."""

from __future__ import annotations

import hashlib
import re
import shutil
import time
import uuid
from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass, field
from pathlib import Path

from bagmcp_bag_store.errors import UploadError, UploadTooLargeError
from bagmcp_bag_store.ingest.archives import ArchiveLimits, extract, is_archive
from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_shared.bags import BagFormat, open_bag
from bagmcp_shared.bags.detect import sniff_file
from bagmcp_shared.bags.ros2_dir import storage_files
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.errors import BagError, StorageError

_SUFFIXES = {
    BagFormat.ROS1: ".bag",
    BagFormat.MCAP: ".mcap",
    BagFormat.ROS2_SQLITE3: ".db3",
    BagFormat.ROS2_MCAP: ".mcap",
    BagFormat.ULOG: ".ulg",
    BagFormat.DATAFLASH: ".bin",
}
_ARCHIVE_SUFFIXES = (".tar.gz", ".tgz", ".tar", ".zip")


@dataclass(frozen=True)
class UploadPolicy:
    """How uploads are taken: ``max_bytes`` bounds the body and what an archive unpacks to, which is also at
    most ``archive_expansion`` times the archive's size. A re-upload of a bag whose ingest failed, or has
    not finished ``stuck_after_s`` after it was queued, queues its ingest again. ``uploads`` False refuses
    uploads (an embedded server over a read-only folder). Bodies and unpacked archives go to ``upload_dir``
    (the process's scratch directory)."""

    shelf: Shelf
    queue_ingest: Callable[[str], None]
    upload_dir: Path
    max_bytes: int
    archive_expansion: int = 20
    stuck_after_s: float = 120.0
    uploads: bool = True

    def archive_limits(self, received_bytes: int) -> ArchiveLimits:
        return ArchiveLimits(max_bytes=min(self.max_bytes, self.archive_expansion * received_bytes))


@dataclass(frozen=True)
class Stored:
    """An upload's outcome: the bag, whether it is new (False: the same content was there), and notes
    (archive members left out)."""

    record: BagRecord
    created: bool
    notes: list[str] = field(default_factory=list)


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
    for suffix in (*_ARCHIVE_SUFFIXES, ".bag", ".mcap", ".db3", ".ulg", ".ulog", ".bin", ".BIN"):
        base = base.removesuffix(suffix)
    clean = re.sub(r"[^A-Za-z0-9._-]+", "_", Path(base).name).strip("._-")[:100]
    if not clean:
        raise UploadError(f"{text!r} gives an empty name; pass a name made of letters, digits, '.', '_' or '-'")
    return clean


def _bag_files(root: Path) -> tuple[list[Path], list[str]]:
    """The files of a ROS 2 bag directory (metadata.yaml and its storage files), and notes on the rest."""
    try:
        storage, _, _ = storage_files(root)
    except BagError:
        storage = []  # opening the bag reports what is wrong
    everything = sorted(p for p in root.iterdir() if p.is_file())
    kept = [p for p in everything if p.name == "metadata.yaml" or p in storage] if storage else everything
    return kept, [
        f"{p.name} was left out: the bag's metadata.yaml does not list it" for p in everything if p not in kept
    ]


def _layout(
    received: Received, staging: Path, filename: str, policy: UploadPolicy
) -> tuple[Path, list[str], str, list[str]]:
    """The bag's local root, its files, its content hash, and notes on what was left out."""
    if not is_archive(received.path):
        root = staging / (sanitize_name(filename) + _SUFFIXES[sniff_file(received.path)])
        shutil.move(received.path, root)
        return root, [root.name], received.sha256, []
    unpacked = extract(received.path, staging / "unpacked", limits=policy.archive_limits(received.size))
    root = unpacked.root
    if root.is_file():
        return root, [root.name], content_id([root], directory=False), unpacked.dropped
    members, left_out = _bag_files(root)
    return root, [p.name for p in members], content_id(members, directory=True), [*unpacked.dropped, *left_out]


def _stuck(record: BagRecord, stuck_after_s: float) -> bool:
    """Failed, or still ingesting long after its ingest was queued (its worker died, or its task was lost)."""
    queued = record.ingest_queued_at or record.created_at
    return record.status == "failed" or (record.status == "ingesting" and time.time() - queued > stuck_after_s)


def store_upload(
    policy: UploadPolicy, received: Received, *, filename: str, name: str | None, tags: list[str]
) -> Stored:
    """Validate and store an upload, then queue its ingest. A re-upload of a stuck bag queues it again."""
    staging = policy.upload_dir / f"staging-{uuid.uuid4().hex}"
    staging.mkdir(parents=True)
    try:
        try:
            root, files, sha, notes = _layout(received, staging, filename, policy)
            with open_bag(root) as bag:
                bag.summary()  # from the bag's index or summary section where it has one
                next(iter(bag.messages()), None)  # the first chunk decompresses: a bag whose data does not even
                # start is refused here (422) instead of failing its ingest later
        except BagError as err:  # name the upload, not the server's temporary paths
            raise type(err)(re.sub(rf"{re.escape(str(policy.upload_dir))}[^\s:]*", filename, str(err))) from err
        shelf = policy.shelf
        record, created = shelf.register(root, files, sha, name=sanitize_name(name or filename), tags=tags)
        if created:
            try:
                policy.queue_ingest(record.id)
            except Exception as err:
                shelf.remove(record)
                raise StorageError(f"the ingest task could not be queued ({err}); nothing was stored") from err
        elif _stuck(record, policy.stuck_after_s):
            record = shelf.requeued(record)
            policy.queue_ingest(record.id)
        return Stored(record, created, notes)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        received.path.unlink(missing_ok=True)
