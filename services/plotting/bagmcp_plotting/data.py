"""The numbers a plot needs, read from a bag: message paths as time series (index first, else decoded)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import read_series
from bagmcp_shared.jobs import Progress, spans
from bagmcp_shared.paths import check_steps, field_paths, format_steps, parse_message_path
from bagmcp_shared.units import unit_of

_NUMERIC = ("float", "int", "uint", "bool", "byte", "char")


@dataclass(frozen=True)
class PathSeries:
    """``name`` is ``/topic.field``; ``t_s`` seconds from the bag start (log time)."""

    name: str
    topic: str
    field: str
    unit: str | None
    t_ns: npt.NDArray[np.int64]
    values: npt.NDArray[np.float64]

    def t_s(self, start_ns: int) -> npt.NDArray[np.float64]:
        return (self.t_ns - start_ns).astype(np.float64) / 1e9


def _numeric_fields(ob: OpenBag, msgtype: str) -> str:
    store = ob.reader.decoder.typestore(msgtype)
    paths = [p for p, t in field_paths(store, msgtype) if t.startswith(_NUMERIC)]
    return ", ".join(paths[:30]) + (f" ... ({len(paths)} in all)" if len(paths) > 30 else "")


def read_path(ob: OpenBag, text: str, lo: int, hi: int, progress: Progress) -> PathSeries:
    """A numeric message path over [lo, hi]; wrong or non-numeric paths list the valid numeric ones."""
    (series,) = read_paths(ob, [text], lo, hi, progress)
    return series


def read_paths(ob: OpenBag, texts: Sequence[str], lo: int, hi: int, progress: Progress) -> list[PathSeries]:
    """Numeric message paths over [lo, hi], in the order given; each topic is read once, its fields
    together (one decoding pass where the index lacks them)."""
    wanted = [_numeric_field(ob, text) for text in texts]
    by_topic: dict[str, list[str]] = {}
    for topic, field in wanted:
        fields = by_topic.setdefault(topic, [])
        if field not in fields:
            fields.append(field)
    found: dict[tuple[str, str], PathSeries] = {}
    for (topic, fields), step in zip(by_topic.items(), spans(progress, len(by_topic)), strict=True):
        found.update({(topic, s.field): s for s in read_fields(ob, topic, fields, lo, hi, step)})
    return [found[key] for key in wanted]


def _numeric_field(ob: OpenBag, text: str) -> tuple[str, str]:
    """The topic and field a numeric message path names; wrong or non-numeric paths list the valid ones."""
    parsed = parse_message_path(text)
    topic = ob.topic_name(parsed.topic)
    msgtype = ob.msgtype(topic)
    if not parsed.steps:
        raise ArgumentError(f"{text!r} names a topic, not a field; plot one of: {_numeric_fields(ob, msgtype)}")
    leaf = check_steps(ob.reader.decoder.typestore(msgtype), msgtype, parsed.steps)
    field = format_steps(parsed.steps)
    if not leaf.startswith(_NUMERIC):
        raise ArgumentError(f"{topic}.{field} is {leaf}, not a number; plot one of: {_numeric_fields(ob, msgtype)}")
    return topic, field


def read_fields(ob: OpenBag, topic: str, fields: list[str], lo: int, hi: int, progress: Progress) -> list[PathSeries]:
    """Numeric fields of one topic over [lo, hi], read together (the index first, else one decoding pass)."""
    series = read_series(ob.reader, topic, fields, index=ob.index, start_ns=lo, stop_ns=hi + 1, progress=progress)
    if not len(series.t_ns):
        raise ArgumentError(
            f"{topic} has no messages between {(lo - ob.start_ns) / 1e9:.3f} s and {(hi - ob.start_ns) / 1e9:.3f} s"
        )
    stated = ob.reader.decoder.units(ob.msgtype(topic))  # DataFlash logs state units (FMTU)
    return [
        PathSeries(
            name=f"{topic}.{field}",
            topic=topic,
            field=field,
            unit=stated.get(field) or unit_of(field),
            t_ns=series.t_ns,
            values=series.columns[field].astype(np.float64),
        )
        for field in fields
    ]


def path_is_indexed(ob: OpenBag, text: str) -> bool:
    parsed = parse_message_path(text)
    topic = ob.topic_name(parsed.topic)
    return ob.index is not None and ob.index.has(topic, [format_steps(parsed.steps)])
