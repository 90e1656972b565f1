"""One bag's rows of every view, taken from what ingest already extracted (its columnar index and catalog
summary): nothing here decodes the bag again, so feeding the store costs a few milliseconds a bag."""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Sequence

import numpy as np
import numpy.typing as npt
import pyarrow as pa

from bagmcp_bag_store.fleet.motion import pose_speeds, topic_gap
from bagmcp_bag_store.fleet.tf_rows import tf_edge_rows
from bagmcp_bag_store.fleet.views import VIEWS
from bagmcp_shared.access import KnownBag
from bagmcp_shared.catalog import BagRecord, CatalogSummary
from bagmcp_shared.flight_types import FLIGHT_POSES
from bagmcp_shared.gps_metres import local_metres
from bagmcp_shared.index import RECORD_TYPES, TF_TYPES
from bagmcp_shared.log_levels import level_name, level_rank

Arrays = dict[str, npt.NDArray[np.generic] | Sequence[object]]
_XYZ = ("x", "y", "z")
_POSES = {  # type -> where its position and orientation are (index columns)
    "nav_msgs/msg/Odometry": "pose.pose",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "pose.pose",
    "geometry_msgs/msg/PoseStamped": "pose",
    "geometry_msgs/msg/Pose": "",
}
_TWISTS = {
    "nav_msgs/msg/Odometry": "twist.twist",
    "geometry_msgs/msg/TwistStamped": "twist",
    "geometry_msgs/msg/Twist": "",
}


def _at(prefix: str, path: str) -> str:
    return f"{prefix}.{path}" if prefix else path


class IngestedBag(KnownBag):
    """What ingest knows about a bag: its record, summary and (when built) columnar index."""

    def topics_of(self, types: Collection[str]) -> Iterator[tuple[str, str]]:
        """(topic, type) of the bag's topics whose type is among ``types``."""
        for topic in self.summary.topics:
            if topic.type in types:
                yield topic.name, topic.type


def _table(kind: str, bag: IngestedBag, rows: list[Arrays]) -> pa.Table:
    """The rows (one dict of equal-length columns per topic) as the view's table, with the bag's columns,
    sorted by time (``t``) when the view has it: the topics interleave (a stable sort keeps each topic's own
    order among equal times), so a file's row groups cover increasing times and readers can skip by time.
    NaN becomes NULL, so max() and comparisons skip unknown values (DuckDB sorts NaN above every number).
    A view without rows is the view's one empty table, and one topic already in time order is not sorted
    (the same rows; on 10 s drives these took 1 of the 7 ms a bag's views cost)."""
    view = VIEWS[kind]
    if not rows:
        return view.empty
    tables = []
    for part in rows:
        count = len(next(iter(part.values())))
        named = {"bag": [bag.record.name] * count, "bag_id": [bag.record.id] * count, **part}
        arrays = [pa.array(named[f.name], type=f.type, from_pandas=True) for f in view.schema]
        tables.append(pa.Table.from_arrays(arrays, schema=view.schema))
    table = tables[0] if len(tables) == 1 else pa.concat_tables(tables)
    if "t" in view.schema.names and table.num_rows > 1 and not (len(rows) == 1 and _ascending(rows[0]["t"])):
        table = table.sort_by("t")
    return table


def _ascending(t: npt.NDArray[np.generic] | Sequence[object]) -> bool:
    times = np.asarray(t, dtype=np.float64)
    return bool(np.all(times[1:] >= times[:-1]))


def _timed(bag: IngestedBag, topic: str, t_ns: npt.NDArray[np.int64], values: Arrays) -> Arrays:
    return {
        "topic": [topic] * len(t_ns),
        "t": t_ns / 1e9,
        "offset_s": (t_ns - bag.start_ns) / 1e9,
        **values,
    }


def _series_rows(bag: IngestedBag, types: dict[str, str], build: Callable[[str, str], Arrays | None]) -> list[Arrays]:
    index = bag.index
    if index is None:
        return []
    found = []
    for topic, msgtype in bag.topics_of(types):
        rows = build(topic, types[msgtype])
        if rows is not None:
            found.append(rows)
    return found


