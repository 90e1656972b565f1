"""Which key and model server a run uses: the CLI's environment variable, the page's key for one request, or
the operator's key only with the operator's server; a key never shows in a repr."""

from __future__ import annotations

import pytest

from bagmcp_lab.errors import KeyMissingError, LabError
from bagmcp_lab.providers.factory import LOCAL_SERVER_KEY, ProviderChoice, key_from_env
from bagmcp_lab.server.keys import ModelRequest, choose_model
from bagmcp_lab.settings import LabSettings, OperatorKey
from bagmcp_shared.settings import Env

TEAM = LabSettings(
    base_urls=("https://api.groq.com/",), operator_keys={"openai": OperatorKey("op-key", "http://ollama:11434/v1")}
)


def test_the_cli_reads_the_named_variable_or_the_providers_own() -> None:
    env = {"ANTHROPIC_API_KEY": "a", "MINE": "m"}
    assert key_from_env("anthropic", env, variable=None, base_url=None) == "a"
    assert key_from_env("openai", env, variable="MINE", base_url=None) == "m"
    assert key_from_env("openai", {}, variable=None, base_url="http://localhost:11434/v1") == LOCAL_SERVER_KEY
    with pytest.raises(KeyMissingError, match=r"^set OPENAI_API_KEY to your openai API key"):
        key_from_env("openai", {}, variable=None, base_url=None)


def test_the_pages_key_goes_only_to_an_allowed_server() -> None:
    mine = choose_model(
        ModelRequest(provider="openai", model="llama", base_url="https://api.groq.com/openai/v1", api_key="k"), TEAM
    )
    assert (mine.api_key, mine.base_url) == ("k", "https://api.groq.com/openai/v1")
    with pytest.raises(
        LabError, match=r"^this server may not call http://10\.0\.0\.5/v1; allowed base URLs start with"
    ):
        choose_model(ModelRequest(provider="openai", model="m", base_url="http://10.0.0.5/v1", api_key="k"), TEAM)


def test_the_operators_key_is_used_only_with_the_operators_server() -> None:
    used = choose_model(ModelRequest(provider="openai", model="llama3.1"), TEAM)
    assert (used.api_key, used.base_url) == ("op-key", "http://ollama:11434/v1")
    with pytest.raises(LabError, match="the operator's key is used only with the operator's model server"):
        choose_model(ModelRequest(provider="openai", model="m", base_url="https://evil.example/v1"), TEAM)
    with pytest.raises(KeyMissingError, match="type your anthropic API key"):
        choose_model(ModelRequest(provider="anthropic", model="claude"), TEAM)


def test_keys_never_show_in_a_repr() -> None:
    choice = ProviderChoice("openai", "m", "secret-key-1", None)
    request = ModelRequest(provider="openai", model="m", api_key="secret-key-2")
    assert "secret" not in repr(choice) + repr(request) + repr(TEAM) + repr(OperatorKey("secret-key-3"))


def test_settings_come_from_the_lab_variables() -> None:
    env = Env(
        {
            "BAGMCP_LAB_RUNS_PER_TOKEN": "3",
            "BAGMCP_LAB_BASE_URLS": "https://a/,https://b/",
            "BAGMCP_LAB_ANTHROPIC_API_KEY": "x",
        }
    )
    settings = LabSettings.from_env(env)
    assert (settings.runs_per_caller, settings.base_urls, list(settings.operator_keys)) == (
        3,
        ("https://a/", "https://b/"),
        ["anthropic"],
    )
    assert LabSettings.from_env(Env({})).base_urls == ("https://",)
