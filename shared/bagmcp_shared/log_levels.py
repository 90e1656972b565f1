"""Severity levels of ROS log messages (rosgraph_msgs/Log and rcl_interfaces/msg/Log): names and parsing.

ROS 1 uses 1 DEBUG, 2 INFO, 4 WARN, 8 ERROR, 16 FATAL; ROS 2 uses 10, 20, 30, 40, 50. Raw values between
levels map to the nearest level at or below; values below DEBUG (such as 0, "unset") map to DEBUG and values
above FATAL to FATAL, so every record has one of the five names (the raw value is kept on the record).
"""

from __future__ import annotations

LEVEL_NAMES = ("DEBUG", "INFO", "WARN", "ERROR", "FATAL")
ROS1_LEVELS = (1, 2, 4, 8, 16)
ROS2_LEVELS = (10, 20, 30, 40, 50)
_ALIASES = {"WARNING": "WARN", "ERR": "ERROR", "CRITICAL": "FATAL", "CRIT": "FATAL", "INFORMATION": "INFO"}


def level_name(raw: int, *, ros2: bool) -> str:
    """Name of a raw level value: nearest level at or below; below DEBUG gives DEBUG."""
    values = ROS2_LEVELS if ros2 else ROS1_LEVELS
    name = LEVEL_NAMES[0]
    for value, candidate in zip(values, LEVEL_NAMES, strict=True):
        if raw >= value:
            name = candidate
    return name


def level_rank(name: str) -> int:
    """0 for DEBUG up to 4 for FATAL."""
    return LEVEL_NAMES.index(name)


def parse_level(value: str | int, *, ros2: bool) -> str:
    """A level name from a name (any case, aliases WARNING/ERR/CRITICAL) or an exact number of either scheme.

    The two numbering schemes share no values, so numbers of both are accepted whatever `ros2` says; `ros2`
    only decides which numbers the error message suggests.
    """
    if isinstance(value, bool):
        raise ValueError(_invalid(value, ros2=ros2))
    if isinstance(value, int):
        return _from_number(value, ros2=ros2)
    text = str(value).strip().upper()
    if text in LEVEL_NAMES:
        return text
    if text in _ALIASES:
        return _ALIASES[text]
    if text.lstrip("+-").isdigit():
        return _from_number(int(text), ros2=ros2)
    raise ValueError(_invalid(value, ros2=ros2))


def level_value(name: str, *, ros2: bool) -> int:
    """The raw number of a level name in one ROS version's scheme (WARN: 4 in ROS 1, 30 in ROS 2)."""
    return (ROS2_LEVELS if ros2 else ROS1_LEVELS)[level_rank(name)]


def _from_number(number: int, *, ros2: bool) -> str:
    for values in (ROS1_LEVELS, ROS2_LEVELS):
        if number in values:
            return LEVEL_NAMES[values.index(number)]
    raise ValueError(_invalid(number, ros2=ros2))


def _invalid(value: object, *, ros2: bool) -> str:
    numbers = ", ".join(str(v) for v in (ROS2_LEVELS if ros2 else ROS1_LEVELS))
    scheme = "ROS 2" if ros2 else "ROS 1"
    return f"Unknown log level {value!r}; use one of {', '.join(LEVEL_NAMES)} or the {scheme} numbers {numbers}."