def _read(
    bag: IngestedBag, topic: str, columns: list[str]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], list[npt.NDArray[np.float64]]] | None:
    index = bag.index
    if index is None or not index.has(topic, columns):
        return None
    series = index.read(topic, columns)
    return series.t_ns, series.header_ns, [series.columns[c].astype(np.float64) for c in columns]


def poses(bag: IngestedBag) -> pa.Table:
    def build(topic: str, prefix: str) -> Arrays | None:
        columns = [_at(prefix, f"position.{a}") for a in _XYZ] + [_at(prefix, "orientation.yaw")]
        found = _read(bag, topic, columns)
        if found is None:
            return None
        t_ns, header_ns, (x, y, z, yaw) = found
        speed = pose_speeds(t_ns, header_ns, x, y)
        return _timed(bag, topic, t_ns, {"x": x, "y": y, "z": z, "yaw": yaw, "speed": speed})

    flights = [r for topic, msgtype in bag.topics_of(FLIGHT_POSES) if (r := _flight_pose(bag, topic, msgtype))]
    return _table("poses", bag, [*_series_rows(bag, _POSES, build), *flights])


def _flight_pose(bag: IngestedBag, topic: str, msgtype: str) -> Arrays | None:
    """A flight log's local position (x, y, z at the top level; the heading under the name its version uses)."""
    known = bag.index.columns(topic) if bag.index is not None else []
    heading = next((h for h in FLIGHT_POSES[msgtype] if h in known), None)
    found = _read(bag, topic, ["x", "y", "z", heading]) if heading is not None else None
    if found is None:
        return None
    t_ns, header_ns, (x, y, z, yaw) = found
    speed = pose_speeds(t_ns, header_ns, x, y)
    return _timed(bag, topic, t_ns, {"x": x, "y": y, "z": z, "yaw": yaw, "speed": speed})


def twists(bag: IngestedBag) -> pa.Table:
    names = {
        "vx": "linear.x",
        "vy": "linear.y",
        "vz": "linear.z",
        "wx": "angular.x",
        "wy": "angular.y",
        "wz": "angular.z",
    }
    return _table("twists", bag, _series_rows(bag, _TWISTS, lambda t, p: _columns(bag, t, p, names)))


def imu(bag: IngestedBag) -> pa.Table:
    names = {
        **{f"a{a}": f"linear_acceleration.{a}" for a in _XYZ},
        **{f"w{a}": f"angular_velocity.{a}" for a in _XYZ},
        **{a: f"orientation.{a}" for a in ("roll", "pitch", "yaw")},
    }
    return _table("imu", bag, _series_rows(bag, {"sensor_msgs/msg/Imu": ""}, lambda t, p: _columns(bag, t, p, names)))


def battery(bag: IngestedBag) -> pa.Table:
    names = {n: n for n in ("voltage", "current", "percentage")}
    types = {"sensor_msgs/msg/BatteryState": ""}
    return _table("battery", bag, _series_rows(bag, types, lambda t, p: _columns(bag, t, p, names)))


def scans(bag: IngestedBag) -> pa.Table:
    names = {"min_range": "min_range", "bearing": "min_bearing"}
    types = {"sensor_msgs/msg/LaserScan": ""}
    return _table("scans", bag, _series_rows(bag, types, lambda t, p: _columns(bag, t, p, names)))


def _columns(bag: IngestedBag, topic: str, prefix: str, names: dict[str, str]) -> Arrays | None:
    """The index columns ``names`` (view column -> message path under ``prefix``) of one topic."""
    found = _read(bag, topic, [_at(prefix, p) for p in names.values()])
    if found is None:
        return None
    t_ns, _, values = found
    return _timed(bag, topic, t_ns, dict(zip(names, values, strict=True)))


