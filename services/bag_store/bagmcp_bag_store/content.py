"""Content ids: how a bag is recognised whatever it is called or however it was uploaded."""

from __future__ import annotations

import hashlib
from pathlib import Path

_CHUNK = 1 << 20


def _file_digest(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as file:
        while chunk := file.read(_CHUNK):
            digest.update(chunk)
    return digest.hexdigest()


def content_id(paths: list[Path], *, directory: bool) -> str:
    """The content hash a bag is known by: the file's sha256, or for a ROS 2 directory the sha256
    of its ``name NUL sha256`` lines (the same rule uploads use)."""
    if not directory:
        return _file_digest(paths[0])
    listing = "".join(f"{p.name}\0{_file_digest(p)}\n" for p in sorted(paths, key=lambda p: p.name))
    return hashlib.sha256(listing.encode()).hexdigest()
