"""Flight modes of a flight log as a timeline: which mode was in effect when.

- PX4 ULog: ``vehicle_status.nav_state``, named as PX4's vehicle_status message defines its values
  (a change is kept when the value differs from the one before).
- ArduPilot DataFlash: every ``MODE`` record is a change; names are pymavlink's for the vehicle type,
  stored on the MODE topic when the log was opened.

The mode in effect at a window's start is the last change before it. Reading costs one pass over
vehicle_status (a few hundred messages) or MODE (a handful).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

from bagmcp_shared.bags import BagReader
from bagmcp_shared.bags.models import MODE_NAMES

# PX4 vehicle_status NAVIGATION_STATE_* (msg/VehicleStatus.msg); 6-9, 11 and 16 are retired names
PX4_NAV_STATES = {
    0: "MANUAL",
    1: "ALTCTL",
    2: "POSCTL",
    3: "AUTO_MISSION",
    4: "AUTO_LOITER",
    5: "AUTO_RTL",
    6: "AUTO_RCRECOVER",
    7: "AUTO_RTGS",
    8: "AUTO_LANDENGFAIL",
    9: "AUTO_LANDGPSFAIL",
    10: "ACRO",
    11: "UNUSED",
    12: "DESCEND",
    13: "TERMINATION",
    14: "OFFBOARD",
    15: "STAB",
    16: "RATTITUDE",
    17: "AUTO_TAKEOFF",
    18: "AUTO_LAND",
    19: "AUTO_FOLLOW_TARGET",
    20: "AUTO_PRECLAND",
    21: "ORBIT",
    22: "AUTO_VTOL_TAKEOFF",
}
PX4_STATUS = "px4/vehicle_status"
ARDUPILOT_MODE = "ardupilot/MODE"


@dataclass(frozen=True)
class ModeChange:
    """A mode taking effect at ``t_ns`` (log time); ``number`` is the log's own value."""

    t_ns: int
    name: str
    number: int


def mode_topic(reader: BagReader) -> str | None:
    """The topic that records flight modes, if the bag is a flight log with one."""
    found = [c for c in reader.connections if c.msgtype in (PX4_STATUS, ARDUPILOT_MODE) and c.count]
    return found[0].topic if found else None


def _ardupilot_names(reader: BagReader, topic: str) -> dict[int, str]:
    meta = dict(reader.topic_connections(topic)[0].metadata)
    return {int(k): str(v) for k, v in json.loads(meta.get(MODE_NAMES, "{}")).items()}


def mode_changes(reader: BagReader, topic: str) -> list[ModeChange]:
    """Every mode change recorded on ``topic`` (vehicle_status or MODE), in time order."""
    changes: list[ModeChange] = []
    px4 = reader.topic_connections(topic)[0].msgtype == PX4_STATUS
    names = PX4_NAV_STATES if px4 else _ardupilot_names(reader, topic)
    for raw in reader.messages([topic]):
        message = reader.decode(raw)
        value = getattr(message, "nav_state" if px4 else "ModeNum", getattr(message, "Mode", None))
        if not isinstance(value, int) or (changes and px4 and changes[-1].number == value):
            continue
        changes.append(ModeChange(raw.log_time_ns, names.get(value, f"mode {value}"), value))
    return changes


def modes_in_window(changes: list[ModeChange], start_ns: int, end_ns: int) -> list[ModeChange]:
    """The mode in effect at ``start_ns`` (if any was set before) and the changes up to ``end_ns``."""
    before = [c for c in changes if c.t_ns < start_ns]
    inside = [c for c in changes if start_ns <= c.t_ns <= end_ns]
    return before[-1:] + inside
