"""The plotting service's background work: one task on its own queue. Its job kinds are derived from the
tool declarations (tools/plot_tools.py), each plot's params model beside it in plots.py."""

from __future__ import annotations

from bagmcp_shared.tasks import TaskRef

QUEUE = "plotting"
RUN_JOB = TaskRef("bagmcp.plotting.run_job", QUEUE)
