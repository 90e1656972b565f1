"""Flight-log records as ROS log rows, so analyze_logs, summarize_window and the index read them as they
read ``rosgraph_msgs/Log``: levels are given in ROS 1 numbers (1 DEBUG .. 16 FATAL).

- PX4 ``logged_messages``: the syslog level of each string (0-2 EMERGENCY..CRITICAL -> FATAL, 3 ERROR,
  4 WARNING -> WARN, 5-6 NOTICE/INFO -> INFO, 7 DEBUG); the node is the module PX4 names in brackets
  (``[commander] Takeoff detected`` -> ``commander``), else ``px4``.
- ArduPilot ``MSG``: DataFlash does not log a severity, so every text is INFO (node ``ardupilot``).
- ArduPilot ``ERR``: an error of a subsystem (``ECode`` 0 says it cleared, INFO; else ERROR), with the
  subsystem's name from ArduPilot's list (node ``ardupilot``).
"""

from __future__ import annotations

import re

from bagmcp_shared.flight_types import ERR_TYPE, LOGGED_TYPE, MSG_TYPE

_SYSLOG_TO_ROS1 = (16, 16, 16, 8, 4, 2, 2, 1)
INFO, ERROR = 2, 8
_MODULE = re.compile(r"^\[([A-Za-z0-9_ ]+)\]\s*")
# ArduPilot's LogErrorSubsystem numbers (AP_Logger's LogStructure.h); ECode 0 is "resolved" for all
SUBSYSTEMS = {
    1: "main",
    2: "radio",
    3: "compass",
    4: "optical flow",
    5: "radio failsafe",
    6: "battery failsafe",
    7: "GPS failsafe",
    8: "GCS failsafe",
    9: "fence failsafe",
    10: "flight mode",
    11: "GPS",
    12: "crash check",
    13: "flip",
    14: "autotune",
    15: "parachutes",
    16: "EKF check",
    17: "EKF failsafe",
    18: "barometer",
    19: "CPU",
    20: "ADSB failsafe",
    21: "terrain",
    22: "navigation",
    23: "terrain failsafe",
    24: "EKF primary",
    25: "thrust loss check",
    26: "sensor failsafe",
    27: "leak failsafe",
    28: "pilot input",
    29: "vibration failsafe",
    30: "internal error",
    31: "dead-reckoning failsafe",
}


Record = tuple[int, str, str]  # ROS 1 level, node, text


def _logged(message: object) -> Record:
    raw = getattr(message, "log_level", 6)
    level = _SYSLOG_TO_ROS1[raw] if isinstance(raw, int) and 0 <= raw < len(_SYSLOG_TO_ROS1) else INFO
    text = str(getattr(message, "message", "")).strip()
    module = _MODULE.match(text)
    return level, module.group(1) if module else "px4", text


def _err(message: object) -> Record:
    subsystem, code = int(getattr(message, "Subsys", 0)), int(getattr(message, "ECode", 0))
    name = SUBSYSTEMS.get(subsystem, f"subsystem {subsystem}")
    text = f"{name} error cleared (Subsys {subsystem})" if code == 0 else f"{name} error {code} (Subsys {subsystem})"
    return INFO if code == 0 else ERROR, "ardupilot", text


def flight_record(message: object) -> Record | None:
    """Level (ROS 1 number), node and text of a flight-log record; None when ``message`` is not one."""
    msgtype = getattr(message, "__msgtype__", "")
    if msgtype == LOGGED_TYPE:
        return _logged(message)
    if msgtype == MSG_TYPE:
        return INFO, "ardupilot", str(getattr(message, "Message", ""))
    if msgtype == ERR_TYPE:
        return _err(message)
    return None
