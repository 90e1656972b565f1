"""search_messages on log topics: level names as values (either ROS version) and matches that show the
level name, node and text."""

from __future__ import annotations

from pydantic import JsonValue

from bagmcp_bag_store.queries.search_params import SearchParams
from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import LOG_TYPES, LogRow, decode_logs
from bagmcp_shared.log_levels import level_name, level_value, parse_level

ROS2_LOG = "rcl_interfaces/msg/Log"
_LEVEL_CONDITIONS = ("equals", "not_equals", "greater_than", "less_than", "between")


def _level(value: JsonValue, *, ros2: bool) -> JsonValue:
    if not isinstance(value, str):
        return value
    try:
        return level_value(parse_level(value, ros2=ros2), ros2=ros2)
    except ValueError as err:
        raise ArgumentError(str(err)) from err


def with_level_numbers(ob: OpenBag, req: SearchParams) -> SearchParams:
    """On a log topic's level, names (WARN, error) become that ROS version's numbers (4 or 30)."""
    msgtype = ob.msgtype(req.topic)
    if msgtype not in LOG_TYPES or req.field not in (None, "level") or req.condition not in _LEVEL_CONDITIONS:
        return req
    ros2 = msgtype == ROS2_LOG
    if isinstance(req.value, list):
        value: JsonValue = [_level(v, ros2=ros2) for v in req.value]
    elif isinstance(req.value, str) and req.condition in ("equals", "not_equals"):
        try:
            value = level_value(parse_level(req.value, ros2=ros2), ros2=ros2)
        except ValueError:
            return req  # a text compare on another field's words, not a level
    else:
        value = _level(req.value, ros2=ros2)
    return req.model_copy(update={"value": value, "field": "level"})


def log_details(ob: OpenBag, topic: str, times_ns: list[int]) -> list[dict[str, JsonValue] | None]:
    """Level name, node and text of the log records at ``times_ns`` (None for non-log topics)."""
    msgtype = ob.msgtype(topic)
    if msgtype not in LOG_TYPES or not times_ns:
        return [None] * len(times_ns)
    ros2 = msgtype == ROS2_LOG
    rows: list[LogRow] | None = ob.index.logs(topic) if ob.index is not None else None
    if rows is None:
        wanted = set(times_ns)
        rows = [r for r in decode_logs(ob.reader, topic) if r.t_ns in wanted]
    by_time = {r.t_ns: r for r in rows}
    details: list[dict[str, JsonValue] | None] = []
    for t in times_ns:
        row = by_time.get(t)
        details.append(
            {"level": level_name(row.level, ros2=ros2), "node": row.node, "text": row.text[:300]} if row else None
        )
    return details
