"""Trajectory summary of a robot's poses: clock choice, GPS fixes to local metres, and summarize_track.

summarize_track reports distances, speeds (robust to batched or repeated stamps), moving/stopped time,
stops, extents and waypoints (start, corners, stops, end). Types live in trajectory_types.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.trajectory.motion import Motion, analyse_motion
from bagmcp_analysis.trajectory.types import Clock, Extents, Stop, Track, TrackSummary, Waypoint
from bagmcp_analysis.trajectory.waypoints import select_waypoints
from bagmcp_shared.gps_metres import EARTH_RADIUS_M, LocalMetres, local_metres
from bagmcp_shared.laser_ranges import MOVING_MPS

__all__ = [
    "EARTH_RADIUS_M",
    "Clock",
    "Extents",
    "Stop",
    "Track",
    "TrackSummary",
    "Waypoint",
    "pick_clock",
    "summarize_track",
    "track_from_fixes",
    "track_of_fixes",
]


def pick_clock(
    log_ns: npt.NDArray[np.int64], header_ns: npt.NDArray[np.int64] | None
) -> tuple[npt.NDArray[np.int64], Clock, str | None]:
    """Header stamps when all are > 0 and never go backwards, else log time with a one-sentence note why."""
    log = np.asarray(log_ns, dtype=np.int64)
    if header_ns is None:
        return log, "log_time", "The messages have no header stamps, so log time was used."
    header = np.asarray(header_ns, dtype=np.int64)
    if header.shape != log.shape:
        raise ValueError(f"Got {header.size} header stamps for {log.size} log times; pass one of each per message.")
    unset = int((header <= 0).sum())
    if unset:
        return log, "log_time", f"{unset} of {header.size} header stamps are zero or negative, so log time was used."
    backwards = int((np.diff(header) < 0).sum())
    if backwards:
        return log, "log_time", f"Header stamps go backwards {backwards} times, so log time was used."
    return header, "header", None


def track_from_fixes(
    t_ns: npt.NDArray[np.int64],
    latitude_deg: npt.NDArray[np.float64],
    longitude_deg: npt.NDArray[np.float64],
    altitude_m: npt.NDArray[np.float64],
    status: npt.NDArray[np.int64],
) -> Track:
    """NavSatFix to metres east (x), north (y), up (z) around the first valid fix; yaw unknown (NaN).

    Fixes with status < 0 or non-finite latitude/longitude are dropped; z is NaN where the altitude is not
    finite (see bagmcp_shared.gps_metres)."""
    stamps = np.asarray(t_ns, dtype=np.int64)
    metres = local_metres(latitude_deg, longitude_deg, altitude_m, np.asarray(status, dtype=np.float64))
    if stamps.shape != metres.kept.shape:
        raise ValueError("Fix stamps, latitude, longitude, altitude and status must have one value per message.")
    return track_of_fixes(stamps[metres.kept], metres)


def track_of_fixes(stamps_ns: npt.NDArray[np.int64], metres: LocalMetres, *, log_time: bool = False) -> Track:
    """The track of valid fixes already in local metres, on ``stamps_ns`` (one per valid fix)."""
    return Track(
        t_ns=stamps_ns,
        x=metres.east_m,
        y=metres.north_m,
        z=metres.up_m,
        yaw=np.full(stamps_ns.shape, np.nan),
        log_time=log_time,
    )


def summarize_track(
    track: Track, *, stop_speed_mps: float = MOVING_MPS, turn_rate_rps: float = 0.1, max_waypoints: int = 12
) -> TrackSummary:
    """Distances, speeds, moving/stopped time, stops, extents and waypoints of a track (see module doc)."""
    _check_inputs(track, stop_speed_mps, turn_rate_rps, max_waypoints)
    x, y, z = track.x, track.y, track.z
    count = x.size
    distance_2d = float(np.hypot(np.diff(x), np.diff(y)).sum())
    displacement_2d = math.hypot(float(x[-1] - x[0]), float(y[-1] - y[0]))
    z_known = bool(np.isfinite(z).all())
    distance_3d = float(np.sqrt(np.diff(x) ** 2 + np.diff(y) ** 2 + np.diff(z) ** 2).sum()) if z_known else None
    displacement_3d = math.hypot(displacement_2d, float(z[-1] - z[0])) if z_known else None
    motion = analyse_motion(track, stop_speed_mps=stop_speed_mps, turn_rate_rps=turn_rate_rps)
    duration_s = motion.duration_s
    moving_s = float(motion.elapsed_s[motion.moving].sum())
    max_speed, max_index = _max_speed(motion)
    return TrackSummary(
        samples=count,
        duration_s=duration_s,
        distance_2d_m=distance_2d,
        distance_3d_m=distance_3d,
        displacement_2d_m=displacement_2d,
        displacement_3d_m=displacement_3d,
        path_efficiency=displacement_2d / distance_2d if distance_2d > 0 else None,
        mean_speed_mps=distance_2d / duration_s if duration_s > 0 else None,
        mean_moving_speed_mps=distance_2d / moving_s if moving_s > 0 else None,
        max_speed_mps=max_speed,
        max_speed_index=max_index,
        moving_s=moving_s,
        stopped_s=max(0.0, duration_s - moving_s),
        stops=motion.stops,
        extents=_extents(x, y, z),
        start_index=0,
        end_index=count - 1,
        waypoints=select_waypoints(x, y, motion.stationary, motion.stops, max_waypoints=max_waypoints),
        notes=_notes(track, motion, z_known),
    )


def _check_inputs(track: Track, stop_speed_mps: float, turn_rate_rps: float, max_waypoints: int) -> None:
    if track.t_ns.size == 0:
        raise ValueError("The track has no poses; pick a topic or time range that contains pose messages.")
    if not (np.isfinite(track.x).all() and np.isfinite(track.y).all()):
        raise ValueError("Track x and y must be finite; drop poses with unknown position before summarising.")
    if not (stop_speed_mps >= 0 and turn_rate_rps >= 0):
        raise ValueError("stop_speed_mps and turn_rate_rps must be zero or positive.")
    if max_waypoints < 2:
        raise ValueError("max_waypoints must be at least 2 (start and end).")


def _max_speed(motion: Motion) -> tuple[float | None, int | None]:
    if motion.speed_mps.size == 0:
        return None, None
    window = int(np.argmax(motion.speed_mps))
    middle = (int(motion.starts[window]) + int(motion.span_ends[window])) // 2
    return float(motion.speed_mps[window]), middle


def _extents(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64], z: npt.NDArray[np.float64]) -> Extents:
    known_z = z[np.isfinite(z)]
    return Extents(
        min_x=float(x.min()),
        max_x=float(x.max()),
        min_y=float(y.min()),
        max_y=float(y.max()),
        min_z=float(known_z.min()) if known_z.size else None,
        max_z=float(known_z.max()) if known_z.size else None,
    )


def _notes(track: Track, motion: Motion, z_known: bool) -> list[str]:
    steps = track.t_ns.size - 1
    notes = []
    if steps == 0:
        notes.append("The track has a single pose, so no motion can be measured.")
    elif motion.window_s is None:
        notes.append("All poses share one timestamp, so speeds and moving time are unknown.")
    if motion.repeated_stamps or motion.backwards_stamps:
        window = f", so speeds use windows of at least {motion.window_s:.3g} s" if motion.window_s else ""
        notes.append(
            f"{motion.repeated_stamps} of {steps} time steps repeat the previous stamp (within 1 % of the speed "
            f"window) and {motion.backwards_stamps} go backwards{window}."
        )
    if motion.bursts:
        notes.append(
            f"Log times bunch up after stalls in {motion.bursts} speed windows, so those speeds count time as "
            "messages x the median period."
        )
    if steps and not np.isfinite(track.yaw).any():
        notes.append("Heading is unknown, so rotation in place and stop-turn corners cannot be detected.")
    if not z_known:
        notes.append("Altitude is unknown for some poses, so 3D distance and displacement are omitted.")
    return notes
