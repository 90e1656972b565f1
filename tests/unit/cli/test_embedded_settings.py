"""Embedded servers over different folders keep their data apart by default."""

from __future__ import annotations

from pathlib import Path

from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.ratelimit import Limit
from bagmcp_shared.settings import Env


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


def test_serve_has_no_rate_limit_unless_one_is_set(tmp_path: Path) -> None:
    assert EmbeddedSettings.from_env(tmp_path, None, Env({})).rate_limit is None
    limited = EmbeddedSettings.from_env(tmp_path, None, Env({"BAGMCP_RATE_LIMIT_PER_S": "5", "BAGMCP_RATE_BURST": "9"}))
    assert limited.rate_limit == Limit(rate_per_s=5.0, burst=9)
