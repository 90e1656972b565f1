"""The Lab's settings, read once at its entry point: how many runs a caller may have going, which model servers
a caller may name, and the operator's keys (optional) that callers may use without bringing their own."""

from __future__ import annotations

from dataclasses import dataclass, field

from bagmcp_shared.settings import Env, HttpSettings

DEFAULT_PORT = 8004
ANY_BASE_URL = "*"


@dataclass(frozen=True)
class OperatorKey:
    """A key from the server's environment; used only with its own base URL (never sent elsewhere)."""

    api_key: str
    base_url: str | None = None

    def __repr__(self) -> str:
        return f"OperatorKey(base_url={self.base_url!r})"


@dataclass(frozen=True)
class LabSettings:
    """``base_urls``: prefixes a caller's ``base_url`` must start with (``*``: any; the embedded server's
    default, as its user is the machine's owner). ``runs_per_caller`` bounds benchmark runs (and chats) going
    at once per token."""

    runs_per_caller: int = 2
    base_urls: tuple[str, ...] = (ANY_BASE_URL,)
    operator_keys: dict[str, OperatorKey] = field(default_factory=dict)
    max_turns: int = 10
    kept_runs: int = 50

    @classmethod
    def from_env(cls, env: Env, *, base_urls: tuple[str, ...] = ("https://",)) -> LabSettings:
        """``BAGMCP_LAB_RUNS_PER_TOKEN``, ``BAGMCP_LAB_BASE_URLS``, ``BAGMCP_LAB_ANTHROPIC_API_KEY``,
        ``BAGMCP_LAB_OPENAI_API_KEY`` (with ``BAGMCP_LAB_OPENAI_BASE_URL`` for a local model server)."""
        keys = {}
        if (anthropic := env.optional("BAGMCP_LAB_ANTHROPIC_API_KEY")) is not None:
            keys["anthropic"] = OperatorKey(anthropic)
        if (openai := env.optional("BAGMCP_LAB_OPENAI_API_KEY")) is not None:
            keys["openai"] = OperatorKey(openai, env.optional("BAGMCP_LAB_OPENAI_BASE_URL"))
        return cls(
            runs_per_caller=env.integer("BAGMCP_LAB_RUNS_PER_TOKEN", 2),
            base_urls=env.items("BAGMCP_LAB_BASE_URLS", base_urls),
            operator_keys=keys,
            max_turns=env.integer("BAGMCP_LAB_MAX_TURNS", 10),
        )


@dataclass(frozen=True)
class LabServiceSettings:
    """The Lab as a service of its own (team mode): it answers only the gateway (service token) and calls the
    gateway's MCP endpoint (``gateway_mcp_url``) with each caller's own token."""

    lab: LabSettings
    http: HttpSettings
    service_token: str
    gateway_mcp_url: str

    @classmethod
    def from_env(cls, env: Env | None = None) -> LabServiceSettings:
        env = env or Env()
        return cls(
            lab=LabSettings.from_env(env),
            http=HttpSettings.from_env(env, port=DEFAULT_PORT, extra_hosts=("lab:*",)),
            service_token=env.secret("BAGMCP_SERVICE_TOKEN"),
            gateway_mcp_url=env.need("BAGMCP_LAB_GATEWAY_URL"),
        )
