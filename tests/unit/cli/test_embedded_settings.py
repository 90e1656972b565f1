"""Embedded servers over different folders keep their data apart by default."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.ratelimit import Limit
from bagmcp_kit.runtime.resources import embedded_resources
from bagmcp_shared import budget
from bagmcp_shared.settings import Env, InputBudget, OpenBagLimits


def test_each_served_folder_gets_its_own_data_directory(tmp_path: Path) -> None:
    env = Env({"BAGMCP_DATA_DIR": str(tmp_path / "data")})
    first = EmbeddedSettings.from_env(tmp_path / "a" / "bags", None, env)
    second = EmbeddedSettings.from_env(tmp_path / "b" / "bags", None, env)
    again = EmbeddedSettings.from_env(tmp_path / "a" / "bags", None, env)
    assert first.data_dir != second.data_dir
    assert first.data_dir == again.data_dir
    assert first.data_dir.parent == second.data_dir.parent == tmp_path / "data"
    assert first.data_dir.name.startswith("bags-")


def test_an_explicit_data_directory_is_used_as_given(tmp_path: Path) -> None:
    chosen = EmbeddedSettings.from_env(tmp_path / "bags", tmp_path / "mine", Env({}))
    assert chosen.data_dir == tmp_path / "mine"


def test_serving_every_address_answers_to_the_names_given_and_never_to_0_0_0_0(tmp_path: Path) -> None:
    settings = EmbeddedSettings.from_env(tmp_path, None, Env({"BAGMCP_ALLOWED_HOSTS": "bags.lab,10.0.0.5:8000"}))
    http = settings.http("0.0.0.0", 8000, allowed_hosts=["robot-pc"])
    assert http.allowed_hosts == (
        "127.0.0.1:*",
        "localhost:*",
        "[::1]:*",
        "bags.lab:*",
        "10.0.0.5:8000",
        "robot-pc:*",
    )


def test_serving_one_address_answers_to_it(tmp_path: Path) -> None:
    settings = EmbeddedSettings.from_env(tmp_path, None, Env({}))
    assert "192.168.1.20:*" in settings.http("192.168.1.20", 8000).allowed_hosts
    assert "[fd00::5]:*" in settings.http("fd00::5", 8000).allowed_hosts


def test_serve_has_no_rate_limit_unless_one_is_set(tmp_path: Path) -> None:
    assert EmbeddedSettings.from_env(tmp_path, None, Env({})).rate_limit is None
    limited = EmbeddedSettings.from_env(tmp_path, None, Env({"BAGMCP_RATE_LIMIT_PER_S": "5", "BAGMCP_RATE_BURST": "9"}))
    assert limited.rate_limit == Limit(rate_per_s=5.0, burst=9)


def test_the_opened_bag_limits_come_from_the_environment_and_reach_the_bag_access(tmp_path: Path) -> None:
    env = Env({"BAGMCP_OPEN_BAGS": "3", "BAGMCP_OPEN_BAGS_MAX_BYTES": "1000000", "BAGMCP_OPEN_READERS_PER_BAG": "2"})
    settings = EmbeddedSettings.from_env(tmp_path, tmp_path / "data", env)
    assert settings.open_bags == OpenBagLimits(max_bags=3, max_bytes=1_000_000, max_readers_per_bag=2)
    assert EmbeddedSettings.from_env(tmp_path, None, Env({})).open_bags == OpenBagLimits()
    embedded = embedded_resources(tmp_path, tmp_path / "data", open_bags=settings.open_bags)
    cache = embedded.resources.access.cache  # the configured one, not a default put in its place
    assert (cache.max_bags, cache.max_bytes) == (3, 1_000_000)
    embedded.runner.shutdown()


def test_the_input_budget_comes_from_the_environment_and_becomes_the_processs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(budget, "_current", InputBudget())  # restored after the test
    env = Env({"BAGMCP_MAX_EXPANSION": "50", "BAGMCP_MAX_RECORD_BYTES": "1000000", "BAGMCP_MAX_IMAGE_BYTES": "2000"})
    settings = EmbeddedSettings.from_env(tmp_path, tmp_path / "data", env)
    assert settings.input_budget == InputBudget(max_expansion=50.0, max_record_bytes=1_000_000, max_image_bytes=2000)
    assert EmbeddedSettings.from_env(tmp_path, None, Env({})).input_budget == InputBudget()
    embedded = embedded_resources(tmp_path, tmp_path / "data", input_budget=settings.input_budget)
    assert budget.input_budget() == settings.input_budget
    embedded.runner.shutdown()
