"""docker-compose.yml and `make stack` describe the same services with the same commands.

There is no Docker engine here, so compose is checked statically; `make stack` runs the same
commands as local processes (its Procfile), and the distributed integration test runs them too.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import yaml

from bagmcp_cli.stack.environment import DEFAULT_PORTS, SECRETS, derived
from bagmcp_shared.settings import Env

ROOT = Path(__file__).resolve().parents[3]
COMPOSE = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
PROCFILE = dict(
    line.split(":", 1)
    for line in (ROOT / "deploy/stack/Procfile").read_text().splitlines()
    if line and not line.startswith("#")
)
APPS = ("bag-store", "bag-store-worker", "analysis", "analysis-worker", "plotting", "plotting-worker", "gateway")


def _procfile_command(name: str) -> list[str]:
    words = shlex.split(PROCFILE[name])
    if words[0] == "env":
        words = [w for w in words[1:] if not re.match(r"^[A-Z_]+=", w)]
    return words


def test_every_app_service_runs_the_same_command_in_compose_and_in_the_stack() -> None:
    for name in APPS:
        assert _procfile_command(name) == COMPOSE["services"][name]["command"], name


def test_only_the_gateway_publishes_a_port() -> None:
    published = [name for name, spec in COMPOSE["services"].items() if spec.get("ports")]
    assert published == ["gateway"]


def test_secrets_must_be_given_and_have_no_defaults() -> None:
    text = (ROOT / "docker-compose.yml").read_text()
    for secret in ("MINIO_ROOT_PASSWORD", "BAGMCP_SERVICE_TOKEN", "BAGMCP_TOKENS"):
        assert f"${{{secret}:?" in text
        assert f"${{{secret}:-" not in text


def test_every_service_the_apps_wait_for_has_a_health_check() -> None:
    services = COMPOSE["services"]
    for spec in services.values():
        for dependency, condition in (spec.get("depends_on") or {}).items():
            if condition.get("condition") == "service_healthy":
                assert "healthcheck" in services[dependency], dependency


def test_the_stack_gives_each_app_the_settings_compose_gives_it(tmp_path: Path) -> None:
    ports = {name: 20000 + i * 20 for i, name in enumerate(DEFAULT_PORTS)}
    settings = derived(tmp_path, ports, dict.fromkeys(SECRETS, "s3cr3t"), Env({}))
    for name in APPS:
        environment = COMPOSE["services"][name].get("environment") or {}
        for key in environment:
            if key.startswith("BAGMCP_") and key not in ("BAGMCP_PUBLIC_URL", "BAGMCP_ALLOWED_HOSTS"):
                assert key in settings or key in PROCFILE[name], f"{name}: {key}"
