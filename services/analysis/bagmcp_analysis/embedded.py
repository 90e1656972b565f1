"""The analysis service inside one process (``bagmcp serve`` / ``stdio``): long scans on a thread pool."""

from __future__ import annotations

from bagmcp_analysis.task_refs import RUN_JOB
from bagmcp_analysis.wiring import build_analysis
from bagmcp_kit.parts import ServicePart
from bagmcp_kit.runtime.resources import Embedded
from bagmcp_shared.jobs import run_job


def embedded_part(embedded: Embedded) -> ServicePart:
    res = embedded.resources
    server, registry = build_analysis(res)
    embedded.runner.bind(RUN_JOB, lambda job_id: run_job(registry, res.job_store, job_id), workers=2)
    return ServicePart("analysis", server)
