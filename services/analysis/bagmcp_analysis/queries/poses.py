"""A pose topic's poses as a Track in metres (index first), on header stamps when they are sane."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.trajectory.track import Track, pick_clock, track_of_fixes
from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.gps_metres import read_local_fixes
from bagmcp_shared.index import read_series
from bagmcp_shared.jobs import Progress
from bagmcp_shared.timebase import MAX_CLOCK_SKEW_NS
from bagmcp_shared.topics import is_fix, pose_source

MAX_RATE_RATIO = 20.0  # header time may run slower or faster than log time (a simulation), but not by more


@dataclass(frozen=True)
class Poses:
    """The track (on ``clock``) and the log time of each of its poses (what answers report)."""

    track: Track
    log_ns: npt.NDArray[np.int64]
    clock: str
    notes: list[str]


def pose_clock(
    log_ns: npt.NDArray[np.int64], header_ns: npt.NDArray[np.int64]
) -> tuple[npt.NDArray[np.int64], str, str | None]:
    """Header stamps whenever they are consistent within the topic, whatever their offset from log time.

    A simulation's clock is far from log time but measures the robot's motion exactly, while log time carries
    the recorder's stalls and bursts; answers still report log time, so only speeds and durations use it."""
    stamps, clock, note = pick_clock(log_ns, header_ns)
    if clock != "header" or len(stamps) < 2:
        return stamps, clock, note
    log_span, header_span = int(log_ns.max() - log_ns.min()), int(stamps[-1] - stamps[0])
    if header_span <= 0 or (log_span > 0 and not 1 / MAX_RATE_RATIO <= header_span / log_span <= MAX_RATE_RATIO):
        return log_ns, "log_time", "header stamps do not advance with log time, so log time was used"
    if float(np.median(np.abs(stamps - log_ns))) > MAX_CLOCK_SKEW_NS:
        note = (
            f"speeds use the header stamps, which run on another clock than log time (a simulation's: they start "
            f"at {stamps[0] * 1e-9:.3f} s); times are given in log time"
        )
    return stamps, clock, note


def read_poses(ob: OpenBag, topic: str, msgtype: str, lo: int, hi: int, progress: Progress) -> Poses:
    """The topic's poses in [lo, hi] as a Track in metres, on header stamps when they are sane."""
    source = pose_source(ob, msgtype)
    notes: list[str] = []
    if is_fix(msgtype):
        fixes = read_local_fixes(ob, topic, lo, hi, progress)
        log_ns = fixes.log_ns
        stamps, clock, note = pose_clock(log_ns, fixes.header_ns)
        track = track_of_fixes(stamps, fixes.metres, log_time=clock == "log_time")
        notes.append("GPS fixes as metres east (x) and north (y) of the first valid fix; no heading")
    else:
        columns = [source.axis(axis) for axis in "xyz"] + ([source.yaw_column] if source.yaw_column else [])
        series = read_series(ob.reader, topic, columns, index=ob.index, start_ns=lo, stop_ns=hi + 1, progress=progress)
        x, y, z, *rest = (series.columns[c].astype(np.float64) for c in columns)
        yaw = rest[0] if rest else np.full(len(x), np.nan)
        log_ns = series.t_ns
        stamps, clock, note = pose_clock(log_ns, series.header_ns)
        track = Track(t_ns=stamps, x=x, y=y, z=z, yaw=yaw, log_time=clock == "log_time")
    if note:
        notes.append(note)
    if len(track.t_ns) < 2:
        raise ArgumentError(f"{topic} has {len(track.t_ns)} pose(s) in this window; a trajectory needs two or more")
    return Poses(track, log_ns, clock, notes)
