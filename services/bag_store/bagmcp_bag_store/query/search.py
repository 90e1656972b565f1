"""search_messages: typed conditions over a topic, answered from the columnar index when it can."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from pydantic import JsonValue

from bagmcp_bag_store.query.conditions import (
    EXTREME_CONDITIONS,
    NUMERIC_CONDITIONS,
    BoundedRegex,
    check_value,
    parse_between,
    parse_near,
)
from bagmcp_bag_store.query.correlate import correlate
from bagmcp_bag_store.query.search_logs import log_details, with_level_numbers
from bagmcp_bag_store.query.search_params import SearchParams
from bagmcp_bag_store.results import ClosestApproach, SearchMatch, SearchResult
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.errors import ArgumentError, MessagePathError
from bagmcp_shared.index import ColumnIndex, read_series
from bagmcp_shared.jobs import Progress
from bagmcp_shared.jsonify import to_json
from bagmcp_shared.paths import check_steps, extract, parse_field_path

OBVIOUS_SCALAR = {
    "nav_msgs/msg/Odometry": "twist.twist.linear.x",
    "geometry_msgs/msg/Twist": "linear.x",
    "geometry_msgs/msg/TwistStamped": "twist.linear.x",
    "sensor_msgs/msg/LaserScan": "min_range",
    "sensor_msgs/msg/BatteryState": "percentage",
    "sensor_msgs/msg/Range": "range",
    "sensor_msgs/msg/Temperature": "temperature",
    "sensor_msgs/msg/NavSatFix": "altitude",
    "rosgraph_msgs/msg/Log": "level",
    "rcl_interfaces/msg/Log": "level",
}
POSITION_FIELD = {
    "nav_msgs/msg/Odometry": "pose.pose.position",
    "geometry_msgs/msg/PoseStamped": "pose.position",
    "geometry_msgs/msg/PoseWithCovarianceStamped": "pose.pose.position",
    "geometry_msgs/msg/Pose": "position",
    "geometry_msgs/msg/Point": "",
    "geometry_msgs/msg/PointStamped": "point",
}


@dataclass
class Found:
    """Indexes (into the window's messages) that matched, with times and values to show."""

    t_ns: npt.NDArray[np.int64]
    mask: npt.NDArray[np.bool_]
    values: list[JsonValue]
    source: str
    field: str
    distance: npt.NDArray[np.float64] | None = None
    xy: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None = None


def _scalar_field(ob: OpenBag, topic: str, field: str | None) -> str:
    msgtype = ob.reader.topic_connections(topic)[0].msgtype
    chosen = field or OBVIOUS_SCALAR.get(msgtype) or ("data" if msgtype.startswith("std_msgs/msg/") else None)
    if chosen is None:
        raise ArgumentError(f"{msgtype} has no obvious number to compare; pass `field`, e.g. from describe_topic")
    return chosen


def _numeric(ob: OpenBag, req: SearchParams, index: ColumnIndex | None, lo: int, hi: int) -> Found:
    field = _scalar_field(ob, req.topic, req.field)
    series = read_series(ob.reader, req.topic, [field], index=index, start_ns=lo, stop_ns=hi + 1)
    try:
        values = series.columns[field].astype(np.float64)
    except (TypeError, ValueError) as err:
        raise ArgumentError(f"{field} is not numeric; use contains, regex or equals with a string") from err
    if req.condition == "greater_than":
        mask = values > float(req.value)  # type: ignore[arg-type]
    elif req.condition == "less_than":
        mask = values < float(req.value)  # type: ignore[arg-type]
    elif req.condition == "between":
        low, high = parse_between(req.value)
        mask = (values >= low) & (values <= high)
    elif req.condition in EXTREME_CONDITIONS:
        finite = np.isfinite(values)
        extreme = (np.max if req.condition == "max" else np.min)(values[finite]) if finite.any() else np.nan
        mask = finite & (values == extreme)
    else:
        equal = np.isclose(values, float(req.value), rtol=0.0, atol=1e-9)  # type: ignore[arg-type]
        mask = equal if req.condition == "equals" else ~equal
    return Found(series.t_ns, mask, [float(v) for v in values[mask]], series.source, field)


def _near(ob: OpenBag, req: SearchParams, index: ColumnIndex | None, lo: int, hi: int) -> Found:
    target = parse_near(req.value)
    msgtype = ob.reader.topic_connections(req.topic)[0].msgtype
    base = req.field if req.field is not None else POSITION_FIELD.get(msgtype)
    if base is None:
        raise ArgumentError(f"{msgtype} has no obvious position; pass `field` naming a point, e.g. pose.position")
    columns = [f"{base}.x" if base else "x", f"{base}.y" if base else "y"]
    series = read_series(ob.reader, req.topic, columns, index=index, start_ns=lo, stop_ns=hi + 1)
    xs, ys = (series.columns[c].astype(np.float64) for c in columns)
    distance = np.hypot(xs - target.x, ys - target.y)
    mask = distance <= target.radius
    values: list[JsonValue] = [{"x": float(x), "y": float(y)} for x, y in zip(xs[mask], ys[mask], strict=True)]
    return Found(series.t_ns, mask, values, series.source, base or "(the message itself)", distance, (xs, ys))


def _texts(value: object) -> Iterator[str]:
    if isinstance(value, str):
        yield value
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _texts(item)
    elif hasattr(value, "__dataclass_fields__"):
        for name in value.__dataclass_fields__:
            if not name.startswith("__"):
                yield from _texts(getattr(value, name))


def _text_test(req: SearchParams) -> Callable[[str], bool]:
    wanted = str(req.value)
    if req.condition == "regex":
        return BoundedRegex(wanted).search
    if req.condition == "contains":
        return lambda text: wanted.casefold() in text.casefold()
    if req.condition == "equals":
        return lambda text: text == wanted
    return lambda text: text != wanted


def _present(value: object) -> bool:
    return not (isinstance(value, str | list | tuple | bytes | np.ndarray) and len(value) == 0)


def _decoded(ob: OpenBag, req: SearchParams, lo: int, hi: int, progress: Progress) -> Found:
    """Conditions that need each message decoded: text searches and field_exists."""
    steps = parse_field_path(req.field) if req.field else None
    msgtype = ob.reader.topic_connections(req.topic)[0].msgtype
    if steps is not None:
        check_steps(ob.reader.decoder.typestore(msgtype), msgtype, steps)
    elif req.condition == "field_exists":
        raise ArgumentError("field_exists needs `field`, the message path to look for")
    test = _text_test(req) if req.condition != "field_exists" else None
    expected = max(ob.topic(req.topic).count, 1)
    times, hits, shown = [], [], []
    for number, raw in enumerate(ob.reader.messages([req.topic], start_ns=lo, stop_ns=hi + 1)):
        message = ob.reader.decode(raw)
        try:
            picked = extract(message, steps) if steps is not None else None
        except MessagePathError:
            picked, exists = None, False
        else:
            exists = True
        if test is None:
            hit, shown_value = exists and _present(picked), to_json(picked, max_items=8, max_text=300)
        else:
            texts = [str(picked)] if steps is not None else list(_texts(message))
            found = next((t for t in texts if test(t)), None)
            hit, shown_value = found is not None, (found or "")[:300]
        times.append(raw.log_time_ns)
        hits.append(hit)
        if hit:
            shown.append(shown_value)
        if number % 500 == 0:
            progress(min(number / expected, 0.99), f"searched {number} messages of {req.topic}")
    tested = req.field or "(every text field)"
    return Found(np.asarray(times, dtype=np.int64), np.asarray(hits, dtype=bool), shown, "bag", tested)


def _closest(ob: OpenBag, found: Found) -> ClosestApproach | None:
    if found.distance is None or found.xy is None or not len(found.distance):
        return None
    best = int(np.argmin(found.distance))
    return ClosestApproach(
        distance_m=float(found.distance[best]),
        x=float(found.xy[0][best]),
        y=float(found.xy[1][best]),
        time=ob.instant(int(found.t_ns[best])),
    )


def _within(matches: list[SearchMatch], budget: int) -> list[SearchMatch]:
    """The leading matches whose JSON fits the byte budget (at least one)."""
    kept: list[SearchMatch] = []
    used = 0
    for match in matches:
        used += len(match.model_dump_json())
        if kept and used > budget:
            break
        kept.append(match)
    return kept


def _is_numeric(req: SearchParams) -> bool:
    return req.condition in NUMERIC_CONDITIONS or (
        req.condition in ("equals", "not_equals")
        and isinstance(req.value, int | float)
        and not isinstance(req.value, bool)
    )


def prepared(ob: OpenBag, req: SearchParams) -> SearchParams:
    """The request with the bag's spelling of the topic and log level names as numbers, checked."""
    req = with_level_numbers(ob, req.model_copy(update={"topic": ob.topic_name(req.topic)}))
    check_value(req.condition, req.value)
    return req


def search_messages(
    access: BagAccess, req: SearchParams, progress: Progress, *, budget_bytes: int, use_index: bool = True
) -> SearchResult:
    with access.open(req.bag) as ob:
        req = prepared(ob, req)
        topic = req.topic
        index = ob.index if use_index else None
        lo, hi = ob.window(req.start, req.end)
        if req.condition == "near_position":
            found = _near(ob, req, index, lo, hi)
        elif _is_numeric(req):
            found = _numeric(ob, req, index, lo, hi)
        else:
            found = _decoded(ob, req, lo, hi, progress)
        hit_times = found.t_ns[found.mask]
        shown = [int(t) for t in hit_times[: req.limit]]
        partners = (
            correlate(ob, index, req.correlate_topic, shown, tolerance_ns=int(req.correlate_tolerance_s * 1e9))
            if req.correlate_topic
            else [None] * len(shown)
        )
        distances = found.distance[found.mask] if found.distance is not None else None
        details = log_details(ob, topic, shown)
        matches = [
            SearchMatch(
                time=ob.instant(t),
                value=found.values[i],
                details=details[i],
                correlated=partners[i],
                distance_m=float(distances[i]) if distances is not None else None,
            )
            for i, t in enumerate(shown)
        ]
        matches = _within(matches, budget_bytes)
        progress(1.0, "done")
        return SearchResult(
            bag=ob.name,
            topic=topic,
            condition=req.condition,
            field=found.field,
            start=ob.instant(lo),
            end=ob.instant(hi),
            clock="log_time",
            scanned=len(found.t_ns),
            total=int(found.mask.sum()),
            returned=len(matches),
            truncated=len(hit_times) > len(matches),
            matches=matches,
            closest=_closest(ob, found),
            source="index" if found.source == "index" else "bag",
        )


def is_small(access: BagAccess, req: SearchParams) -> bool:
    """Whether the search answers quickly: from the index, or over few messages (checks the request too)."""
    with access.open(req.bag) as ob:
        req = prepared(ob, req)
        topic = req.topic
        columnar = req.condition == "near_position" or _is_numeric(req)
        return (columnar and ob.indexed(topic) and not req.correlate_topic) or ob.short(topic)
