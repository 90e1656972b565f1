"""Embedded mode: every service in one process over a local folder of bags, behind the gateway."""

from __future__ import annotations

from dataclasses import dataclass

from fastapi import FastAPI
from mcp.server import Server

from bagmcp_analysis.embedded import embedded_part as analysis_part
from bagmcp_bag_store.embedded import embedded_part as bag_store_part
from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_cli.token_actions import tokens_file
from bagmcp_gateway.access.tokens.models import token_hash
from bagmcp_gateway.app import create_app
from bagmcp_gateway.mcp_front.aggregator import build_gateway_server
from bagmcp_gateway.settings import GatewaySettings
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.job_tools import build_jobs_server
from bagmcp_kit.parts import ServicePart
from bagmcp_kit.runtime.resources import Embedded, embedded_resources
from bagmcp_lab.server.embedded import lab_in_process
from bagmcp_plotting.embedded import embedded_part as plotting_part
from bagmcp_shared.settings import HttpSettings


@dataclass(frozen=True)
class Composition:
    embedded: Embedded
    parts: list[ServicePart]
    upstreams: list[Upstream]


def compose(settings: EmbeddedSettings, *, public_url: str = "") -> Composition:
    """Catalog the folder (read-only), start ingest, and expose every service and the jobs tools in process.
    ``public_url`` is where callers reach this server (for artifact links)."""
    embedded = embedded_resources(
        settings.folder,
        settings.data_dir,
        job_budget_s=settings.job_budget_s,
        open_bags=settings.open_bags,
        input_budget=settings.input_budget,
    )
    parts = [
        bag_store_part(embedded, queries=settings.queries),
        analysis_part(embedded),
        plotting_part(embedded, artifact_base_url=public_url),
    ]
    jobs = Upstream(name="jobs", server=build_jobs_server(embedded.resources.job_store))
    return Composition(embedded, parts, [*(Upstream(name=p.name, server=p.server) for p in parts), jobs])


def create_embedded_app(
    settings: EmbeddedSettings, *, token: str | None, http: HttpSettings, public_url: str
) -> FastAPI:
    """The HTTP app of ``bagmcp serve``."""
    composition = compose(settings, public_url=public_url)
    # Tokens made with `bagmcp token create --data D` count, also those made while it runs, whenever the
    # server checks tokens: started with --token, or with a token file there already.
    made = tokens_file(settings.data_dir)
    gateway = GatewaySettings(
        token_hashes=[token_hash(token)] if token else [],
        http=http,
        public_url=public_url,
        tokens_file=made if token or made.exists() else None,
        rate_limit=settings.rate_limit,
    )
    lab = lab_in_process(settings.lab, port=http.port)
    app = create_app(
        gateway,
        upstreams=composition.upstreams,
        rest=[*(router for part in composition.parts for router in part.routers), lab.router],
        statuses=[*(row for part in composition.parts for row in part.statuses), *lab.statuses],
        on_shutdown=composition.embedded.runner.shutdown,
    )
    lab.attach(app)  # the Lab's agent loops call this app's /mcp in process, with each caller's token
    return app


def create_embedded_server(settings: EmbeddedSettings) -> Server[object]:
    """The MCP server of ``bagmcp stdio``."""
    return build_gateway_server(compose(settings).upstreams)
