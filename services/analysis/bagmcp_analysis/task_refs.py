"""The analysis service's background work: one task on its own queue. Its job kinds are derived from the
tool declarations (tools/), each tool's params model beside its query (queries/)."""

from __future__ import annotations

from bagmcp_shared.tasks import TaskRef

QUEUE = "analysis"
RUN_JOB = TaskRef("bagmcp.analysis.run_job", QUEUE)
