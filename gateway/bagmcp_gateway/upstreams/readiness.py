"""What each of the team's own services says about the stores it depends on (its ``/readyz``: ``{"ready": ...,
"s3": "up" | "down"}``), read by the catalog each time it lists the service, so the gateway's /readyz says
"not ready" naming the store (it said ready while S3 was down: the services list their tools without it).

Third-party upstreams (no service token) and services without ``/readyz`` report nothing. One GET per
service per catalog poll (5 s by default), at most 3 s each.
"""

from __future__ import annotations

import httpx

from bagmcp_gateway.upstreams.upstream import Upstream

TIMEOUT_S = 3.0
STATES = ("up", "down")


def readyz_url(upstream: Upstream) -> str | None:
    """``<service>/readyz`` for one of our services reached at ``<service>/mcp``; None for others."""
    if upstream.service_token is None or upstream.url is None or not upstream.url.endswith("/mcp"):
        return None
    return f"{upstream.url.removesuffix('/mcp')}/readyz"


async def dependencies_of(upstream: Upstream, client: httpx.AsyncClient) -> dict[str, str]:
    """Each store the service names in its /readyz, "up" or "down" ({} when it cannot say)."""
    url = readyz_url(upstream)
    if url is None:
        return {}
    try:
        answer = await client.get(url, timeout=TIMEOUT_S)
        body = answer.json() if answer.status_code in (200, 503) else {}
    except (httpx.HTTPError, ValueError):
        return {}
    if not isinstance(body, dict):
        return {}
    return {str(name): state for name, state in body.items() if name != "ready" and state in STATES}


def down_dependencies(dependencies: dict[str, dict[str, str]]) -> dict[str, list[str]]:
    """Per service, the stores it reports down (services with none left out)."""
    down = {name: sorted(d for d, state in deps.items() if state == "down") for name, deps in dependencies.items()}
    return {name: stores for name, stores in down.items() if stores}
