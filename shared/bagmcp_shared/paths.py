"""Message paths: ``/topic.field.sub[index]`` with derived roll/pitch/yaw on quaternions.

A path is checked against the message type's definition before any message is read, so a
wrong path fails fast with the list of valid paths instead of producing an empty answer.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from rosbags.interfaces import Nodetype
from rosbags.typesys.store import Typestore

from bagmcp_shared.errors import MessagePathError

QUATERNION = "geometry_msgs/msg/Quaternion"
DERIVED = ("roll", "pitch", "yaw")
Step = str | int
_TOPIC = re.compile(r"^/?[A-Za-z0-9_~{}][A-Za-z0-9_/~{}-]*$")
_STEP = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[-?\d+\])*)")
_INDEX = re.compile(r"\[(-?\d+)\]")


@dataclass(frozen=True)
class MessagePath:
    """A parsed path: the topic and the steps (field names and indexes) inside its message."""

    topic: str
    steps: tuple[Step, ...]

    @property
    def field(self) -> str:
        return format_steps(self.steps)

    def __str__(self) -> str:
        return f"{self.topic}.{self.field}" if self.steps else self.topic


def format_steps(steps: tuple[Step, ...]) -> str:
    text = ""
    for step in steps:
        text += f"[{step}]" if isinstance(step, int) else (f".{step}" if text else step)
    return text


def parse_field_path(text: str) -> tuple[Step, ...]:
    """``pose.pose.position.x`` or ``ranges[3]`` -> steps; "" means the whole message."""
    steps: list[Step] = []
    rest = text.strip()
    for part in rest.split(".") if rest else []:
        match = _STEP.fullmatch(part)
        if match is None:
            raise MessagePathError(
                f"{text!r} is not a message path; use field names joined by '.' with optional "
                "[index], e.g. pose.pose.position.x or ranges[0]"
            )
        steps.append(match.group(1))
        steps.extend(int(i) for i in _INDEX.findall(match.group(2)))
    return tuple(steps)


def parse_message_path(text: str) -> MessagePath:
    """``/odom.pose.pose.position.x`` -> topic ``/odom`` and its field steps."""
    topic, _, fields = text.strip().partition(".")
    if not _TOPIC.match(topic):
        raise MessagePathError(
            f"{text!r} does not start with a topic name; write /topic.field.sub[index], e.g. /odom.twist.twist.linear.x"
        )
    return MessagePath(topic=topic, steps=parse_field_path(fields))


def _fields(store: Typestore, msgtype: str) -> list[tuple[str, tuple[object, ...]]]:
    return [(name, tuple(node)) for name, node in store.fielddefs[msgtype][1]]


def _type_name(node: tuple[object, ...]) -> str:
    kind, detail = node
    if kind == Nodetype.BASE:
        return str(detail[0]) if isinstance(detail, tuple) else str(detail)
    if kind == Nodetype.NAME:
        return str(detail)
    assert isinstance(detail, tuple)
    inner = tuple(detail[0]) if isinstance(detail[0], tuple) else ()
    size = detail[1] if kind == Nodetype.ARRAY else ""
    return f"{_type_name(inner)}[{size}]"


def field_paths(store: Typestore, msgtype: str, *, max_depth: int = 8) -> list[tuple[str, str]]:
    """Every leaf path of ``msgtype`` with its type, e.g. ``("pose.pose.position.x", "float64")``.

    Arrays of messages are shown with ``[0]`` as the example index; quaternions add roll,
    pitch and yaw (radians).
    """
    found: list[tuple[str, str]] = []

    def walk(typ: str, prefix: str, depth: int) -> None:
        if typ == QUATERNION:
            found.extend((f"{prefix}.{name}", "float64 (derived, rad)") for name in DERIVED)
        for name, node in _fields(store, typ):
            path = f"{prefix}.{name}" if prefix else name
            kind, detail = node
            if kind == Nodetype.NAME and depth < max_depth:
                walk(str(detail), path, depth + 1)
            elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE) and isinstance(detail, tuple):
                inner = tuple(detail[0])
                if inner[0] == Nodetype.NAME and depth < max_depth:
                    walk(str(inner[1]), f"{path}[0]", depth + 1)
                else:
                    found.append((path, _type_name(node)))
            else:
                found.append((path, _type_name(node)))

    walk(msgtype, "", 0)
    return found


def _path_error(store: Typestore, msgtype: str, steps: tuple[Step, ...], problem: str) -> MessagePathError:
    valid = [p for p, _ in field_paths(store, msgtype)]
    shown = ", ".join(valid[:40]) + (f" ... ({len(valid)} in all)" if len(valid) > 40 else "")
    return MessagePathError(f"{format_steps(steps)!r} on {msgtype}: {problem}; valid paths: {shown}")


def check_steps(store: Typestore, msgtype: str, steps: tuple[Step, ...]) -> str:
    """Validate ``steps`` against ``msgtype``; return the type at the end of the path."""
    node: tuple[object, ...] = (Nodetype.NAME, msgtype)
    for pos, step in enumerate(steps):
        kind, detail = node
        if isinstance(step, int):
            if kind not in (Nodetype.ARRAY, Nodetype.SEQUENCE) or not isinstance(detail, tuple):
                raise _path_error(store, msgtype, steps, f"{format_steps(steps[:pos])!r} is not an array")
            node = tuple(detail[0])
            continue
        if kind != Nodetype.NAME:
            raise _path_error(store, msgtype, steps, f"{format_steps(steps[:pos])!r} has no fields")
        if str(detail) == QUATERNION and step in DERIVED and pos == len(steps) - 1:
            return "float64"
        fields = dict(_fields(store, str(detail)))
        if step not in fields:
            raise _path_error(store, msgtype, steps, f"no field {step!r} in {detail}")
        node = fields[step]
    return _type_name(node)


def quaternion_angles(x: float, y: float, z: float, w: float) -> dict[str, float]:
    """Roll, pitch, yaw (radians, ZYX convention) of a unit quaternion."""
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return {"roll": roll, "pitch": pitch, "yaw": yaw}


def extract(message: object, steps: tuple[Step, ...]) -> object:
    """The value at ``steps`` in a decoded message (steps already checked against the type)."""
    value = message
    for pos, step in enumerate(steps):
        if isinstance(step, int):
            try:
                value = value[step]  # type: ignore[index]
            except IndexError as err:
                length = len(value)  # type: ignore[arg-type]
                raise MessagePathError(
                    f"index {step} is out of range at {format_steps(steps[: pos + 1])!r} "
                    f"(this message has {length} elements)"
                ) from err
        elif step in DERIVED and not hasattr(value, step):
            q = (float(getattr(value, axis)) for axis in "xyzw")
            value = quaternion_angles(*q)[step]
        else:
            value = getattr(value, step)
    return value
