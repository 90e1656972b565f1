"""filter_bag: write a subset of a stored bag as a new bag and add it to the store."""

from __future__ import annotations

import hashlib
import json
import tempfile
from collections.abc import Callable
from pathlib import Path

from pydantic import JsonValue

from bagmcp_bag_store.content import content_id
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import ArgumentError, ReadOnlyError
from bagmcp_bag_store.ingest import ingest_bag
from bagmcp_bag_store.jobs import ProgressReporter
from bagmcp_bag_store.opened import opened
from bagmcp_bag_store.results import FilterResult
from bagmcp_bag_store.upload import register_bag, sanitize_name
from bagmcp_shared.bags import BagReader
from bagmcp_shared.bags.writer import FilterSpec, OutputFormat, default_output, write_filtered


def _strings(value: JsonValue, what: str) -> tuple[str, ...]:
    if value is None:
        return ()
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ArgumentError(f"{what} takes a list of topic names")
    return tuple(str(v) for v in value)


def _rates(value: JsonValue) -> tuple[tuple[str, float], ...]:
    if value is None:
        return ()
    if not isinstance(value, dict):
        raise ArgumentError("rates takes {topic: max Hz}, e.g. {'/scan': 2}")
    pairs = []
    for topic, rate in value.items():
        if isinstance(rate, bool) or not isinstance(rate, int | float) or rate <= 0:
            raise ArgumentError(f"rate for {topic} must be a positive number of Hz, got {rate!r}")
        pairs.append((topic, float(rate)))
    return tuple(sorted(pairs))


def _format(value: JsonValue, reader: BagReader) -> OutputFormat:
    if value is None:
        return default_output(reader.format, reader.connections)
    try:
        return OutputFormat(str(value))
    except ValueError as err:
        choices = ", ".join(f.value for f in OutputFormat)
        raise ArgumentError(f"format {value!r} is not one of {choices}") from err


def _default_name(source: str, params: dict[str, JsonValue]) -> str:
    digest = hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()[:8]
    return f"{source}-filtered-{digest}"


def filter_bag(
    deps: BagStoreDeps, params: dict[str, JsonValue], report: ProgressReporter | Callable[[float, str], None]
) -> FilterResult:
    if deps.store is None:
        raise ReadOnlyError("this server has no writable store; filter_bag cannot store new bags")
    with opened(deps, str(params["bag"])) as ob, tempfile.TemporaryDirectory(prefix="bagmcp-filter-") as tmp:
        include = _strings(params.get("include_topics"), "include_topics") or None
        start, end = params.get("start"), params.get("end")
        spec = FilterSpec(
            include_topics=include,
            exclude_topics=_strings(params.get("exclude_topics"), "exclude_topics"),
            start_ns=ob.time(start, what="start") if isinstance(start, int | float | str) else None,
            end_ns=ob.time(end, what="end") if isinstance(end, int | float | str) else None,
            rates_hz=_rates(params.get("rates")),
        )
        fmt = _format(params.get("format"), ob.reader)
        name = sanitize_name(str(params.get("name") or _default_name(ob.record.name, params)))
        cancelled = getattr(report, "cancelled", None)
        written = write_filtered(
            ob.reader,
            Path(tmp),
            name,
            fmt=fmt,
            spec=spec,
            progress=lambda f, m: report(0.9 * f, m),
            cancelled=cancelled,
        )
        path = written.path
        members = [path] if path.is_file() else sorted(p for p in path.iterdir() if p.is_file())
        sha = content_id(members, directory=path.is_dir())
        record, created = register_bag(
            deps, path, [m.name for m in members], sha, name=name, tags=[f"filtered-from:{ob.record.id}"]
        )
    if created or record.status != "ready":
        report(0.95, "indexing the new bag")
        ingest_bag(deps, record.id)
    return FilterResult(
        bag_id=record.id,
        name=record.name,
        format=fmt.value,
        counts=written.counts,
        message_count=sum(written.counts.values()),
        created=created,
    )
