"""The Celery worker entry point: ``celery -A bagmcp_analysis.worker:app worker`` (takes only the
analysis queue). Settings come from BAGMCP_*; resources are built on the first task."""

from __future__ import annotations

from bagmcp_analysis.task_refs import RUN_JOB
from bagmcp_analysis.wiring import build_registry
from bagmcp_kit.runtime.worker import job_worker

app, _resources = job_worker(RUN_JOB, lambda res: build_registry(res.access))
