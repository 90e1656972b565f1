"""The bag-store's background work: its two tasks, and the job kinds of the fleet's questions (query_bags,
find_bags, still adapted by hand in tools/fleet_tools.py). The job kinds of search_messages and filter_bag are
derived from their declarations (tools/search_tools.py)."""

from __future__ import annotations

from bagmcp_bag_store.fleet.answers import QueryAnswer
from bagmcp_bag_store.fleet.find import FindAnswer
from bagmcp_bag_store.fleet.find_params import FindParams, QueryParams
from bagmcp_shared.jobs import JobKind
from bagmcp_shared.tasks import TaskRef

QUEUE = "bag_store"
INGEST = TaskRef("bagmcp.bag_store.ingest", QUEUE)
RUN_JOB = TaskRef("bagmcp.bag_store.run_job", QUEUE)

QUERY = JobKind("bag_store.query", QueryParams, QueryAnswer, RUN_JOB)
FIND = JobKind("bag_store.find", FindParams, FindAnswer, RUN_JOB)
