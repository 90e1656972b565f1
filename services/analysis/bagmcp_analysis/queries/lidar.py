"""analyze_lidar_scan: one LaserScan or PointCloud2 at full resolution, or per-scan minima over a window."""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
import numpy.typing as npt
from pydantic import BaseModel, ConfigDict, Field

from bagmcp_analysis.lidar.pointcloud import CloudField, CloudStats, cloud_stats
from bagmcp_analysis.lidar.scan import ScanStats, first_within, minimum_profile, scan_stats
from bagmcp_analysis.reports.lidar import Closest, FirstWithin, LidarReport, MinimumProfile
from bagmcp_kit.arguments import BagRef, OptionalTopic, TimeArg
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.bags.counted import counted
from bagmcp_shared.carry import carried
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import read_series
from bagmcp_shared.jobs import Progress
from bagmcp_shared.laser_ranges import laser_ranges
from bagmcp_shared.timebase import Instant
from bagmcp_shared.topics import CLOUD, SCAN, choose_lidar_topic


class LidarParams(BaseModel):
    """The arguments of analyze_lidar_scan (``within`` is ``within_m`` in the job and the report)."""

    model_config = ConfigDict(validate_by_name=True, validate_by_alias=True)

    bag: BagRef
    topic: OptionalTopic = None
    time: Annotated[TimeArg | None, Field(description="one scan, nearest this time")] = None
    start: TimeArg | None = None
    end: TimeArg | None = None
    within_m: Annotated[
        float | None, Field(gt=0, alias="within", description="m: when something first came this close")
    ] = None


def _cloud(message: object) -> CloudStats:
    fields = [CloudField(f.name, int(f.offset), int(f.datatype), int(f.count)) for f in getattr(message, "fields")]  # noqa: B009
    data = getattr(message, "data")  # noqa: B009
    return cloud_stats(
        fields=fields,
        data=bytes(data) if not isinstance(data, np.ndarray) else data.tobytes(),
        point_step=int(getattr(message, "point_step")),  # noqa: B009
        row_step=int(getattr(message, "row_step")),  # noqa: B009
        width=int(getattr(message, "width")),  # noqa: B009
        height=int(getattr(message, "height")),  # noqa: B009
        is_bigendian=bool(getattr(message, "is_bigendian")),  # noqa: B009
    )


def _frame(message: object) -> str | None:
    frame = getattr(getattr(message, "header", None), "frame_id", None)
    return str(frame) if frame else None


def _one(ob: OpenBag, topic: str, msgtype: str, params: LidarParams) -> LidarReport:
    assert params.time is not None
    wanted = ob.time(params.time)
    raw = ob.nearest(topic, wanted)
    message = ob.reader.decode(raw)
    try:
        scan = scan_stats(laser_ranges(message)) if msgtype == SCAN else None
        cloud = _cloud(message) if msgtype == CLOUD else None
    except ValueError as err:
        raise ArgumentError(f"{topic} at {raw.log_time_ns}: {err}") from err
    closest = _closest_of_one(scan, cloud, ob.instant(raw.log_time_ns))
    near = closest is not None and params.within_m is not None and closest.range_m < params.within_m
    return LidarReport(
        bag=ob.name,
        topic=topic,
        type=msgtype,
        frame=_frame(message),
        mode="scan",
        time=ob.instant(raw.log_time_ns),
        delta_s=(raw.log_time_ns - wanted) / 1e9,
        scan=scan,
        cloud=cloud,
        start=None,
        end=None,
        scans=None,
        closest=closest,
        within_m=params.within_m,
        first_within=carried(FirstWithin, closest, stays_s=0.0, until_end=False, total_within_s=0.0, episodes=1)
        if near and closest is not None
        else None,
        minimum=None,
        source="bag",
    )


def _closest_of_one(scan: ScanStats | None, cloud: CloudStats | None, when: Instant) -> Closest | None:
    hit = scan.closest if scan is not None else cloud.closest if cloud is not None else None
    if hit is None:
        return None
    return Closest(range_m=hit.range_m, bearing_deg=hit.bearing_deg, time=when)


def _minima(
    ob: OpenBag, topic: str, msgtype: str, lo: int, hi: int, progress: Progress
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], npt.NDArray[np.float64], str]:
    """Per-scan minimum range and its bearing (rad) over [lo, hi]: from the index for LaserScan."""
    if msgtype == SCAN:
        columns = ["min_range", "min_bearing"]
        series = read_series(ob.reader, topic, columns, index=ob.index, start_ns=lo, stop_ns=hi + 1, progress=progress)
        ranges, bearings = (series.columns[c].astype(np.float64) for c in columns)
        return series.t_ns, ranges, bearings, series.source
    times, ranges_out, bearings_out = [], [], []
    clouds = ob.reader.messages([topic], start_ns=lo, stop_ns=hi + 1)
    for raw in counted(clouds, expected=ob.topic(topic).count, progress=progress, what=topic, every=20):
        stats = _cloud(ob.reader.decode(raw))
        hit = stats.closest
        times.append(raw.log_time_ns)
        ranges_out.append(float(hit.range_m) if hit else math.nan)
        bearings_out.append(math.radians(hit.bearing_deg) if hit else math.nan)
    return (
        np.asarray(times, dtype=np.int64),
        np.asarray(ranges_out, dtype=np.float64),
        np.asarray(bearings_out, dtype=np.float64),
        "bag",
    )


def lidar_window(ob: OpenBag, topic: str, msgtype: str, params: LidarParams, progress: Progress) -> LidarReport:
    lo, hi = ob.window(params.start, params.end)
    times, ranges, bearings, source = _minima(ob, topic, msgtype, lo, hi, progress)
    closest = None
    if np.isfinite(ranges).any():
        best = int(np.nanargmin(ranges))
        bearing = float(bearings[best])
        closest = Closest(
            range_m=float(ranges[best]),
            bearing_deg=round(math.degrees(bearing), 6) if math.isfinite(bearing) else None,
            time=ob.instant(int(times[best])),
        )
    approach = first_within(times, ranges, bearings, distance_m=params.within_m) if params.within_m else None
    profile_t, profile_r = minimum_profile(times, ranges) if len(times) else ([], [])
    return LidarReport(
        bag=ob.name,
        topic=topic,
        type=msgtype,
        frame=None,
        mode="window",
        time=None,
        delta_s=None,
        scan=None,
        cloud=None,
        start=ob.instant(lo),
        end=ob.instant(hi),
        scans=len(times),
        closest=closest,
        within_m=params.within_m,
        first_within=carried(FirstWithin, approach, time=ob.instant(approach.t_ns)) if approach is not None else None,
        minimum=MinimumProfile(offset_s=[round((t - ob.start_ns) / 1e9, 6) for t in profile_t], range_m=profile_r),
        source="index" if source == "index" else "bag",
    )


def analyze_lidar(access: BagAccess, params: LidarParams, progress: Progress) -> LidarReport:
    with access.open(params.bag) as ob:
        topic, msgtype = choose_lidar_topic(ob, params.topic)
        if params.time is not None:
            return _one(ob, topic, msgtype, params)
        return lidar_window(ob, topic, msgtype, params, progress)


def lidar_is_small(access: BagAccess, params: LidarParams) -> bool:
    with access.open(params.bag) as ob:
        topic, msgtype = choose_lidar_topic(ob, params.topic)
        return params.time is not None or (msgtype == SCAN and ob.indexed(topic)) or ob.short(topic)
