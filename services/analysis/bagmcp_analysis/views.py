"""What analyze_trajectory and analyze_lidar_scan look like to an MCP Apps viewer and the web console: the
path with its stops, and scans across the window (kit/web/view_data.py). The poses are read again (an
indexed pose topic in milliseconds); a window's scans are at most ``MAX_SCANS`` decoded messages."""

from __future__ import annotations

from typing import Any

import numpy as np

from bagmcp_analysis.queries.lidar import LidarParams
from bagmcp_analysis.queries.poses import read_poses
from bagmcp_analysis.queries.trajectory import TrajectoryParams
from bagmcp_kit.web.view_data import View, numbers, scan_entry, thin_indices
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.jobs import Unreported
from bagmcp_shared.topics import SCAN

PATH_POINTS = 4000
MAX_SCANS = 60


class AnalysisViews:
    def __init__(self, access: BagAccess) -> None:
        self._access = access

    def trajectory(self, params: TrajectoryParams, result: dict[str, Any]) -> View:
        with self._access.open(params.bag) as ob:
            topic = str(result["topic"])
            lo, hi = ob.window(params.start, params.end)
            poses = read_poses(ob, topic, ob.msgtype(topic), lo, hi, Unreported())
        x, y = poses.track.x, poses.track.y
        t_s = (poses.log_ns - ob.start_ns).astype(np.float64) / 1e9
        keep = thin_indices(x.size, max_points=PATH_POINTS)
        stops = []
        for stop in result.get("stops", []):
            at = int(np.clip(np.searchsorted(t_s, stop["start"]["offset_s"]), 0, x.size - 1))
            stops.append({"x": float(x[at]), "y": float(y[at]), "start_s": t_s[at], "end_s": stop["end"]["offset_s"]})
        return {
            "kind": "trajectory",
            "title": f"{topic} ({result.get('distance_2d_m', 0):.2f} m, {len(stops)} stops)",
            "x": numbers(x[keep]),
            "y": numbers(y[keep]),
            "t": numbers(t_s[keep]),
            "x_label": "x [m]",
            "y_label": "y [m]",
            "equal_aspect": True,
            "stops": stops,
        }

    def lidar(self, params: LidarParams, result: dict[str, Any]) -> View | None:
        """The scan shown (mode scan), or up to MAX_SCANS scans evenly spread over the window plus the one
        where something first came within the distance; None for point clouds."""
        with self._access.open(params.bag) as ob:
            topic = str(result["topic"])
            if ob.msgtype(topic) != SCAN:
                return None
            if params.time is not None:
                targets = [ob.time(params.time)]
            else:
                lo, hi = ob.window(params.start, params.end)
                targets = np.linspace(lo, hi, MAX_SCANS).astype(np.int64).tolist()
                first = result.get("first_within")
                if first is not None:
                    targets.append(ob.start_ns + int(first["time"]["offset_s"] * 1e9))
            scans = _scans_near(ob, topic, sorted(targets))
        return {
            "kind": "scan",
            "title": f"{topic}: {len(scans)} scan{'s' if len(scans) != 1 else ''}",
            "range_max_m": max((s["range_max"] for s in scans), default=None),
            "within_m": params.within_m,
            "scans": scans,
        }


def _scans_near(ob: OpenBag, topic: str, targets: list[int]) -> list[View]:
    seen: set[int] = set()
    scans = []
    for target in targets:
        raw = ob.nearest(topic, target)
        if raw.log_time_ns in seen:
            continue
        seen.add(raw.log_time_ns)
        scans.append(scan_entry(ob.reader.decode(raw), offset_s=(raw.log_time_ns - ob.start_ns) / 1e9))
    return scans
