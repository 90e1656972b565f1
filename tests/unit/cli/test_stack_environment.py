"""The settings `make stack` chooses: ports that are free (the defaults when they are), kept for the next
start; random secrets kept readable by their owner only; the running stack's settings for commands."""

from __future__ import annotations

import socket
import stat
from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path

import pytest

from bagmcp_cli.stack import environment
from bagmcp_cli.stack.environment import SAVED, ports_free, ports_of, stack_settings
from bagmcp_shared.errors import SettingsError
from bagmcp_shared.settings import Env
from tests.fixtures.servers import free_ports


@pytest.fixture
def held() -> Iterator[list[int]]:
    """Six ports held by listening sockets for the test (the "defaults" it gives the stack)."""
    with ExitStack() as stack:
        sockets = [stack.enter_context(socket.socket()) for _ in environment.DEFAULT_PORTS]
        for sock in sockets:
            sock.bind(("127.0.0.1", 0))
            sock.listen()
        yield [int(s.getsockname()[1]) for s in sockets]


def _env(stack_dir: Path, **values: str) -> Env:
    return Env({"BAGMCP_STACK_DIR": str(stack_dir), **values})


def test_taken_defaults_are_replaced_by_free_ports_and_kept_for_the_next_start(
    tmp_path: Path, held: list[int], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(environment, "DEFAULT_PORTS", dict(zip(environment.DEFAULT_PORTS, held, strict=True)))
    first = stack_settings(_env(tmp_path / "a"), starting=True)
    chosen = {name: int(first[name]) for name in environment.DEFAULT_PORTS}
    assert not set(chosen.values()) & set(held)
    occupied = [p for name, port in chosen.items() for p in ports_of(name, port)]
    assert len(occupied) == len(set(occupied)) == len(chosen) + 7  # the S3 server's block has eight ports
    again = stack_settings(_env(tmp_path / "a"), starting=True)
    assert {name: int(again[name]) for name in chosen} == chosen
    assert again["BAGMCP_SERVICE_TOKEN"] == first["BAGMCP_SERVICE_TOKEN"]


def test_free_defaults_are_used_and_given_ports_win(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    free = free_ports(len(environment.DEFAULT_PORTS) - 1)
    defaults = dict(zip(environment.DEFAULT_PORTS, [*free, 0], strict=True))
    defaults["S3_PORT"] = next(p for p in range(24000, 30000, 37) if ports_free("S3_PORT", p, set(free)))
    monkeypatch.setattr(environment, "DEFAULT_PORTS", defaults)
    settings = stack_settings(_env(tmp_path, GATEWAY_PORT="18999"), starting=True)
    assert settings["GATEWAY_PORT"] == "18999"
    assert int(settings["BAG_STORE_PORT"]) == defaults["BAG_STORE_PORT"]
    assert int(settings["S3_PORT"]) == defaults["S3_PORT"]
    assert settings["BAGMCP_S3_ENDPOINT"] == f"127.0.0.1:{defaults['S3_PORT']}"
    assert settings["BAGMCP_REDIS_URL"].endswith(f"@127.0.0.1:{defaults['REDIS_PORT']}/0")


def test_secrets_are_random_per_stack_and_saved_for_the_owner_only(tmp_path: Path) -> None:
    a = stack_settings(_env(tmp_path / "a"), starting=True)
    b = stack_settings(_env(tmp_path / "b"), starting=True)
    for secret in environment.SECRETS:
        assert len(a[secret]) >= 40
        assert a[secret] != b[secret]
    saved = tmp_path / "a" / SAVED
    assert stat.S_IMODE(saved.stat().st_mode) == 0o600
    assert stat.S_IMODE((tmp_path / "a").stat().st_mode) == 0o700
    assert f"BAGMCP_SERVICE_TOKEN={a['BAGMCP_SERVICE_TOKEN']}" in saved.read_text()


def test_a_command_uses_what_the_stack_chose_and_needs_a_stack(tmp_path: Path) -> None:
    with pytest.raises(SettingsError, match="run `make stack` first"):
        stack_settings(_env(tmp_path / "none"), starting=False)
    started = stack_settings(_env(tmp_path / "a"), starting=True)
    assert stack_settings(_env(tmp_path / "a"), starting=False) == started
