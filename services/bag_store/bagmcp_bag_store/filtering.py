"""filter_bag: write a subset of a stored bag as a new bag and add it to the store."""

from __future__ import annotations

import hashlib
import json
import tempfile
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, Field

from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_bag_store.ingest.upload import sanitize_name
from bagmcp_bag_store.reports import FilterResult
from bagmcp_kit.arguments import BagRef, TimeArg
from bagmcp_shared.access import BagAccess
from bagmcp_shared.bags import BagReader
from bagmcp_shared.bags.writer import FilterSpec, OutputFormat, default_output, write_filtered
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.jobs import Progress

Format = Literal["ros1", "ros2-sqlite3", "ros2-mcap", "mcap-json"]  # OutputFormat's values, inline in the schema


class FilterParams(BaseModel):
    """The arguments of filter_bag, in the order the tool lists them."""

    bag: BagRef
    name: Annotated[str | None, Field(description="name of the new bag")] = None
    include_topics: Annotated[list[str] | None, Field(description="keep only these")] = None
    exclude_topics: Annotated[list[str] | None, Field(description="drop these")] = None
    start: TimeArg | None = None
    end: TimeArg | None = None
    rates: Annotated[dict[str, float] | None, Field(description="max Hz per topic, e.g. {'/scan': 2}")] = None
    format: Annotated[Format | None, Field(description="default: the source's")] = None


def _rates(value: dict[str, float] | None) -> tuple[tuple[str, float], ...]:
    for topic, rate in (value or {}).items():
        if rate <= 0:
            raise ArgumentError(f"rate for {topic} must be a positive number of Hz, got {rate!r}")
    return tuple(sorted((value or {}).items()))


def _format(value: str | None, reader: BagReader) -> OutputFormat:
    if value is None:
        return default_output(reader.format, reader.connections)
    try:
        return OutputFormat(value)
    except ValueError as err:
        choices = ", ".join(f.value for f in OutputFormat)
        raise ArgumentError(f"format {value!r} is not one of {choices}") from err


def _default_name(source: str, params: FilterParams) -> str:
    request = params.model_dump(mode="json", exclude={"name"})
    digest = hashlib.sha256(json.dumps(request, sort_keys=True).encode()).hexdigest()[:8]
    return f"{source}-filtered-{digest}"


def _name_note(asked: str | None, existing: str) -> str | None:
    """Said when the same filtered content existed already under another name than the one asked for."""
    if asked is None or sanitize_name(asked) == existing:
        return None
    return (
        f"the same bag existed already as {existing!r}, so the name {asked!r} was not used; refer to it as {existing!r}"
    )


def filter_bag(
    access: BagAccess, shelf: Shelf, ingestor: Ingestor, params: FilterParams, progress: Progress
) -> FilterResult:
    with access.open(params.bag) as ob, tempfile.TemporaryDirectory(prefix="bagmcp-filter-") as tmp:
        spec = FilterSpec(
            include_topics=tuple(params.include_topics) if params.include_topics else None,
            exclude_topics=tuple(params.exclude_topics or ()),
            start_ns=ob.time(params.start, what="start") if params.start is not None else None,
            end_ns=ob.time(params.end, what="end") if params.end is not None else None,
            rates_hz=_rates(params.rates),
        )
        fmt = _format(params.format, ob.reader)
        name = sanitize_name(params.name or _default_name(ob.name, params))
        written = write_filtered(
            ob.reader,
            Path(tmp),
            name,
            fmt=fmt,
            spec=spec,
            progress=lambda f, m: progress(0.9 * f, m),
            cancelled=progress.cancelled,
        )
        path = written.path
        members = [path] if path.is_file() else sorted(p for p in path.iterdir() if p.is_file())
        sha = content_id(members, directory=path.is_dir())
        record, created = shelf.register(
            path, [m.name for m in members], sha, name=name, tags=[f"filtered-from:{ob.record.id}"]
        )
    if created or record.status != "ready":
        progress(0.95, "indexing the new bag")
        ingestor.ingest(record.id)
    return FilterResult(
        note=_name_note(params.name, record.name),
        bag_id=record.id,
        name=record.name,
        format=fmt.value,
        counts=written.counts,
        message_count=sum(written.counts.values()),
        created=created,
    )
