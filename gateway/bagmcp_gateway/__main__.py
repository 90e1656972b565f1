"""``python -m bagmcp_gateway``: the team gateway (settings from BAGMCP_* variables)."""

from __future__ import annotations

import logging

from bagmcp_gateway.app import create_app
from bagmcp_gateway.rest_front.proxy import build_proxy
from bagmcp_gateway.settings import GatewaySettings
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.job_tools import build_jobs_server
from bagmcp_kit.service_app import serve
from bagmcp_shared.jobs import RedisJobStore
from bagmcp_shared.redis_connection import redis_client


def main() -> None:
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    settings = GatewaySettings.from_env()
    upstreams = list(settings.upstreams)
    if settings.redis_url is not None:  # the jobs of every service, followed here with get_job / cancel_job
        jobs = build_jobs_server(RedisJobStore(redis_client(settings.redis_url)))
        upstreams.append(Upstream(name="jobs", server=jobs))
    proxy = build_proxy(settings.rest_routes, settings.service_token, caller_segments=settings.caller_routes)
    app = create_app(settings, upstreams=upstreams, rest=[proxy])
    serve(app, settings.http)


if __name__ == "__main__":
    main()
