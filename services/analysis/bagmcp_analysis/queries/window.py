"""summarize_window: what happened in a window, as evidence: rates and silences, warnings, motion, obstacles."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.job_kinds import LidarParams, WindowParams
from bagmcp_analysis.logs.records import filter_records
from bagmcp_analysis.queries.lidar import lidar_window
from bagmcp_analysis.queries.logs import log_entry, log_topics, read_records
from bagmcp_analysis.queries.poses import read_poses
from bagmcp_analysis.reports.lidar import Closest
from bagmcp_analysis.reports.window import Motion, TopicActivity, WindowReport
from bagmcp_analysis.trajectory.track import summarize_track
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.catalog import TopicStats
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.jobs import Progress
from bagmcp_shared.topics import choose_lidar_topic, choose_pose_topic

MAX_LOG_ENTRIES = 10
_ORDER = {"silent": 0, "gap": 1, "slow": 2, "absent": 3, "ok": 4}


def _times(ob: OpenBag, topic: str, lo: int, hi: int) -> npt.NDArray[np.int64]:
    if ob.indexed(topic) and ob.index is not None:
        return ob.index.read(topic, [], start_ns=lo, stop_ns=hi + 1).t_ns
    stamps = [raw.log_time_ns for raw in ob.reader.messages([topic], start_ns=lo, stop_ns=hi + 1)]
    return np.asarray(stamps, dtype=np.int64)


def _activity(ob: OpenBag, stats: TopicStats, lo: int, hi: int) -> TopicActivity:
    times = _times(ob, stats.name, lo, hi)
    span_s = max((hi - lo) / 1e9, 1e-9)
    rate = len(times) / span_s if len(times) else 0.0
    recorded = stats.first_ns is not None and stats.last_ns is not None and stats.first_ns <= hi and stats.last_ns >= lo
    edges = np.concatenate(([max(lo, stats.first_ns or lo)], times, [min(hi, stats.last_ns or hi)]))
    silences = np.diff(edges)
    longest = int(silences.argmax()) if len(silences) else 0
    silence_s = float(silences[longest]) / 1e9 if len(silences) else None
    period = 1 / stats.rate_hz if stats.rate_hz else None
    if not recorded:
        status = "absent"
    elif not len(times) and period is not None:
        status = "silent"
    elif period is not None and silence_s is not None and silence_s > 3 * period and silence_s > 0.1:
        status = "gap"
    elif stats.rate_hz and span_s > 2 * (period or 0) and rate < 0.5 * stats.rate_hz:
        status = "slow"
    else:
        status = "ok"
    flagged = status in ("silent", "gap")
    return TopicActivity(
        topic=stats.name,
        count=len(times),
        rate_hz=round(rate, 4) if len(times) > 1 else None,
        bag_rate_hz=stats.rate_hz,
        longest_silence_s=round(silence_s, 6) if silence_s is not None else None,
        silent_from=ob.instant(int(edges[longest])) if flagged and len(silences) else None,
        status=status,  # type: ignore[arg-type]
    )


def _statement(activity: TopicActivity) -> str | None:
    if activity.status == "silent":
        return f"{activity.topic} was silent for the whole window (normally {activity.bag_rate_hz:.3g} Hz)"
    if activity.status == "gap" and activity.silent_from is not None:
        return (
            f"{activity.topic} went silent for {activity.longest_silence_s:.3f} s from "
            f"{activity.silent_from.offset_s:.3f} s (normally {activity.bag_rate_hz:.3g} Hz)"
        )
    if activity.status == "slow":
        return (
            f"{activity.topic} ran at {activity.rate_hz or 0:.3g} Hz against {activity.bag_rate_hz:.3g} Hz over the bag"
        )
    return None


def _motion(ob: OpenBag, lo: int, hi: int, progress: Progress) -> Motion | None:
    try:
        topic, msgtype, _ = choose_pose_topic(ob, None)
        summary = summarize_track(read_poses(ob, topic, msgtype, lo, hi, progress).track)
    except (BagmcpError, ValueError):
        return None
    return Motion(
        topic=topic,
        distance_m=summary.distance_2d_m,
        mean_speed_mps=summary.mean_speed_mps,
        max_speed_mps=summary.max_speed_mps,
        moving_s=summary.moving_s,
        stopped_s=summary.stopped_s,
        stops=len(summary.stops),
    )


def _obstacle(ob: OpenBag, lo: int, hi: int, progress: Progress) -> Closest | None:
    try:
        topic, _ = choose_lidar_topic(ob, None)
    except BagmcpError:
        return None
    params = LidarParams(bag=ob.record.id, topic=topic, start=(lo - ob.start_ns) / 1e9, end=(hi - ob.start_ns) / 1e9)
    return lidar_window(ob, topic, ob.msgtype(topic), params, progress).closest


def summarize_window(access: BagAccess, params: WindowParams, progress: Progress) -> WindowReport:
    with access.open(params.bag) as ob:
        lo, hi = ob.window(params.start, params.end)
        activity = [_activity(ob, t, lo, hi) for t in ob.summary.topics if t.count]
        activity.sort(key=lambda a: (_ORDER[a.status], a.topic))
        progress(0.3, "topics done")
        statements = [s for a in activity if (s := _statement(a))]
        entries, warnings = [], {}
        try:
            records, _ = read_records(ob, log_topics(ob, None), progress)
            bad = filter_records(records, min_level="WARN", start_ns=lo, end_ns=hi)
            warnings = {level: sum(1 for r in bad if r.level == level) for level in ("WARN", "ERROR", "FATAL")}
            entries = [log_entry(ob, r) for r in bad[:MAX_LOG_ENTRIES]]
            if bad:
                first = bad[0]
                statements.append(
                    f"{len(bad)} log records at WARN or above; the first at {(first.t_ns - ob.start_ns) / 1e9:.3f} s "
                    f"from {first.node}: {first.level} {first.text[:120]!r}"
                )
        except BagmcpError:
            pass
        progress(0.6, "logs done")
        motion = _motion(ob, lo, hi, progress)
        if motion is not None:
            statements.append(
                f"the robot moved {motion.distance_m:.2f} m ({motion.moving_s:.2f} s moving, "
                f"{motion.stopped_s:.2f} s stopped, {motion.stops} stops; max {motion.max_speed_mps or 0:.3f} m/s)"
            )
        closest = _obstacle(ob, lo, hi, progress)
        if closest is not None:
            statements.append(
                f"closest obstacle {closest.range_m:.3f} m at bearing {closest.bearing_deg or 0:.1f} deg "
                f"at {closest.time.offset_s:.3f} s"
            )
        return WindowReport(
            bag=ob.name,
            start=ob.instant(lo),
            end=ob.instant(hi),
            statements=statements,
            topics=activity,
            warnings=warnings,
            log_entries=entries,
            motion=motion,
            closest_obstacle=closest,
        )


def window_is_small(access: BagAccess, params: WindowParams) -> bool:
    """Small when the messages to read without an index (estimated from rates) are few."""
    with access.open(params.bag) as ob:
        lo, hi = ob.window(params.start, params.end)
        span_s = (hi - lo) / 1e9
        unindexed = sum((t.rate_hz or 0) * span_s for t in ob.summary.topics if not ob.indexed(t.name))
        return unindexed <= 20_000
