"""The views of the columnar store: their columns (names, Arrow types, meanings), stated once. The Parquet
files ingest writes, the DuckDB views ``query_bags`` reads, the tool's description and its resource all come
from this table, so they cannot disagree.

Each view also names the per-bag tools that reveal the same data: a token that may call none of them does
not see the view (the gateway passes the tools a restricted token may call).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import pyarrow as pa

VERSION = "v1"  # part of every file's key: a new layout is written beside the old, never mixed with it
TIMED = ("t", "offset_s")
RAW_READERS = ("get_messages_in_range", "get_message_at_time", "search_messages")


@dataclass(frozen=True)
class Column:
    name: str
    type: pa.DataType
    doc: str = ""


@dataclass(frozen=True)
class View:
    name: str
    doc: str
    columns: tuple[Column, ...]
    tools: tuple[str, ...]  # per-bag tools that answer from the same data

    @cached_property
    def schema(self) -> pa.Schema:
        """Built once (every bag's ingest asks for it once per view: rebuilding it cost 0.1 ms each time)."""
        return pa.schema([pa.field(c.name, c.type) for c in self.columns])

    @cached_property
    def empty(self) -> pa.Table:
        """No rows (an Arrow table is immutable, so one serves every bag without the view's topics)."""
        return self.schema.empty_table()

    @property
    def names(self) -> list[str]:
        return [c.name for c in self.columns]

    def signature(self) -> str:
        return f"{self.name}({', '.join(self.names)})"


_F, _S, _I = pa.float64(), pa.string(), pa.int64()


def _c(names: str, kind: pa.DataType = _F, doc: str = "") -> tuple[Column, ...]:
    return tuple(Column(n, kind, doc) for n in names.split())


_BAG = (Column("bag", _S, "bag name"), Column("bag_id", _S, "bag id"))
_TOPIC = (Column("topic", _S),)
_TIME = (Column("t", _F, "epoch s (log time)"), Column("offset_s", _F, "s from the bag's start"))


def _series(name: str, doc: str, values: tuple[Column, ...], tools: tuple[str, ...] = ()) -> View:
    return View(name, doc, (*_BAG, *_TOPIC, *_TIME, *values), (*tools, *RAW_READERS))


VIEWS: dict[str, View] = {
    v.name: v
    for v in (
        View(
            "bags",
            "one row per bag",
            (
                Column("bag", _S, "name"),
                Column("id", _S),
                Column("format", _S),
                *_c("start end", doc="epoch s"),
                Column("duration_s", _F),
                *_c("size_bytes message_count", _I),
                Column("tags", pa.list_(_S)),
            ),
            ("list_bags", "bag_info"),
        ),
        View(
            "topics",
            "per topic: count, mean rate, longest gap between messages and its start (NULL: times not indexed)",
            (
                *_BAG,
                *_TOPIC,
                Column("type", _S),
                Column("count", _I),
                *_c("rate_hz max_gap_s max_gap_at_s"),
                *_c("first_t last_t", doc="epoch s"),
            ),
            ("bag_info", "topic_statistics"),
        ),
        _series(
            "poses",
            "odometry, pose topics and PX4 local positions; speed m/s over >= 0.05 s windows (header clock when sane)",
            _c("x y z yaw speed"),
            ("analyze_trajectory",),
        ),
        _series("twists", "twist, twist-stamped and odometry twists (m/s, rad/s)", _c("vx vy vz wx wy wz")),
        _series(
            "imu", "acceleration m/s^2, angular rate rad/s, orientation rad", _c("ax ay az wx wy wz roll pitch yaw")
        ),
        _series(
            "gps",
            "NavSatFix; east/north m from the bag's first valid fix (NULL when invalid)",
            (*_c("lat lon alt east north"), Column("status", _I)),
            ("analyze_trajectory",),
        ),
        _series("battery", "BatteryState", _c("voltage current percentage")),
        _series(
            "scans",
            "closest valid range of each LaserScan (m) and its bearing (rad)",
            _c("min_range bearing"),
            ("analyze_lidar_scan",),
        ),
        _series(
            "logs",
            "ROS log records and flight-log texts; level DEBUG INFO WARN ERROR FATAL, level_rank 0..4",
            (Column("level", _S), Column("level_rank", _I), *_c("node text file function", _S), Column("line", _I)),
            ("analyze_logs",),
        ),
        View(
            "tf_edges",
            "TF parent->child edges with their rates",
            (
                *_BAG,
                *_c("parent child", _S),
                Column("static", pa.bool_()),
                Column("count", _I),
                *_c("rate_hz"),
                *_c("first_t last_t", doc="epoch s"),
            ),
            ("get_tf_tree", *RAW_READERS),
        ),
    )
}
KINDS = tuple(VIEWS)


def views_for(tools: frozenset[str] | None) -> list[str]:
    """The views a caller may read: all of them (``tools`` None: not restricted), else those at least one of
    whose per-bag tools the caller may call."""
    return [v.name for v in VIEWS.values() if tools is None or any(t in tools for t in v.tools)]


def describe(names: list[str] | None = None) -> str:
    """Every view (or those named) as ``name(col, ...)``, one a line."""
    chosen = [VIEWS[n] for n in (names if names is not None else KINDS)]
    return "\n".join(f"{v.signature()}: {v.doc}" for v in chosen)
