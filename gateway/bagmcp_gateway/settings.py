"""Gateway settings, one class, read once from ``BAGMCP_*`` environment variables (team mode) or
built by the embedded command."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_gateway.access.profiles import DEFAULT_PROFILES, Profile
from bagmcp_gateway.access.ratelimit import Limit
from bagmcp_gateway.access.tokens.models import token_hash
from bagmcp_gateway.access.tokens.verifier import JwtSettings
from bagmcp_gateway.access.upload_limits import DEFAULT_IDLE_S, DEFAULT_PER_TOKEN, UploadLimits
from bagmcp_gateway.mcp_front.wire_answers import DEFAULT_MAX_CHARS
from bagmcp_gateway.upstreams.upstream import DEFAULT_UPSTREAM_TIMEOUT_S, GatewayConfigError, Upstream
from bagmcp_shared.settings import Env, HttpSettings

DEFAULT_PORT = 8080
TEAM_RATE_PER_S = 20.0
DEFAULT_BURST = 40


def rate_limit_from_env(env: Env, *, default_per_s: float) -> Limit | None:
    """``BAGMCP_RATE_LIMIT_PER_S`` calls a second per token (0: no limit), ``BAGMCP_RATE_BURST`` at once."""
    rate = env.number("BAGMCP_RATE_LIMIT_PER_S", default_per_s)
    return Limit(rate, env.integer("BAGMCP_RATE_BURST", DEFAULT_BURST)) if rate > 0 else None


def parse_upstreams(
    text: str, *, service_token: str | None, connect_timeout_s: float = DEFAULT_UPSTREAM_TIMEOUT_S
) -> list[Upstream]:
    """``name=url[@prefix][#timeout_s]`` items separated by commas: ``@prefix`` prefixes that upstream's tool
    names, ``#timeout_s`` bounds its calls. Our services get the service token; ``!name=url`` marks a
    third-party server, which never does. ``connect_timeout_s`` bounds connecting to each and listing its tools
    (``BAGMCP_UPSTREAM_TIMEOUT_S``): past it the upstream counts as down."""
    upstreams = []
    for item in (i.strip() for i in text.split(",") if i.strip()):
        foreign = item.startswith("!")
        name, _, rest = item.lstrip("!").partition("=")
        rest, _, timeout = rest.partition("#")
        url, _, prefix = rest.partition("@")
        if not url:
            raise GatewayConfigError(f"BAGMCP_UPSTREAMS item {item!r} must look like name=http://host:port/mcp")
        try:
            call_timeout_s = float(timeout) if timeout else 600.0
        except ValueError as err:
            raise GatewayConfigError(f"BAGMCP_UPSTREAMS item {item!r}: the timeout after # must be seconds") from err
        upstreams.append(
            Upstream(
                name=name,
                url=url,
                service_token=None if foreign else service_token,
                prefix=prefix or None,
                call_timeout_s=call_timeout_s,
                timeout_s=connect_timeout_s,
            )
        )
    names = [u.name for u in upstreams]
    if len(set(names)) != len(names):
        raise GatewayConfigError(f"BAGMCP_UPSTREAMS names an upstream twice: {', '.join(names)}")
    return upstreams


def parse_routes(text: str) -> dict[str, str]:
    """``segment=base_url`` items: REST requests under ``/api/v1/<segment>`` go to that service."""
    routes = {}
    for item in (i.strip() for i in text.split(",") if i.strip()):
        segment, _, url = item.partition("=")
        if not segment.isidentifier() or not url:
            raise GatewayConfigError(f"BAGMCP_REST_ROUTES item {item!r} must look like bags=http://host:port")
        routes[segment] = url.rstrip("/")
    return routes


def parse_profiles(text: str | None) -> dict[str, Profile]:
    """``{"name": {"tools": [globs], "lean": bool}}`` added to (or replacing) the built-in full and core."""
    profiles = dict(DEFAULT_PROFILES)
    if not text:
        return profiles
    try:
        raw = json.loads(text)
        for name, body in raw.items():
            profiles[str(name)] = Profile(tuple(str(g) for g in body["tools"]), lean=bool(body.get("lean", False)))
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise GatewayConfigError(
            f'BAGMCP_PROFILES must be {{"name": {{"tools": ["glob"], "lean": false}}}} ({err})'
        ) from err
    return profiles


@dataclass(frozen=True)
class GatewaySettings:
    """No ``token_hashes``, ``redis_url`` (tokens made with `bagmcp token`), ``tokens_file`` or ``jwt`` means
    no authentication (only for a loopback embedded server). Every token in ``token_hashes`` has every scope
    (the development token).

    ``rest_routes`` maps the first segment under /api/v1 (``bags``, ``artifacts``, ``lab``) to the service
    that serves it; those in ``caller_routes`` also get the caller's own token (the Lab acts for the caller);
    ``redis_url`` holds the shared job store, the team's tokens, the rate limits and the change
    events every replica tells its clients. ``instructions`` replaces what the upstreams' instructions say."""

    upstreams: list[Upstream] = field(default_factory=list)
    token_hashes: list[str] = field(default_factory=list)
    service_token: str | None = None
    http: HttpSettings = field(default_factory=HttpSettings)
    public_url: str = "http://127.0.0.1:8080"
    rest_routes: dict[str, str] = field(default_factory=dict)
    caller_routes: tuple[str, ...] = ("lab",)
    redis_url: str | None = None
    tokens_file: Path | None = None
    jwt: JwtSettings | None = None
    policy: ToolPolicy = field(default_factory=ToolPolicy)
    rate_limit: Limit | None = None
    max_answer_chars: int = DEFAULT_MAX_CHARS
    audit: bool = False
    audit_arguments: bool = False
    upstream_poll_s: float = 5.0
    instructions: str | None = None
    uploads: UploadLimits = field(default_factory=UploadLimits)

    @property
    def authenticated(self) -> bool:
        return bool(self.token_hashes or self.redis_url or self.tokens_file or self.jwt)

    @classmethod
    def from_env(cls, env: Env | None = None) -> GatewaySettings:
        """Refuses to start without a way to authenticate callers and a real service token."""
        env = env or Env()
        service = env.secret("BAGMCP_SERVICE_TOKEN")
        tokens = env.items("BAGMCP_TOKENS") or env.items("BAGMCP_DEV_TOKEN")
        hashes = [token_hash(t) for t in tokens] + list(env.items("BAGMCP_TOKEN_HASHES"))
        redis_url = env.optional("BAGMCP_REDIS_URL")
        jwks = env.optional("BAGMCP_JWT_JWKS_URL")
        jwt_settings = (
            JwtSettings(jwks, env.need("BAGMCP_JWT_ISSUER"), env.optional("BAGMCP_JWT_AUDIENCE")) if jwks else None
        )
        if not hashes and not redis_url and jwt_settings is None:
            raise GatewayConfigError(
                "set BAGMCP_TOKENS, BAGMCP_REDIS_URL (tokens made with `bagmcp token`) or BAGMCP_JWT_*"
            )
        http = HttpSettings.from_env(env, port=DEFAULT_PORT, extra_hosts=("gateway:*",))
        upstreams = parse_upstreams(
            env.need("BAGMCP_UPSTREAMS"),
            service_token=service,
            connect_timeout_s=env.number("BAGMCP_UPSTREAM_TIMEOUT_S", DEFAULT_UPSTREAM_TIMEOUT_S),
        )
        return cls(
            upstreams=upstreams,
            token_hashes=hashes,
            service_token=service,
            http=http,
            public_url=env.text("BAGMCP_PUBLIC_URL", f"http://{http.host}:{http.port}"),
            rest_routes=parse_routes(env.text("BAGMCP_REST_ROUTES", "")),
            caller_routes=env.items("BAGMCP_CALLER_TOKEN_ROUTES", ("lab",)),
            redis_url=redis_url,
            jwt=jwt_settings,
            policy=ToolPolicy(
                enabled=env.items("BAGMCP_ENABLED_TOOLS", ("*",)),
                disabled=env.items("BAGMCP_DISABLED_TOOLS"),
                profiles=parse_profiles(env.optional("BAGMCP_PROFILES")),
            ),
            rate_limit=rate_limit_from_env(env, default_per_s=TEAM_RATE_PER_S),
            max_answer_chars=env.integer("BAGMCP_MAX_ANSWER_CHARS", DEFAULT_MAX_CHARS),
            audit=env.flag("BAGMCP_AUDIT", True),
            audit_arguments=env.flag("BAGMCP_AUDIT_ARGUMENTS", False),
            upstream_poll_s=env.number("BAGMCP_UPSTREAM_POLL_S", 5.0),
            instructions=env.optional("BAGMCP_INSTRUCTIONS"),
            uploads=UploadLimits(
                idle_s=env.number("BAGMCP_UPLOAD_IDLE_S", DEFAULT_IDLE_S),
                per_token=env.integer("BAGMCP_UPLOADS_PER_TOKEN", DEFAULT_PER_TOKEN),
            ),
        )