def gps(bag: IngestedBag) -> pa.Table:
    def build(topic: str, _prefix: str) -> Arrays | None:
        found = _read(bag, topic, ["latitude", "longitude", "altitude", "status.status"])
        if found is None:
            return None
        t_ns, _, (lat, lon, alt, status) = found
        east, north = np.full(len(t_ns), np.nan), np.full(len(t_ns), np.nan)
        try:
            metres = local_metres(lat, lon, alt, status)
            east[metres.kept], north[metres.kept] = metres.east_m, metres.north_m
        except ValueError:
            pass  # no valid fix: east and north stay NULL
        values: Arrays = {
            "lat": lat,
            "lon": lon,
            "alt": alt,
            "east": east,
            "north": north,
            "status": status.astype(np.int64),
        }
        return _timed(bag, topic, t_ns, values)

    return _table("gps", bag, _series_rows(bag, {"sensor_msgs/msg/NavSatFix": ""}, build))


def logs(bag: IngestedBag) -> pa.Table:
    parts: list[Arrays] = []
    index = bag.index
    for topic, msgtype in bag.topics_of(RECORD_TYPES):  # ROS logs and flight-log texts (ROS 1 level numbers)
        records = index.logs(topic) if index is not None else None
        if not records:
            continue
        ros2 = msgtype.startswith("rcl_interfaces/")
        levels = [level_name(r.level, ros2=ros2) for r in records]
        t_ns = np.asarray([r.t_ns for r in records], dtype=np.int64)
        values: Arrays = {
            "level": levels,
            "level_rank": [level_rank(n) for n in levels],
            "node": [r.node for r in records],
            "text": [r.text for r in records],
            "file": [r.file for r in records],
            "function": [r.function for r in records],
            "line": [r.line for r in records],
        }
        parts.append(_timed(bag, topic, t_ns, values))
    return _table("logs", bag, parts)


def tf_edges(bag: IngestedBag) -> pa.Table:
    index = bag.index
    found = [index.transforms(topic) if index is not None else None for topic, _ in bag.topics_of(TF_TYPES)]
    rows = [r for r in found if r is not None and len(r)]
    return _table("tf_edges", bag, [tf_edge_rows(rows)] if rows else [])


def topics(bag: IngestedBag) -> pa.Table:
    found = bag.summary.topics
    gaps = [topic_gap(bag.index, t.name) if bag.index is not None else None for t in found]
    columns: Arrays = {
        "topic": [t.name for t in found],
        "type": [t.type for t in found],
        "count": [t.count for t in found],
        "rate_hz": [t.rate_hz for t in found],
        "max_gap_s": [g[0] if g else None for g in gaps],
        "max_gap_at_s": [(g[1] - bag.start_ns) / 1e9 if g else None for g in gaps],
        "first_t": [t.first_ns / 1e9 if t.first_ns is not None else None for t in found],
        "last_t": [t.last_ns / 1e9 if t.last_ns is not None else None for t in found],
    }
    return _table("topics", bag, [columns] if found else [])


def bag_row(record: BagRecord, summary: CatalogSummary) -> dict[str, object]:
    return {
        "bag": record.name,
        "id": record.id,
        "format": summary.format,
        "start": summary.start_ns / 1e9 if summary.start_ns is not None else None,
        "end": summary.end_ns / 1e9 if summary.end_ns is not None else None,
        "duration_s": summary.duration_s,
        "size_bytes": record.size_bytes,
        "message_count": summary.message_count,
        "tags": list(record.tags),
    }


def bags_of(records: list[tuple[BagRecord, CatalogSummary]]) -> pa.Table:
    """The ``bags`` view of these bags (queries build it from the catalog itself, so tags are current)."""
    rows = [bag_row(record, summary) for record, summary in records]
    return pa.Table.from_pylist(rows, schema=VIEWS["bags"].schema)


def bags(bag: IngestedBag) -> pa.Table:
    return bags_of([(bag.record, bag.summary)])


EXTRACTORS: dict[str, Callable[[IngestedBag], pa.Table]] = {
    "bags": bags,
    "topics": topics,
    "poses": poses,
    "twists": twists,
    "imu": imu,
    "gps": gps,
    "battery": battery,
    "scans": scans,
    "logs": logs,
    "tf_edges": tf_edges,
}
