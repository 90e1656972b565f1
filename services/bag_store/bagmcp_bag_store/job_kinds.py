"""The bag-store's background work: its two tasks and its kinds of job, with typed parameters."""

from __future__ import annotations

from pydantic import BaseModel, Field, JsonValue

from bagmcp_bag_store.fleet.answers import QueryAnswer
from bagmcp_bag_store.fleet.find import FindAnswer
from bagmcp_bag_store.fleet.find_params import FindParams, QueryParams
from bagmcp_bag_store.query.conditions import Condition
from bagmcp_bag_store.results import FilterResult, SearchResult
from bagmcp_shared.jobs import JobKind
from bagmcp_shared.tasks import TaskRef

QUEUE = "bag_store"
INGEST = TaskRef("bagmcp.bag_store.ingest", QUEUE)
RUN_JOB = TaskRef("bagmcp.bag_store.run_job", QUEUE)


class SearchParams(BaseModel):
    bag: str
    topic: str
    condition: Condition
    value: JsonValue = None
    field: str | None = None
    start: float | str | None = None
    end: float | str | None = None
    limit: int = Field(default=20, ge=1, le=200)
    correlate_topic: str | None = None
    correlate_tolerance_s: float = Field(default=0.1, gt=0, le=60)


class FilterParams(BaseModel):
    bag: str
    name: str | None = None
    include_topics: list[str] | None = None
    exclude_topics: list[str] | None = None
    start: float | str | None = None
    end: float | str | None = None
    rates: dict[str, float] | None = None
    format: str | None = None


SEARCH = JobKind("bag_store.search", SearchParams, SearchResult, RUN_JOB)
FILTER = JobKind("bag_store.filter", FilterParams, FilterResult, RUN_JOB)

QUERY = JobKind("bag_store.query", QueryParams, QueryAnswer, RUN_JOB)
FIND = JobKind("bag_store.find", FindParams, FindAnswer, RUN_JOB)
