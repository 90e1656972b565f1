"""summarize_window: what happened in a window, as evidence: rates, silences and delays, warnings, motion,
obstacles."""

from __future__ import annotations

from collections import Counter

from pydantic import BaseModel

from bagmcp_analysis.logs.records import LogRecord, filter_records
from bagmcp_analysis.queries.activity import ORDER, activity_statement, topic_activity
from bagmcp_analysis.queries.lidar import LidarParams, lidar_window
from bagmcp_analysis.queries.logs import log_entry, log_topics, read_records
from bagmcp_analysis.queries.poses import read_poses
from bagmcp_analysis.reports.lidar import Closest
from bagmcp_analysis.reports.trajectory import StopOut
from bagmcp_analysis.reports.window import FlightMode, Motion, TopicActivity, WindowReport
from bagmcp_analysis.trajectory.track import summarize_track
from bagmcp_kit.arguments import BagRef, TimeArg
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.carry import carried
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.flight_modes import mode_changes, mode_topic, modes_in_window
from bagmcp_shared.jobs import Progress, spans
from bagmcp_shared.topics import choose_lidar_topic, choose_pose_topic
from bagmcp_shared.wording import counted

MAX_LOG_ENTRIES = 10
MAX_TOPICS = 25
MAX_STOPS = 10
MAX_TOPIC_STATEMENTS = 10


class WindowParams(BaseModel):
    """The arguments of summarize_window."""

    bag: BagRef
    start: TimeArg | None = None
    end: TimeArg | None = None


def _topics(ob: OpenBag, lo: int, hi: int, progress: Progress) -> list[TopicActivity]:
    recorded = [t for t in ob.summary.topics if t.count]
    activity = []
    for number, stats in enumerate(recorded):
        progress(number / len(recorded), f"timing {stats.name}")
        activity.append(topic_activity(ob, stats, lo, hi))
    return sorted(activity, key=lambda a: (ORDER[a.status], a.topic))


def _warnings(ob: OpenBag, lo: int, hi: int, progress: Progress) -> list[LogRecord]:
    try:
        records, _ = read_records(ob, log_topics(ob, None), progress)
    except BagmcpError:
        return []
    return filter_records(records, min_level="WARN", start_ns=lo, end_ns=hi)


def _motion(ob: OpenBag, lo: int, hi: int, progress: Progress) -> Motion | None:
    try:
        topic, msgtype, _ = choose_pose_topic(ob, None)
        poses = read_poses(ob, topic, msgtype, lo, hi, progress)
        summary = summarize_track(poses.track)
    except (BagmcpError, ValueError):
        return None

    def at(index: int) -> int:
        return int(poses.log_ns[index])

    stops = [
        StopOut(start=ob.instant(at(s.start_index)), end=ob.instant(at(s.end_index)), duration_s=s.duration_s)
        for s in summary.stops
    ]
    return carried(
        Motion, summary, topic=topic, distance_m=summary.distance_2d_m, stops=stops[:MAX_STOPS], stop_count=len(stops)
    )


def _obstacle(ob: OpenBag, lo: int, hi: int, progress: Progress) -> Closest | None:
    try:
        topic, _ = choose_lidar_topic(ob, None)
    except BagmcpError:
        return None
    params = LidarParams(bag=ob.record.id, topic=topic, start=(lo - ob.start_ns) / 1e9, end=(hi - ob.start_ns) / 1e9)
    return lidar_window(ob, topic, ob.msgtype(topic), params, progress).closest


def _flight_modes(ob: OpenBag, lo: int, hi: int) -> list[FlightMode]:
    topic = mode_topic(ob.reader)
    if topic is None:
        return []
    try:
        changes = modes_in_window(mode_changes(ob.reader, topic), lo, hi)
    except BagmcpError:
        return []
    return [FlightMode(mode=c.name, value=c.number, since=ob.instant(c.t_ns)) for c in changes]


def _modes_statement(modes: list[FlightMode]) -> str:
    steps = ", then ".join(f"{m.mode} from {m.since.offset_s:.1f} s" for m in modes)
    return f"flight modes: {steps}"


def _topic_statements(activity: list[TopicActivity]) -> list[str]:
    said = [s for a in activity if (s := activity_statement(a))]
    if len(said) <= MAX_TOPIC_STATEMENTS:
        return said
    return [*said[:MAX_TOPIC_STATEMENTS], f"and {len(said) - MAX_TOPIC_STATEMENTS} more topics that were not ok"]


def _log_statement(ob: OpenBag, bad: list[LogRecord]) -> str:
    first = bad[0]
    return (
        f"{counted(len(bad), 'log record')} at WARN or above; the first at {(first.t_ns - ob.start_ns) / 1e9:.3f} s "
        f"from {first.node}: {first.level} {first.text[:120]!r}"
    )


def _motion_statement(motion: Motion) -> str:
    stops = ", ".join(f"{s.start.offset_s:.1f}-{s.end.offset_s:.1f} s" for s in motion.stops)
    more = f" and {motion.stop_count - len(motion.stops)} more" if motion.stop_count > len(motion.stops) else ""
    return (
        f"the robot moved {motion.distance_m:.2f} m ({motion.moving_s:.2f} s moving, {motion.stopped_s:.2f} s "
        f"stopped; max {motion.max_speed_mps or 0:.3f} m/s); {counted(motion.stop_count, 'stop')}"
        + (f": {stops}{more}" if stops else "")
    )


def summarize_window(access: BagAccess, params: WindowParams, progress: Progress) -> WindowReport:
    with access.open(params.bag) as ob:
        lo, hi = ob.window(params.start, params.end)
        timing, logs, moving, scanning = spans(progress, 4)
        activity = _topics(ob, lo, hi, timing)
        statements = _topic_statements(activity)
        bad = _warnings(ob, lo, hi, logs)
        if bad:
            statements.append(_log_statement(ob, bad))
        motion = _motion(ob, lo, hi, moving)
        if motion is not None:
            statements.append(_motion_statement(motion))
        modes = _flight_modes(ob, lo, hi)
        if modes:
            statements.insert(0, _modes_statement(modes))
        closest = _obstacle(ob, lo, hi, scanning)
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
            topics=activity[:MAX_TOPICS],
            topics_total=len(activity),
            topics_by_status=dict(Counter(a.status for a in activity)),
            warnings={level: sum(1 for r in bad if r.level == level) for level in ("WARN", "ERROR", "FATAL")},
            log_entries=[log_entry(ob, r) for r in bad[:MAX_LOG_ENTRIES]],
            motion=motion,
            closest_obstacle=closest,
            flight_modes=modes,
        )


def window_is_small(access: BagAccess, params: WindowParams) -> bool:
    """Small when the messages to read without an index (the window, and whole topics for their delays) are few."""
    with access.open(params.bag) as ob:
        unindexed = sum(t.count for t in ob.summary.topics if not ob.indexed(t.name))
        return unindexed <= 20_000
