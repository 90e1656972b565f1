"""A chat turn for the page: the agent loop over the caller's tools, each step streamed as one JSON line (the
model's text, a tool call with its arguments, the answer with its time, text and images, progress of long
work), then the final answer with token counts. The key is used for this turn and dropped."""

from __future__ import annotations

import json
from collections.abc import AsyncIterator
from typing import Any

import anyio
from pydantic import BaseModel, Field

from bagmcp_lab.agent import AgentEvent, run_agent
from bagmcp_lab.errors import LabError
from bagmcp_lab.providers import ProviderChoice, open_conversation
from bagmcp_lab.server.keys import ModelRequest
from bagmcp_lab.server.service import Caller, LabService
from bagmcp_lab.toolbox import open_toolbox


class ChatLine(BaseModel):
    role: str = Field(pattern="^(user|assistant)$")
    text: str = Field(max_length=20_000)


class ChatRequest(ModelRequest):
    prompt: str = Field(min_length=1, max_length=20_000)
    history: list[ChatLine] = Field(default_factory=list, max_length=40)
    max_turns: int = Field(default=10, ge=1, le=30)


def _line(kind: str, data: dict[str, Any]) -> bytes:
    return (json.dumps({"kind": kind, **data}) + "\n").encode()


async def chat_lines(
    lab: LabService, caller: Caller, choice: ProviderChoice, request: ChatRequest
) -> AsyncIterator[bytes]:
    """The turn's events as JSON lines; the caller's place (see RunRegistry) is given back at the end."""
    send, receive = anyio.create_memory_object_stream[bytes](256)

    async def watch(event: AgentEvent) -> None:
        await send.send(_line(event.kind, event.data))

    async def produce() -> None:
        async with send:
            try:
                async with open_toolbox(lab.target.url, token=caller.token, transport=lab.target.transport()) as box:
                    await send.send(_line("tools", {"names": [t.name for t in box.tools]}))
                    history = [(line.role, line.text) for line in request.history] + [("user", request.prompt)]
                    conversation = open_conversation(choice, box.tools, history, instructions=box.instructions)
                    outcome = await run_agent(conversation, box, max_turns=request.max_turns, watch=watch)
                done = {
                    "final_answer": outcome.final_answer,
                    "stopped": outcome.stopped,
                    "input_tokens": outcome.input_tokens,
                    "output_tokens": outcome.output_tokens,
                    "latency_s": round(outcome.latency_s, 3),
                    "tool_calls": [c.as_json() for c in outcome.calls],
                }
                await send.send(_line("done", done))
            except LabError as err:
                await send.send(_line("error", {"message": str(err)}))

    try:
        async with anyio.create_task_group() as group, receive:
            group.start_soon(produce)
            async for line in receive:
                yield line
    finally:
        lab.registry.release(caller.owner)
