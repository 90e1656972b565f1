"""Which provider, model and key a run uses, and the conversation that gives. The SDKs are imported by the
first conversation of their kind (importing both takes seconds, which `bagmcp serve` need not wait for)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

from mcp.types import Tool

from bagmcp_lab.errors import KeyMissingError, LabError
from bagmcp_lab.providers.conversation import Conversation

ProviderName = Literal["anthropic", "openai"]
PROVIDERS: dict[str, str] = {"anthropic": "ANTHROPIC_API_KEY", "openai": "OPENAI_API_KEY"}
LOCAL_SERVER_KEY = "none"  # Ollama, vLLM and LM Studio ignore the key, the SDK needs one


@dataclass(frozen=True)
class ProviderChoice:
    """A model to run. ``api_key`` lives only as long as this object: it is never written or logged (``repr``
    hides it)."""

    provider: str
    model: str
    api_key: str
    base_url: str | None = None
    images: bool = True

    def __repr__(self) -> str:
        return f"ProviderChoice(provider={self.provider!r}, model={self.model!r}, base_url={self.base_url!r})"

    @property
    def label(self) -> str:
        return self.model


@dataclass(frozen=True)
class Opening:
    """What a conversation starts from: the model, the MCP server's tools and instructions, and the chat so far
    as (role, text) pairs, the last being the user's new question."""

    choice: ProviderChoice
    tools: Sequence[Tool]
    history: Sequence[tuple[str, str]]
    instructions: str | None


def key_from_env(provider: str, env: Mapping[str, str], *, variable: str | None, base_url: str | None) -> str:
    """The key in the environment variable ``variable`` (default: the provider's usual one)."""
    if provider not in PROVIDERS:
        raise LabError(f"unknown provider {provider!r}; use one of {', '.join(PROVIDERS)}")
    name = variable or PROVIDERS[provider]
    key = env.get(name, "").strip()
    if key:
        return key
    if base_url is not None:
        return LOCAL_SERVER_KEY
    raise KeyMissingError(f"set {name} to your {provider} API key (or name another variable with --api-key-env)")


def open_conversation(
    choice: ProviderChoice,
    tools: Sequence[Tool],
    history: Sequence[tuple[str, str]],
    *,
    instructions: str | None = None,
) -> Conversation:
    """A conversation whose last ``history`` entry is the user's question; ``instructions``: the MCP server's."""
    make: Callable[[Opening], Conversation]
    if choice.provider == "anthropic":
        from bagmcp_lab.providers.anthropic_chat import anthropic_conversation as make
    elif choice.provider == "openai":
        from bagmcp_lab.providers.openai_chat import openai_conversation as make
    else:
        raise LabError(f"unknown provider {choice.provider!r}; use one of {', '.join(PROVIDERS)}")
    return make(Opening(choice, tools, history, instructions))
