"""Content ids: how a bag is recognised whatever it is called or however it was uploaded."""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from pathlib import Path

_CHUNK = 1 << 20
Hashed = Callable[[int], None]  # told the bytes hashed so far


def _file_digest(path: Path, hashed: Hashed, done_before: int) -> str:
    digest = hashlib.sha256()
    done = done_before
    with path.open("rb") as file:
        while chunk := file.read(_CHUNK):
            digest.update(chunk)
            done += len(chunk)
            hashed(done)
    return digest.hexdigest()


def content_id(paths: list[Path], *, directory: bool, hashed: Hashed = lambda _bytes: None) -> str:
    """The content hash a bag is known by: the file's sha256, or for a ROS 2 directory the sha256
    of its ``name NUL sha256`` lines (the same rule uploads use). ``hashed`` follows the reading."""
    if not directory:
        return _file_digest(paths[0], hashed, 0)
    lines, done = [], 0
    for path in sorted(paths, key=lambda p: p.name):
        lines.append(f"{path.name}\0{_file_digest(path, hashed, done)}\n")
        done += path.stat().st_size
    return hashlib.sha256("".join(lines).encode()).hexdigest()


SAMPLE = 1 << 20  # bytes read at each of three places of a large file


def _sample(path: Path) -> bytes:
    size = path.stat().st_size
    with path.open("rb") as file:
        if size <= 3 * SAMPLE:
            return file.read()
        parts = []
        for offset in (0, size // 2, size - SAMPLE):
            file.seek(offset)
            parts.append(file.read(SAMPLE))
        return b"".join(parts)


def quick_content_id(paths: list[Path], *, directory: bool) -> str:
    """A content hash read in milliseconds whatever the size: each file's size and its first, middle and
    last MiB (small files whole). Served folders list bags by it at once; the full sha256 follows."""
    digest = hashlib.sha256(b"dir" if directory else b"file")
    for path in sorted(paths, key=lambda p: p.name):
        digest.update(f"{path.name if directory else ''}\0{path.stat().st_size}\0".encode())
        digest.update(_sample(path))
    return digest.hexdigest()
