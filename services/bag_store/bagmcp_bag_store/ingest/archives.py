"""Unpacking uploaded zip/tar archives of ROS 2 bag directories, refusing anything unsafe.

Only files that can belong to a bag are written (metadata.yaml and recordings); the rest is dropped with a
note. Bombs are refused: the sizes the archive declares and the bytes actually written both count against
``ArchiveLimits.max_bytes``, there is a member count limit, and a zip member may not expand more than
``max_ratio`` times.
"""

from __future__ import annotations

import tarfile
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import IO

from bagmcp_bag_store.errors import UploadError, UploadTooLargeError

BAG_FILE_SUFFIXES = (".bag", ".mcap", ".db3", ".mcap.zstd", ".db3.zstd", ".ulg", ".bin", ".BIN")
_STEP = 1 << 20
_RATIO_FLOOR_BYTES = 1 << 20  # small members (metadata.yaml) compress well; judge ratios above this size


@dataclass(frozen=True)
class ArchiveLimits:
    """``max_bytes``: everything the archive holds, declared and written; ``max_ratio``: how much one
    compressed zip member may expand."""

    max_bytes: int
    max_members: int = 1000
    max_ratio: float = 200.0


@dataclass
class Unpacked:
    """Where the bag is (a directory or one file) and what was left out of it, one note per member."""

    root: Path
    dropped: list[str] = field(default_factory=list)


def is_archive(path: Path) -> bool:
    return zipfile.is_zipfile(path) or _is_tar(path)


def _is_tar(path: Path) -> bool:
    try:
        return tarfile.is_tarfile(path)
    except OSError:
        return False


def _safe_name(name: str) -> PurePosixPath:
    pure = PurePosixPath(name)
    if pure.is_absolute() or ".." in pure.parts or "\\" in name:
        raise UploadError(f"the archive holds an unsafe path {name!r}; refusing it")
    return pure


def _belongs_to_a_bag(name: PurePosixPath) -> bool:
    hidden = any(part.startswith((".", "__MACOSX")) for part in name.parts)
    return not hidden and (name.name == "metadata.yaml" or name.name.endswith(BAG_FILE_SUFFIXES))


class _Budget:
    """Counts members and bytes against the limits; the first excess refuses the whole archive."""

    def __init__(self, limits: ArchiveLimits) -> None:
        self.limits = limits
        self.members = 0
        self.declared = 0
        self.written = 0

    def declare(self, size: int) -> None:
        self.members += 1
        self.declared += size
        if self.members > self.limits.max_members:
            raise UploadError(f"the archive holds more than {self.limits.max_members} files; a bag has far fewer")
        if self.declared > self.limits.max_bytes:
            raise self._too_big()

    def write(self, source: IO[bytes], target: Path, *, compressed_bytes: int | None) -> None:
        """Copy one member while counting what is actually written."""
        written = 0
        with target.open("wb") as out:
            while chunk := source.read(_STEP):
                written += len(chunk)
                self.written += len(chunk)
                if self.written > self.limits.max_bytes:
                    raise self._too_big()
                if compressed_bytes is not None and written > max(
                    _RATIO_FLOOR_BYTES, self.limits.max_ratio * compressed_bytes
                ):
                    raise UploadError(
                        f"{target.name} in the archive expands more than {self.limits.max_ratio:.0f} times "
                        "(a zip bomb?); refusing it"
                    )
                out.write(chunk)

    def _too_big(self) -> UploadTooLargeError:
        return UploadTooLargeError(
            f"the archive unpacks to more than {self.limits.max_bytes:,} bytes, more than this server accepts "
            "for an upload of its size; upload the bag's files without padding, or as a plain tar"
        )


def _kept(name: str, *, directory: bool, dest: Path, dropped: list[str]) -> Path | None:
    """Where a member goes, or None: a directory (made as its files need it), or not part of a bag (noted)."""
    pure = _safe_name(name)
    if directory:
        return None
    if not _belongs_to_a_bag(pure):
        dropped.append(f"{name} was left out: it is not part of a bag")
        return None
    target = dest.joinpath(*pure.parts)
    target.parent.mkdir(parents=True, exist_ok=True)
    return target


def _zip_members(path: Path, dest: Path, budget: _Budget, dropped: list[str]) -> None:
    with zipfile.ZipFile(path) as archive:
        members = archive.infolist()
        for member in members:
            _safe_name(member.filename)
            if (member.external_attr >> 16) & 0o170000 == 0o120000:
                raise UploadError(f"the archive holds a symbolic link {member.filename!r}; refusing it")
            budget.declare(member.file_size)
        for member in members:
            if (target := _kept(member.filename, directory=member.is_dir(), dest=dest, dropped=dropped)) is not None:
                with archive.open(member) as source:
                    budget.write(source, target, compressed_bytes=member.compress_size)


def _tar_members(path: Path, dest: Path, budget: _Budget, dropped: list[str]) -> None:
    with tarfile.open(path) as archive:
        for member in _tar_headers(archive, budget):  # headers are read one at a time
            if (target := _kept(member.name, directory=member.isdir(), dest=dest, dropped=dropped)) is not None:
                source = archive.extractfile(member)
                assert source is not None  # a regular file
                with source:
                    budget.write(source, target, compressed_bytes=None)


def _tar_headers(archive: tarfile.TarFile, budget: _Budget) -> Iterator[tarfile.TarInfo]:
    for member in archive:
        _safe_name(member.name)
        if not (member.isfile() or member.isdir()):
            raise UploadError(f"the archive holds {member.name!r}, which is not a plain file; refusing it")
        budget.declare(member.size)
        yield member


def extract(path: Path, dest: Path, *, limits: ArchiveLimits) -> Unpacked:
    """Unpack the bag files of ``path`` into ``dest``; returns the bag inside (a directory or one bag file)."""
    dest.mkdir(parents=True)
    budget, dropped = _Budget(limits), list[str]()
    try:
        if zipfile.is_zipfile(path):
            _zip_members(path, dest, budget, dropped)
        else:
            _tar_members(path, dest, budget, dropped)
    except (zipfile.BadZipFile, zipfile.LargeZipFile, tarfile.TarError, EOFError, OSError, ValueError) as err:
        raise UploadError(f"the archive could not be unpacked ({err}); send an intact zip or tar") from err
    return Unpacked(_bag_root(dest), dropped)


def _bag_root(directory: Path) -> Path:
    files = [e for e in directory.iterdir() if e.is_file()]
    dirs = [e for e in directory.iterdir() if e.is_dir()]
    if any(f.name == "metadata.yaml" or f.name.endswith((".db3", ".mcap", ".zstd")) for f in files) and not dirs:
        return directory
    if len(files) == 1 and not dirs:
        return files[0]
    if len(dirs) == 1 and not files:
        return _bag_root(dirs[0])
    raise UploadError(
        "the archive must hold exactly one bag: a ROS 2 bag directory (metadata.yaml and its "
        ".db3/.mcap files) or a single bag file"
    )
