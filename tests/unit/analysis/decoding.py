"""The same bags without their columnar index, so every question is answered by decoding."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from bagmcp_shared.access import BagAccess, BagFiles
from bagmcp_shared.access.parts import BagPart
from bagmcp_shared.bags import BagReader
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.index.column_index import Locate


class WithoutIndex:
    """The same bag files, but no columnar index."""

    def __init__(self, files: BagFiles) -> None:
        self._files = files

    def path_for(self, record: BagRecord) -> Path:
        return self._files.path_for(record)

    def index_dir(self, record: BagRecord) -> Path | None:
        return None

    def index_locator(self, record: BagRecord) -> Locate | None:
        return None

    def reader_for(self, record: BagRecord) -> tuple[Path, Callable[[], BagReader]]:
        return self._files.reader_for(record)

    def parts_of(self, record: BagRecord) -> list[BagPart]:
        return self._files.parts_of(record)


@contextmanager
def decoding(access: BagAccess) -> Iterator[BagAccess]:
    """``access`` over the same catalog and files, never reading an index; its own readers closed after."""
    decoded = BagAccess(access.catalog, WithoutIndex(access.files))
    try:
        yield decoded
    finally:
        decoded.cache.close()
