"""Unpacking uploaded zip/tar archives of ROS 2 bag directories, refusing anything unsafe."""

from __future__ import annotations

import tarfile
import zipfile
from pathlib import Path, PurePosixPath

from bagmcp_bag_store.errors import UploadError

MAX_MEMBERS = 10_000


def is_archive(path: Path) -> bool:
    return zipfile.is_zipfile(path) or _is_tar(path)


def _is_tar(path: Path) -> bool:
    try:
        return tarfile.is_tarfile(path)
    except OSError:
        return False


def _check_member(name: str) -> None:
    pure = PurePosixPath(name)
    if pure.is_absolute() or ".." in pure.parts or "\\" in name:
        raise UploadError(f"the archive holds an unsafe path {name!r}; refusing it")


def _extract_zip(path: Path, dest: Path, max_bytes: int) -> None:
    with zipfile.ZipFile(path) as archive:
        members = archive.infolist()
        if len(members) > MAX_MEMBERS or sum(m.file_size for m in members) > max_bytes:
            raise UploadError("the archive unpacks to more than the upload limit allows")
        for member in members:
            _check_member(member.filename)
            if (member.external_attr >> 16) & 0o170000 == 0o120000:
                raise UploadError(f"the archive holds a symbolic link {member.filename!r}; refusing it")
        archive.extractall(dest)


def _extract_tar(path: Path, dest: Path, max_bytes: int) -> None:
    with tarfile.open(path) as archive:
        total = 0
        for number, member in enumerate(archive, start=1):  # headers are read one at a time
            total += member.size
            if number > MAX_MEMBERS or total > max_bytes:
                raise UploadError("the archive unpacks to more than the upload limit allows")
            _check_member(member.name)
            if not (member.isfile() or member.isdir()):
                raise UploadError(f"the archive holds {member.name!r}, which is not a plain file; refusing it")
        archive.extractall(dest, filter="data")


def extract(path: Path, dest: Path, *, max_bytes: int) -> Path:
    """Unpack ``path`` into ``dest`` and return the bag inside (a directory or one bag file)."""
    dest.mkdir(parents=True)
    try:
        if zipfile.is_zipfile(path):
            _extract_zip(path, dest, max_bytes)
        else:
            _extract_tar(path, dest, max_bytes)
    except (zipfile.BadZipFile, tarfile.TarError, EOFError, OSError) as err:
        raise UploadError(f"the archive could not be unpacked ({err})") from err
    return _bag_root(dest)


def _bag_root(directory: Path) -> Path:
    entries = [e for e in directory.iterdir() if not e.name.startswith(("__MACOSX", "."))]
    files = [e for e in entries if e.is_file()]
    dirs = [e for e in entries if e.is_dir()]
    if any(f.name == "metadata.yaml" or f.suffix in (".db3", ".mcap") for f in files) and not dirs:
        return directory
    if len(files) == 1 and not dirs:
        return files[0]
    if len(dirs) == 1 and not files:
        return _bag_root(dirs[0])
    raise UploadError(
        "the archive must hold exactly one bag: a ROS 2 bag directory (metadata.yaml and its "
        ".db3/.mcap files) or a single bag file"
    )
