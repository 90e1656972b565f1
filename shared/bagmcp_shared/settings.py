"""Settings every service shares, read once from ``BAGMCP_*`` environment variables at the entry point.

Nothing else in the project reads the environment: services compose these into their own
settings and pass the values down.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from bagmcp_shared.errors import SettingsError

PLACEHOLDER_SECRETS = frozenset({"", "changeme", "change-me", "secret", "password", "replace-me"})
LOOPBACK_HOSTS = ("127.0.0.1:*", "localhost:*", "[::1]:*")


class Env:
    """Typed access to environment variables, with errors that name the variable."""

    def __init__(self, environ: Mapping[str, str] | None = None) -> None:
        self._env = dict(os.environ) if environ is None else dict(environ)

    def text(self, key: str, default: str) -> str:
        return self._env.get(key) or default

    def optional(self, key: str) -> str | None:
        return self._env.get(key) or None

    def need(self, key: str) -> str:
        value = self._env.get(key, "")
        if not value:
            raise SettingsError(f"{key} must be set")
        return value

    def secret(self, key: str) -> str:
        """A required secret that must not be a placeholder such as "changeme"."""
        value = self.need(key)
        if value.lower() in PLACEHOLDER_SECRETS or value.lower().startswith("replace-with"):
            raise SettingsError(f"{key} must be set to a real secret, not a placeholder")
        return value

    def number(self, key: str, default: float) -> float:
        return float(self._parse(key, default, float))

    def integer(self, key: str, default: int) -> int:
        return int(self._parse(key, default, int))

    def flag(self, key: str, default: bool) -> bool:
        raw = self._env.get(key)
        return default if not raw else raw.strip().lower() in ("1", "true", "yes", "on")

    def items(self, key: str, default: tuple[str, ...] = ()) -> tuple[str, ...]:
        raw = self._env.get(key)
        return default if raw is None else tuple(p.strip() for p in raw.split(",") if p.strip())

    def _parse(self, key: str, default: float, kind: type[float] | type[int]) -> float:
        raw = self._env.get(key)
        if not raw:
            return default
        try:
            return kind(raw)
        except ValueError as err:
            raise SettingsError(f"{key} must be a number, got {raw!r}") from err


@dataclass(frozen=True)
class S3Settings:
    endpoint: str
    access_key: str
    secret_key: str
    bucket: str = "bagmcp"
    secure: bool = False
    read_timeout_s: float = 60.0
    ca_file: str | None = None  # certificate authorities for https endpoints (default: certifi's)

    @classmethod
    def from_env(cls, env: Env) -> S3Settings:
        return cls(
            endpoint=env.need("BAGMCP_S3_ENDPOINT"),
            access_key=env.need("BAGMCP_S3_ACCESS_KEY"),
            secret_key=env.secret("BAGMCP_S3_SECRET_KEY"),
            bucket=env.text("BAGMCP_S3_BUCKET", "bagmcp"),
            secure=env.flag("BAGMCP_S3_SECURE", False),
            read_timeout_s=env.number("BAGMCP_S3_READ_TIMEOUT_S", 60.0),
            ca_file=env.optional("BAGMCP_S3_CA_FILE") or env.optional("SSL_CERT_FILE"),
        )


def host_patterns(names: Sequence[str]) -> tuple[str, ...]:
    """Allowed Host entries from what a user writes: ``name`` or ``[v6]`` means any port (``name:*``);
    ``name:port`` and ``name:*`` stay as they are."""
    return tuple(n if n.rsplit("]", 1)[-1].count(":") == 1 else f"{n}:*" for n in names if n)


DEFAULT_STOP_GRACE_S = 8.0  # under Docker's 10 s before SIGKILL, so a stop ends on its own


@dataclass(frozen=True)
class HttpSettings:
    """Where a process listens and which Host headers it answers (DNS-rebinding protection)."""

    host: str = "127.0.0.1"
    port: int = 8000
    allowed_hosts: tuple[str, ...] = LOOPBACK_HOSTS
    stop_grace_s: float = DEFAULT_STOP_GRACE_S

    @classmethod
    def from_env(cls, env: Env, *, port: int, extra_hosts: tuple[str, ...] = ()) -> HttpSettings:
        return cls(
            host=env.text("BAGMCP_HOST", "127.0.0.1"),
            port=env.integer("BAGMCP_PORT", port),
            allowed_hosts=host_patterns(env.items("BAGMCP_ALLOWED_HOSTS", (*LOOPBACK_HOSTS, *extra_hosts))),
            stop_grace_s=env.number("BAGMCP_STOP_GRACE_S", DEFAULT_STOP_GRACE_S),
        )


@dataclass(frozen=True)
class OpenBagLimits:
    """The opened-bag cache of each process: at most ``max_bags`` bags and about ``max_bytes`` of readers'
    indexes and loaded index columns; ``max_readers_per_bag`` idle readers of one bag kept for concurrent
    callers. Least recently used bags are closed past these limits."""

    max_bags: int = 32
    max_bytes: int = 2**30
    max_readers_per_bag: int = 8

    @classmethod
    def from_env(cls, env: Env) -> OpenBagLimits:
        return cls(
            max_bags=env.integer("BAGMCP_OPEN_BAGS", 32),
            max_bytes=env.integer("BAGMCP_OPEN_BAGS_MAX_BYTES", 2**30),
            max_readers_per_bag=env.integer("BAGMCP_OPEN_READERS_PER_BAG", 8),
        )


DEFAULT_OPEN_BAGS = OpenBagLimits()


@dataclass(frozen=True)
class InputBudget:
    """How much memory one piece of stored input may ask for, checked before it is decompressed or decoded
    (see bagmcp_shared.budget): a compressed record (MCAP chunk, ROS 1 chunk, zstd storage file) may expand
    at most ``max_expansion`` times past ``expansion_floor_bytes`` and to at most ``max_record_bytes``; a
    decoded image at most ``max_image_bytes`` in its own pixel type. Real recordings stay far inside these:
    the corpus's largest chunk ratio is 31 and MCAP writers' chunks are 1-4 MiB."""

    max_expansion: float = 200.0
    max_record_bytes: int = 256 << 20
    max_image_bytes: int = 128 << 20
    expansion_floor_bytes: int = 64 << 20

    @classmethod
    def from_env(cls, env: Env) -> InputBudget:
        return cls(
            max_expansion=env.number("BAGMCP_MAX_EXPANSION", 200.0),
            max_record_bytes=env.integer("BAGMCP_MAX_RECORD_BYTES", 256 << 20),
            max_image_bytes=env.integer("BAGMCP_MAX_IMAGE_BYTES", 128 << 20),
        )

    def record_limit(self, compressed_bytes: int) -> int:
        """The most bytes a record of ``compressed_bytes`` may decompress to."""
        by_ratio = max(self.expansion_floor_bytes, int(self.max_expansion * compressed_bytes))
        return min(self.max_record_bytes, by_ratio)


DEFAULT_INPUT_BUDGET = InputBudget()


@dataclass(frozen=True)
class RangeReads:
    """Team mode reads MCAP bags where they are stored, by byte ranges, through a block cache on local
    disk shared by the host's processes: ``block_bytes`` per block (one MCAP chunk is typically 1-4 MiB),
    at most ``cache_bytes`` on disk, and ``read_ahead_bytes`` more fetched when a reader streams."""

    block_bytes: int = 2**20
    cache_bytes: int = 4 * 2**30
    read_ahead_bytes: int = 8 * 2**20

    @classmethod
    def from_env(cls, env: Env) -> RangeReads:
        reads = cls(
            block_bytes=env.integer("BAGMCP_BLOCK_BYTES", 2**20),
            cache_bytes=env.integer("BAGMCP_BLOCK_CACHE_BYTES", 4 * 2**30),
            read_ahead_bytes=env.integer("BAGMCP_READ_AHEAD_BYTES", 8 * 2**20),
        )
        if reads.block_bytes < 4096 or reads.read_ahead_bytes < 0:
            raise SettingsError("BAGMCP_BLOCK_BYTES must be at least 4096 and BAGMCP_READ_AHEAD_BYTES at least 0")
        if reads.cache_bytes < 4 * (reads.block_bytes + reads.read_ahead_bytes):
            raise SettingsError(
                "BAGMCP_BLOCK_CACHE_BYTES must hold at least four reads: 4 x (BAGMCP_BLOCK_BYTES + "
                "BAGMCP_READ_AHEAD_BYTES); raise it or lower those"
            )
        return reads


@dataclass(frozen=True)
class TeamSettings:
    """What every service process needs in team mode: Redis, S3, the service token, local data."""

    redis_url: str
    s3: S3Settings
    service_token: str
    data_dir: Path
    cache_max_bytes: int = 20 * 2**30
    max_result_bytes: int = 16_000
    job_budget_s: float = 20.0
    task_visibility_timeout_s: int = 60  # a task of a worker that died goes to another after this long
    open_bags: OpenBagLimits = DEFAULT_OPEN_BAGS
    input_budget: InputBudget = DEFAULT_INPUT_BUDGET
    range_reads: RangeReads = RangeReads()

    @classmethod
    def from_env(cls, env: Env) -> TeamSettings:
        return cls(
            redis_url=env.need("BAGMCP_REDIS_URL"),
            s3=S3Settings.from_env(env),
            service_token=env.secret("BAGMCP_SERVICE_TOKEN"),
            data_dir=Path(env.text("BAGMCP_DATA_DIR", "/var/lib/bagmcp")),
            cache_max_bytes=env.integer("BAGMCP_CACHE_MAX_BYTES", 20 * 2**30),
            max_result_bytes=env.integer("BAGMCP_MAX_RESULT_BYTES", 16_000),
            job_budget_s=env.number("BAGMCP_JOB_BUDGET_S", 20.0),
            task_visibility_timeout_s=env.integer("BAGMCP_TASK_VISIBILITY_TIMEOUT_S", 60),
            open_bags=OpenBagLimits.from_env(env),
            input_budget=InputBudget.from_env(env),
            range_reads=RangeReads.from_env(env),
        )

    @property
    def cache_dir(self) -> Path:
        return self.data_dir / "cache"

    @property
    def scratch_dir(self) -> Path:
        return self.data_dir / "scratch"


@dataclass(frozen=True)
class ServiceSettings:
    """A service process in team mode: the shared team settings, where it listens, its public URL."""

    team: TeamSettings
    http: HttpSettings
    public_url: str

    @classmethod
    def from_env(cls, env: Env, *, name: str, port: int) -> ServiceSettings:
        """``name`` is the service's host name in compose (accepted in the Host header)."""
        http = HttpSettings.from_env(env, port=port, extra_hosts=(f"{name}:*", f"{name.replace('-', '_')}:*"))
        return cls(
            team=TeamSettings.from_env(env),
            http=http,
            public_url=env.text("BAGMCP_PUBLIC_URL", f"http://{http.host}:{http.port}"),
        )


def default_data_dir(env: Env) -> Path:
    """Where an embedded server keeps indexes and the bags it makes (never inside the served folder)."""
    cache = env.optional("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(env.optional("BAGMCP_DATA_DIR") or Path(cache) / "bagmcp")
