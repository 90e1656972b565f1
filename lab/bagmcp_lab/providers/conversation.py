"""What the agent loop needs from a provider: the model's next reply, and a way to hand it tool answers."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any, Generic, Protocol, TypeVar

from bagmcp_lab.toolbox import ToolAnswer

SYSTEM_PROMPT = (
    "You answer questions about robot recordings (bags) by calling the tools given. Times are seconds from the "
    "bag's start unless stated otherwise. Call the tools you need, then give a short final answer in plain text "
    "that states the numbers (with units), times and names the tools returned."
)


def system_prompt(instructions: str | None) -> str:
    """Ours, then the MCP server's own instructions, as an MCP host (Claude Desktop, Cursor) gives them."""
    return f"{SYSTEM_PROMPT}\n\nThe MCP server's instructions:\n{instructions}" if instructions else SYSTEM_PROMPT


C = TypeVar("C")


@dataclass
class Chat(Generic[C]):
    """A provider's conversation so far: its SDK client, the model, the tools in the provider's format, the
    messages, and whether the images of tool answers are passed on."""

    client: C
    model: str
    tools: list[dict[str, Any]]
    messages: list[dict[str, Any]] = field(default_factory=list)
    images: bool = True


@dataclass(frozen=True)
class ProposedCall:
    """A tool call the model asked for; ``arguments`` is None when the model sent malformed JSON."""

    call_id: str
    name: str
    arguments: dict[str, Any] | None
    raw_arguments: str


@dataclass(frozen=True)
class ModelReply:
    text: str
    calls: tuple[ProposedCall, ...]
    input_tokens: int
    output_tokens: int


class Conversation(Protocol):
    async def reply(self) -> ModelReply:
        """The model's next turn over everything said so far."""

    def add_answers(self, answers: list[tuple[ProposedCall, ToolAnswer]]) -> None:
        """Hand the model the answers to the calls of its last reply."""


def parse_arguments(raw: str | dict[str, Any] | None) -> dict[str, Any] | None:
    """A call's arguments as an object, or None when they are not a JSON object."""
    if isinstance(raw, dict):
        return raw
    if not raw:
        return {}
    try:
        value = json.loads(raw)
    except ValueError:
        return None
    return value if isinstance(value, dict) else None


def refusal(body: object, fallback: str) -> str:
    """The message of a provider's error body (``{"error": {"message": ...}}``, or the inner object the OpenAI
    SDK keeps), else ``fallback``."""
    error = body.get("error", body) if isinstance(body, dict) else None
    message = error.get("message") if isinstance(error, dict) else None
    return str(message) if message else fallback
