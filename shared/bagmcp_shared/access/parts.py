"""A bag's files as parts to send (a download): each with its name, size and a way to stream it, so a
download never makes a local copy first (in team mode it streams from the object store)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

CHUNK_BYTES = 1 << 20


@dataclass(frozen=True)
class BagPart:
    name: str  # the file's name within the bag (a ROS 2 directory's member, or the bag file itself)
    size: int
    open: Callable[[], AbstractContextManager[BinaryIO]]

    def chunks(self) -> Iterator[bytes]:
        with self.open() as stream:
            while chunk := stream.read(CHUNK_BYTES):
                yield chunk


def local_parts(path: Path) -> list[BagPart]:
    """The parts of a local bag: the file, or the files of a ROS 2 directory (sorted by name)."""
    files = [path] if path.is_file() else sorted(p for p in path.iterdir() if p.is_file())
    return [BagPart(p.name, p.stat().st_size, lambda p=p: p.open("rb")) for p in files]  # type: ignore[misc]
