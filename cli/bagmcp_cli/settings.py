"""Settings of the embedded server, read once from the environment and the command line."""

from __future__ import annotations

import hashlib
import ipaddress
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from bagmcp_bag_store.settings import DEFAULT_QUERY_LIMITS, QueryLimits
from bagmcp_gateway.access.ratelimit import Limit
from bagmcp_gateway.settings import rate_limit_from_env
from bagmcp_lab.settings import ANY_BASE_URL, LabSettings
from bagmcp_shared.settings import (
    DEFAULT_INPUT_BUDGET,
    DEFAULT_OPEN_BAGS,
    DEFAULT_STOP_GRACE_S,
    LOOPBACK_HOSTS,
    Env,
    HttpSettings,
    InputBudget,
    OpenBagLimits,
    default_data_dir,
    host_patterns,
)


@dataclass(frozen=True)
class EmbeddedSettings:
    """``rate_limit`` (``bagmcp serve`` only) is off unless BAGMCP_RATE_LIMIT_PER_S is set: one user, one machine."""

    folder: Path
    data_dir: Path
    job_budget_s: float = 20.0
    allowed_hosts: tuple[str, ...] = ()
    stop_grace_s: float = DEFAULT_STOP_GRACE_S
    rate_limit: Limit | None = None
    open_bags: OpenBagLimits = DEFAULT_OPEN_BAGS
    input_budget: InputBudget = DEFAULT_INPUT_BUDGET
    lab: LabSettings = field(default_factory=LabSettings)
    queries: QueryLimits = DEFAULT_QUERY_LIMITS

    @classmethod
    def from_env(cls, folder: Path, data_dir: Path | None, env: Env | None = None) -> EmbeddedSettings:
        """Without ``data_dir``, each served folder gets its own directory under the default data directory,
        so servers over different folders never share indexes or the bags filter_bag made."""
        env = env or Env()
        return cls(
            folder=folder,
            data_dir=data_dir or default_data_dir(env) / folder_key(folder),
            job_budget_s=env.number("BAGMCP_JOB_BUDGET_S", 20.0),
            allowed_hosts=env.items("BAGMCP_ALLOWED_HOSTS"),
            stop_grace_s=env.number("BAGMCP_STOP_GRACE_S", DEFAULT_STOP_GRACE_S),
            rate_limit=rate_limit_from_env(env, default_per_s=0.0),
            open_bags=OpenBagLimits.from_env(env),
            input_budget=InputBudget.from_env(env),
            lab=LabSettings.from_env(env, base_urls=(ANY_BASE_URL,)),  # the machine's owner may name any server
            queries=QueryLimits.from_env(env),
        )

    def http(self, host: str, port: int, *, allowed_hosts: Sequence[str] = ()) -> HttpSettings:
        """Where ``bagmcp serve`` listens, answering to loopback names, the address it binds (unless that is
        every address), BAGMCP_ALLOWED_HOSTS and ``allowed_hosts`` (``--allowed-host``)."""
        bound = [] if _is_any_address(host) else [f"[{host}]" if ":" in host else host]
        names = host_patterns([*bound, *self.allowed_hosts, *allowed_hosts])
        hosts = tuple(dict.fromkeys([*LOOPBACK_HOSTS, *names]))
        return HttpSettings(host=host, port=port, allowed_hosts=hosts, stop_grace_s=self.stop_grace_s)


def _is_any_address(host: str) -> bool:
    try:
        return ipaddress.ip_address(host).is_unspecified
    except ValueError:
        return False


def folder_key(folder: Path) -> str:
    """A directory name for a served folder: its name and a hash of its absolute path."""
    resolved = folder.resolve()
    digest = hashlib.sha256(str(resolved).encode()).hexdigest()[:12]
    name = "".join(c if c.isalnum() or c in "-_." else "_" for c in resolved.name)[:40] or "root"
    return f"{name}-{digest}"
