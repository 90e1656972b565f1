"""The bag-store's background work: its two tasks. Its job kinds are derived from the tool declarations
(tools/), each tool's params model beside its work."""

from __future__ import annotations

from bagmcp_shared.tasks import TaskRef

QUEUE = "bag_store"
INGEST = TaskRef("bagmcp.bag_store.ingest", QUEUE)
RUN_JOB = TaskRef("bagmcp.bag_store.run_job", QUEUE)
