"""A built index on local disk: columns of a topic (loaded once, kept read-only), its transforms and logs;
and ``read_series``, which answers from the index when it has every column asked for, else decodes.

Its files are found through ``Locate``: a directory's files in embedded mode, and in team mode a file
fetched from the object store when it is first read (only the manifest to open the index, then only the
files a question reads: a bag's index is about fifteen files, most of which a question does not use)."""

from __future__ import annotations

import json
import threading
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
import numpy.typing as npt

from bagmcp_shared.bags import BagReader
from bagmcp_shared.index.build import FORMAT_VERSION, MANIFEST
from bagmcp_shared.index.logs import LogRow, load_logs
from bagmcp_shared.index.series import Series, decode_series
from bagmcp_shared.index.transforms import TransformRows, load_transforms

Entries = dict[str, dict[str, object]]
Locate = Callable[[str], Path]  # the local path of one of the index's files (fetched first where need be)


def _entries(document: dict[str, object], key: str) -> Entries:
    found = document.get(key)
    return found if isinstance(found, dict) else {}


def _find(entries: Entries, topic: str) -> dict[str, object] | None:
    wanted = topic.lstrip("/")
    return next((e for t, e in entries.items() if t.lstrip("/") == wanted), None)


class ColumnIndex:
    def __init__(self, locate: Locate, document: dict[str, object]) -> None:
        self._locate = locate
        self._columns = _entries(document, "topics")
        self._transforms = _entries(document, "transforms")
        self._logs = _entries(document, "logs")
        self._loaded: dict[str, object] = {}
        self._lock = threading.Lock()

    @classmethod
    def load(cls, directory: Path | None) -> ColumnIndex | None:
        """The index in ``directory``; None when there is none or it is of another format version."""
        return None if directory is None else cls.open(directory.joinpath)

    @classmethod
    def open(cls, locate: Locate | None) -> ColumnIndex | None:
        """The index whose files ``locate`` finds (its manifest read now, the rest when read); None when there
        is none or it is of another format version."""
        if locate is None:
            return None
        try:
            document = json.loads(locate(MANIFEST).read_text())
        except (OSError, ValueError):
            return None
        if not isinstance(document, dict) or document.get("version") != FORMAT_VERSION:
            return None
        return cls(locate, document)

    def header_rates(self) -> dict[str, float]:
        """Header-stamp rate of each indexed topic that has sane header stamps."""
        return {t: float(r) for t, e in self._columns.items() if isinstance(r := e.get("header_rate_hz"), int | float)}

    def columns(self, topic: str) -> list[str]:
        entry = _find(self._columns, topic)
        names = entry.get("columns") if entry else None
        return [str(n) for n in names] if isinstance(names, list) else []

    def has(self, topic: str, columns: Iterable[str]) -> bool:
        known = set(self.columns(topic))
        return bool(known) and all(c in known for c in columns)

    def transform_topics(self) -> list[str]:
        return sorted(self._transforms)

    def log_topics(self) -> list[str]:
        return sorted(self._logs)

    def loaded_bytes(self) -> int:
        with self._lock:
            return sum(_size(v) for v in self._loaded.values())

    def read(
        self, topic: str, columns: Iterable[str], *, start_ns: int | None = None, stop_ns: int | None = None
    ) -> Series:
        arrays = self._arrays(topic)
        series = Series(arrays["t_ns"], arrays["header_ns"], {c: arrays[f"c:{c}"] for c in columns}, "index")  # type: ignore[arg-type]
        return series.window(start_ns, stop_ns)

    def transforms(self, topic: str) -> TransformRows | None:
        entry = _find(self._transforms, topic)
        if entry is None:
            return None
        loaded = self._cached(f"tf:{entry['file']}", lambda: load_transforms(str(self._locate(str(entry["file"])))))
        assert isinstance(loaded, TransformRows)
        return loaded

    def logs(self, topic: str) -> list[LogRow] | None:
        entry = _find(self._logs, topic)
        if entry is None:
            return None
        loaded = self._cached(f"logs:{entry['file']}", lambda: load_logs(self._locate(str(entry["file"]))))
        assert isinstance(loaded, list)
        return loaded

    def _arrays(self, topic: str) -> dict[str, npt.NDArray[np.generic]]:
        entry = _find(self._columns, topic)
        assert entry is not None
        loaded = self._cached(f"columns:{entry['file']}", lambda: _read_npz(self._locate(str(entry["file"]))))
        assert isinstance(loaded, dict)
        return loaded

    def _cached(self, key: str, load: object) -> object:
        with self._lock:
            if key not in self._loaded:
                assert callable(load)
                self._loaded[key] = load()
            return self._loaded[key]


def _read_npz(path: Path) -> dict[str, npt.NDArray[np.generic]]:
    with np.load(path) as data:
        arrays = {key: data[key] for key in data.files}
    for array in arrays.values():
        array.setflags(write=False)
    return arrays


def _size(value: object) -> int:
    if isinstance(value, dict):
        return sum(a.nbytes for a in value.values() if isinstance(a, np.ndarray))
    if isinstance(value, TransformRows):
        return value.t_ns.nbytes * 8
    if isinstance(value, list):
        return 200 * len(value)
    return 0


def read_series(
    reader: BagReader,
    topic: str,
    columns: Iterable[str],
    *,
    index: ColumnIndex | None,
    start_ns: int | None = None,
    stop_ns: int | None = None,
    progress: Callable[[float, str], None] | None = None,
) -> Series:
    """Columns of ``topic`` in a window: from the index when it has them all, else decoded."""
    names = list(columns)
    if index is not None and index.has(topic, names):
        return index.read(topic, names, start_ns=start_ns, stop_ns=stop_ns)
    return decode_series(reader, topic, names, start_ns=start_ns, stop_ns=stop_ns, progress=progress)
