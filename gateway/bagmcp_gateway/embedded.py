"""Embedded mode: the gateway with the bag-store inside one process, over a local folder of bags."""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from fastapi import FastAPI
from mcp.server import Server

from bagmcp_bag_store.api import build_router, install_error_handler
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.tools import build_mcp
from bagmcp_bag_store.wiring import ThreadRunner, folder_deps
from bagmcp_gateway.aggregator import build_gateway_server
from bagmcp_gateway.app import GatewayConfig, create_app
from bagmcp_gateway.auth import token_hash
from bagmcp_gateway.upstreams import Upstream


@dataclass(frozen=True)
class Embedded:
    deps: BagStoreDeps
    upstreams: list[Upstream]
    runner: ThreadRunner


def embed(bags_dir: Path, data_dir: Path | None = None) -> Embedded:
    """Catalog ``bags_dir`` (read-only), start ingest, and expose the bag-store in-process.

    ``data_dir`` (default ``$BAGMCP_DATA_DIR`` or ``~/.cache/bagmcp``) holds indexes and the bags
    filter_bag writes. ``BAGMCP_JOB_BUDGET_S`` sets how long long-running tools wait before
    answering with a job.
    """
    budget = float(os.environ.get("BAGMCP_JOB_BUDGET_S", "20"))
    deps, runner = folder_deps(bags_dir, data_dir=data_dir, job_budget_s=budget)
    return Embedded(deps, [Upstream(name="bag-store", server=build_mcp(deps))], runner)


def create_embedded_app(
    bags_dir: Path, *, data_dir: Path | None, token: str | None, public_url: str, allowed_hosts: tuple[str, ...]
) -> FastAPI:
    """The HTTP app of ``bagmcp serve``."""
    embedded = embed(bags_dir, data_dir)
    config = GatewayConfig(
        upstreams=embedded.upstreams,
        token_hashes=[token_hash(token)] if token else [],
        public_url=public_url,
        allowed_hosts=allowed_hosts,
    )
    rest = build_router(embedded.deps, upload_dir=Path(tempfile.gettempdir()), max_upload_bytes=0)
    app = create_app(config, rest=rest, on_shutdown=embedded.runner.shutdown)
    install_error_handler(app)
    return app


def create_embedded_server(bags_dir: Path, data_dir: Path | None) -> Server[object]:
    """The MCP server of ``bagmcp stdio``."""
    return build_gateway_server(embed(bags_dir, data_dir).upstreams)
