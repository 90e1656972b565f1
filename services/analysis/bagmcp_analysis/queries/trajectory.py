"""analyze_trajectory: the summary of a pose topic's path over a window."""

from __future__ import annotations

import math

from pydantic import BaseModel

from bagmcp_analysis.queries.poses import Poses, read_poses
from bagmcp_analysis.reports.trajectory import Pose, StopOut, TrajectoryReport, Waypoint
from bagmcp_analysis.trajectory.track import summarize_track
from bagmcp_kit.arguments import BagRef, OptionalTopic, TimeArg
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.carry import carried
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.jobs import Progress
from bagmcp_shared.timebase import Instant
from bagmcp_shared.topics import choose_pose_topic, is_fix


class TrajectoryParams(BaseModel):
    """The arguments of analyze_trajectory."""

    bag: BagRef
    topic: OptionalTopic = None
    start: TimeArg | None = None
    end: TimeArg | None = None


def _number(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _pose(ob: OpenBag, poses: Poses, index: int) -> Pose:
    track = poses.track
    yaw = _number(float(track.yaw[index]))
    return Pose(
        x=float(track.x[index]),
        y=float(track.y[index]),
        z=_number(float(track.z[index])),
        yaw_deg=round(math.degrees(yaw), 6) if yaw is not None else None,
        time=ob.instant(int(poses.log_ns[index])),
    )


def _frame(ob: OpenBag, topic: str, msgtype: str, lo: int) -> str | None:
    if is_fix(msgtype):
        return "local east/north of the first fix"
    if msgtype.startswith("px4/"):
        return "PX4 local frame (x north, y east, z down, metres from the estimator's origin)"
    first = next(ob.reader.messages([topic], start_ns=lo), None)
    header = getattr(ob.reader.decode(first), "header", None) if first is not None else None
    frame = getattr(header, "frame_id", None)
    return str(frame) if frame else None


def analyze_trajectory(access: BagAccess, params: TrajectoryParams, progress: Progress) -> TrajectoryReport:
    with access.open(params.bag) as ob:
        topic, msgtype, alternatives = choose_pose_topic(ob, params.topic)
        lo, hi = ob.window(params.start, params.end)
        poses = read_poses(ob, topic, msgtype, lo, hi, progress)
        try:
            summary = summarize_track(poses.track)
        except ValueError as err:
            raise ArgumentError(f"{topic}: {err}") from err

        def at(index: int) -> Instant:
            return ob.instant(int(poses.log_ns[index]))

        return carried(
            TrajectoryReport,
            summary,
            bag=ob.name,
            topic=topic,
            type=msgtype,
            frame=_frame(ob, topic, msgtype, lo),
            alternatives=alternatives,
            clock="header" if poses.clock == "header" else "log_time",
            start=ob.instant(lo),
            end=ob.instant(hi),
            max_speed_at=at(summary.max_speed_index) if summary.max_speed_index is not None else None,
            stops=[
                StopOut(start=at(s.start_index), end=at(s.end_index), duration_s=s.duration_s) for s in summary.stops
            ],
            start_pose=_pose(ob, poses, summary.start_index),
            end_pose=_pose(ob, poses, summary.end_index),
            waypoints=[carried(Waypoint, _pose(ob, poses, w.index), reason=w.reason) for w in summary.waypoints],
            notes=[*poses.notes, *summary.notes],
        )


def trajectory_is_small(access: BagAccess, params: TrajectoryParams) -> bool:
    """Small when the index holds the poses, or the topic is short enough to decode at once."""
    with access.open(params.bag) as ob:
        topic, _, _ = choose_pose_topic(ob, params.topic)
        return ob.indexed(topic) or ob.short(topic)
