"""TF transforms as rows: one per transform in every message of a TF topic (``tf2_msgs/TFMessage`` and
the old ``tf/tfMessage``), with frames as indexes into a frame list. Built at ingest, or decoded."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Protocol, cast

import numpy as np
import numpy.typing as npt

from bagmcp_shared.bags import BagReader, Connection
from bagmcp_shared.bags.counted import ReportProgress, counted
from bagmcp_shared.timebase import MAX_CLOCK_SKEW_NS, header_stamp_ns

TF_TYPES = frozenset({"tf2_msgs/msg/TFMessage", "tf/msg/tfMessage"})


class _Vector(Protocol):
    x: float
    y: float
    z: float


class _Quaternion(_Vector, Protocol):
    w: float


class _Transform(Protocol):
    translation: _Vector
    rotation: _Quaternion


class _Header(Protocol):
    frame_id: str


class _Stamped(Protocol):
    header: _Header
    child_frame_id: str
    transform: _Transform


class _TfMessage(Protocol):
    transforms: list[_Stamped]


def normalize_frame(name: str) -> str:
    """Frame id without leading slashes or surrounding whitespace ("/base_link" -> "base_link")."""
    return name.strip().lstrip("/")


def is_finite_sample(translation: Sequence[float], rotation: Sequence[float]) -> bool:
    """True when the translation is finite and the rotation is a finite, non-zero quaternion."""
    values = (*translation, *rotation)
    if not all(math.isfinite(v) for v in values):
        return False
    return math.sqrt(sum(v * v for v in rotation)) > 1e-9


def is_static(conn: Connection) -> bool:
    """Static transforms come on /tf_static, or on a latched (transient-local) TF connection."""
    return conn.topic.rstrip("/").endswith("tf_static") or conn.latched


@dataclass(frozen=True)
class TransformRows:
    """``t_ns`` is each transform's header stamp, or its log time when the stamp is zero or on another
    clock (a simulation's), so transforms and the bag's times can be compared."""

    t_ns: npt.NDArray[np.int64]
    parent: npt.NDArray[np.int32]
    child: npt.NDArray[np.int32]
    translation: npt.NDArray[np.float64]  # (n, 3)
    rotation: npt.NDArray[np.float64]  # (n, 4): x, y, z, w
    static: npt.NDArray[np.bool_]
    frames: tuple[str, ...]

    def __len__(self) -> int:
        return len(self.t_ns)


@dataclass
class TransformCollector:
    """Accumulates rows, one decoded TF message at a time."""

    frames: dict[str, int] = field(default_factory=dict)
    rows: list[tuple[int, int, int, float, float, float, float, float, float, float, bool]] = field(
        default_factory=list
    )

    def _frame(self, name: str) -> int:
        return self.frames.setdefault(name, len(self.frames))

    def add(self, log_ns: int, message: object, *, static: bool) -> None:
        for item in cast(_TfMessage, message).transforms:
            stamp = header_stamp_ns(item) or log_ns
            if abs(stamp - log_ns) > MAX_CLOCK_SKEW_NS:
                stamp = log_ns
            t, r = item.transform.translation, item.transform.rotation
            parent, child = self._frame(item.header.frame_id), self._frame(item.child_frame_id)
            self.rows.append((stamp, parent, child, t.x, t.y, t.z, r.x, r.y, r.z, r.w, static))

    def rows_out(self) -> TransformRows:
        table = self.rows
        values = np.asarray([r[3:10] for r in table], dtype=np.float64).reshape(-1, 7)
        return TransformRows(
            t_ns=np.asarray([r[0] for r in table], dtype=np.int64),
            parent=np.asarray([r[1] for r in table], dtype=np.int32),
            child=np.asarray([r[2] for r in table], dtype=np.int32),
            translation=values[:, :3],
            rotation=values[:, 3:],
            static=np.asarray([r[10] for r in table], dtype=bool),
            frames=tuple(self.frames),
        )


def tf_connections(reader: BagReader) -> list[Connection]:
    return [c for c in reader.connections if c.msgtype in TF_TYPES and c.count]


def decode_transforms(
    reader: BagReader, connections: Iterable[Connection] | None = None, *, progress: ReportProgress | None = None
) -> TransformRows:
    """Every transform of the bag's TF topics, decoded (when the index has none)."""
    chosen = list(connections) if connections is not None else tf_connections(reader)
    static = {c.id: is_static(c) for c in chosen}
    collector = TransformCollector()
    topics = sorted({c.topic for c in chosen})
    expected = sum(c.count for t in topics for c in reader.topic_connections(t))
    for raw in counted(reader.messages(topics), expected=expected, progress=progress, what=", ".join(topics)):
        if raw.connection.id in static or raw.connection.msgtype in TF_TYPES:
            collector.add(raw.log_time_ns, reader.decode(raw), static=static.get(raw.connection.id, False))
    return collector.rows_out()


def save_transforms(rows: TransformRows, path: str) -> None:
    np.savez(
        path,
        t_ns=rows.t_ns,
        parent=rows.parent,
        child=rows.child,
        translation=rows.translation,
        rotation=rows.rotation,
        static=rows.static,
        frames=np.asarray(rows.frames, dtype=np.str_),
    )


def load_transforms(path: str) -> TransformRows:
    with np.load(path) as data:
        return TransformRows(
            t_ns=data["t_ns"],
            parent=data["parent"],
            child=data["child"],
            translation=data["translation"],
            rotation=data["rotation"],
            static=data["static"],
            frames=tuple(str(f) for f in data["frames"]),
        )
