"""Gateway settings for team mode, read once from ``BAGMCP_*`` environment variables."""

from __future__ import annotations

import os
from dataclasses import dataclass

from bagmcp_gateway.auth import token_hash
from bagmcp_gateway.upstreams import GatewayConfigError, Upstream

PLACEHOLDERS = {"", "changeme", "change-me", "secret"}


@dataclass(frozen=True)
class GatewaySettings:
    upstreams: list[Upstream]
    token_hashes: list[str]
    bag_store_url: str
    service_token: str
    host: str
    port: int
    public_url: str
    allowed_hosts: tuple[str, ...]

    @classmethod
    def from_env(cls, env: dict[str, str] | None = None) -> GatewaySettings:
        """Refuses to start without a client token and a non-placeholder service token.

        ``BAGMCP_UPSTREAMS`` is ``name=url[,name=url...]``; an optional ``@prefix`` after the url
        prefixes that upstream's tool names.
        """
        env = dict(os.environ) if env is None else env
        service = env.get("BAGMCP_SERVICE_TOKEN", "")
        if service.lower() in PLACEHOLDERS:
            raise GatewayConfigError("BAGMCP_SERVICE_TOKEN must be set to a real secret")
        tokens = [t for t in env.get("BAGMCP_TOKENS", env.get("BAGMCP_DEV_TOKEN", "")).split(",") if t.strip()]
        hashes = [token_hash(t.strip()) for t in tokens]
        hashes += [h for h in env.get("BAGMCP_TOKEN_HASHES", "").split(",") if h.strip()]
        if not hashes:
            raise GatewayConfigError("set BAGMCP_TOKENS (or BAGMCP_TOKEN_HASHES): the gateway needs client tokens")
        upstreams = []
        for item in env.get("BAGMCP_UPSTREAMS", "bag-store=http://127.0.0.1:8001/mcp").split(","):
            name, _, rest = item.strip().partition("=")
            url, _, prefix = rest.partition("@")
            upstreams.append(Upstream(name=name, url=url, service_token=service, prefix=prefix or None))
        host = env.get("BAGMCP_HOST", "127.0.0.1")
        port = int(env.get("BAGMCP_PORT", "8080"))
        allowed = tuple(h for h in env.get("BAGMCP_ALLOWED_HOSTS", "127.0.0.1:*,localhost:*").split(",") if h)
        return cls(
            upstreams=upstreams,
            token_hashes=hashes,
            bag_store_url=env.get("BAGMCP_BAG_STORE_URL", "http://127.0.0.1:8001"),
            service_token=service,
            host=host,
            port=port,
            public_url=env.get("BAGMCP_PUBLIC_URL", f"http://{host}:{port}"),
            allowed_hosts=allowed,
        )
