"""The plotting service inside one process (``bagmcp serve`` / ``stdio``): plots on a thread pool,
artifacts in the data directory."""

from __future__ import annotations

from bagmcp_kit.parts import ServicePart
from bagmcp_kit.runtime.resources import Embedded
from bagmcp_plotting.task_refs import RUN_JOB
from bagmcp_plotting.wiring import build_plotting
from bagmcp_shared.jobs import run_job


def embedded_part(embedded: Embedded, *, artifact_base_url: str = "") -> ServicePart:
    res = embedded.resources
    server, router, registry = build_plotting(res, artifact_base_url=artifact_base_url)
    embedded.runner.bind(RUN_JOB, lambda job_id: run_job(registry, res.job_store, job_id), workers=2)
    return ServicePart("plotting", server, (router,))
