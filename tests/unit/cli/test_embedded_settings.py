"""Embedded servers over different folders keep their data apart by default."""

from __future__ import annotations

from pathlib import Path

from bagmcp_cli.settings import EmbeddedSettings
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
