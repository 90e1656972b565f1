"""Reading a topic's window for a search condition (query/conditions.py): a column of numbers or x/y
positions from the columnar index when it has them (else decoded), or each message decoded."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from pydantic import JsonValue

from bagmcp_bag_store.queries.conditions import Judging, Masking, NearPosition
from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import ColumnIndex, read_series
from bagmcp_shared.jobs import Progress
from bagmcp_shared.paths import check_steps, parse_field_path

OBVIOUS_SCALAR = {
    "nav_msgs/msg/Odometry": "twist.twist.linear.x",
    "geometry_msgs/msg/Twist": "linear.x",
    "geometry_msgs/msg/TwistStamped": "twist.linear.x",
    "sensor_msgs/msg/LaserScan": "min_range",
    "sensor_msgs/msg/BatteryState": "percentage",
    "sensor_msgs/msg/Range": "range",
    "sensor_msgs/msg/Temperature": "temperature",
    "sensor_msgs/msg/NavSatFix": "altitude",
    "rosgraph_msgs/msg/Log": "level",
    "rcl_interfaces/msg/Log": "level",
}
POSITION_FIELD = {
    "nav_msgs/msg/Odometry": "pose.pose.position",
    "geometry_msgs/msg/PoseStamped": "pose.position",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "pose.pose.position",
    "geometry_msgs/msg/Pose": "position",
    "geometry_msgs/msg/Point": "",
    "geometry_msgs/msg/PointStamped": "point",
}
PROGRESS_EVERY = 500  # decoded messages between progress reports


@dataclass
class Found:
    """Indexes (into the window's messages) that matched, with times and values to show."""

    t_ns: npt.NDArray[np.int64]
    mask: npt.NDArray[np.bool_]
    values: list[JsonValue]
    source: str
    field: str
    distance: npt.NDArray[np.float64] | None = None
    xy: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None = None


@dataclass(frozen=True)
class BagScan:
    """One topic's [lo, hi] window of an open bag; ``field`` is the caller's path (None: the obvious one)."""

    ob: OpenBag
    topic: str
    field: str | None
    index: ColumnIndex | None
    lo: int
    hi: int
    progress: Progress

    @property
    def msgtype(self) -> str:
        return self.ob.msgtype(self.topic)

    def numbers(self, condition: Masking) -> Found:
        field = self.field or OBVIOUS_SCALAR.get(self.msgtype)
        if field is None and self.msgtype.startswith("std_msgs/msg/"):
            field = "data"
        if field is None:
            raise ArgumentError(
                f"{self.msgtype} has no obvious number to compare; pass `field`, e.g. from describe_topic"
            )
        series = read_series(
            self.ob.reader, self.topic, [field], index=self.index, start_ns=self.lo, stop_ns=self.hi + 1
        )
        try:
            values = series.columns[field].astype(np.float64)
        except (TypeError, ValueError) as err:
            raise ArgumentError(f"{field} is not numeric; use contains, regex or equals with a string") from err
        mask = condition.mask(values)
        return Found(series.t_ns, mask, [float(v) for v in values[mask]], series.source, field)

    def positions(self, near: NearPosition) -> Found:
        base = self.field if self.field is not None else POSITION_FIELD.get(self.msgtype)
        if base is None:
            raise ArgumentError(
                f"{self.msgtype} has no obvious position; pass `field` naming a point, e.g. pose.position"
            )
        columns = [f"{base}.x" if base else "x", f"{base}.y" if base else "y"]
        series = read_series(
            self.ob.reader, self.topic, columns, index=self.index, start_ns=self.lo, stop_ns=self.hi + 1
        )
        xs, ys = (series.columns[c].astype(np.float64) for c in columns)
        distance = near.distances(xs, ys)
        mask = distance <= near.radius
        values: list[JsonValue] = [{"x": float(x), "y": float(y)} for x, y in zip(xs[mask], ys[mask], strict=True)]
        return Found(series.t_ns, mask, values, series.source, base or "(the message itself)", distance, (xs, ys))

    def messages(self, condition: Judging) -> Found:
        """Each message of the window decoded and judged (text conditions and field_exists)."""
        steps = parse_field_path(self.field) if self.field else None
        if steps is not None:
            check_steps(self.ob.reader.decoder.typestore(self.msgtype), self.msgtype, steps)
        expected = max(self.ob.topic(self.topic).count, 1)
        times, hits, shown = [], [], []
        for number, raw in enumerate(self.ob.reader.messages([self.topic], start_ns=self.lo, stop_ns=self.hi + 1)):
            hit, value = condition.judge(self.ob.reader.decode(raw), steps)
            times.append(raw.log_time_ns)
            hits.append(hit)
            if hit:
                shown.append(value)
            if number % PROGRESS_EVERY == 0:
                self.progress(min(number / expected, 0.99), f"searched {number} messages of {self.topic}")
        tested = self.field or "(every text field)"
        return Found(np.asarray(times, dtype=np.int64), np.asarray(hits, dtype=bool), shown, "bag", tested)
