"""The Celery worker entry point: ``celery -A bagmcp_plotting.worker:app worker`` (takes only the
plotting queue). Settings come from BAGMCP_*; resources are built on the first task."""

from __future__ import annotations

from bagmcp_kit.runtime.worker import job_worker
from bagmcp_plotting.artifacts import Artifacts
from bagmcp_plotting.settings import PlottingSettings
from bagmcp_plotting.task_refs import RUN_JOB
from bagmcp_plotting.wiring import build_registry

_base_url = PlottingSettings.from_env().artifact_base_url
app, _resources = job_worker(RUN_JOB, lambda res: build_registry(res.access, Artifacts(res.store, base_url=_base_url)))
