"""The agent loop: the model proposes tool calls, they run through MCP, their answers go back, until the model
answers in text or runs out of turns. Every call is recorded as the benchmark reports it."""

from __future__ import annotations

import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any

from mcp.shared.dispatcher import ProgressFnT

from bagmcp_lab.providers.conversation import Conversation, ProposedCall
from bagmcp_lab.toolbox import ToolAnswer, ToolBox

DEFAULT_MAX_TURNS = 10


@dataclass(frozen=True)
class CallRecord:
    """One tool call as results.json lists it (``arguments`` is the raw text when it was not JSON)."""

    name: str
    arguments: dict[str, Any] | str
    ms: float
    is_error: bool

    def as_json(self) -> dict[str, Any]:
        return {"name": self.name, "arguments": self.arguments, "ms": round(self.ms, 1), "is_error": self.is_error}


@dataclass
class AgentOutcome:
    final_answer: str = ""
    calls: list[CallRecord] = field(default_factory=list)
    answers: list[ToolAnswer] = field(default_factory=list)
    input_tokens: int = 0
    output_tokens: int = 0
    latency_s: float = 0.0
    turns: int = 0
    stopped: str | None = None  # why the loop ended without a final answer


@dataclass(frozen=True)
class AgentEvent:
    """What a watcher (the Lab page) is told: ``kind`` is text, call, answer or progress."""

    kind: str
    data: dict[str, Any]


Watcher = Callable[[AgentEvent], Awaitable[None]]


async def _ignore(_event: AgentEvent) -> None:
    return None


def _malformed(call: ProposedCall) -> ToolAnswer:
    text = f"the arguments of {call.name} are not a JSON object ({call.raw_arguments[:200]!r}); send a JSON object"
    return ToolAnswer(call.name, {}, text, (), None, True, 0.0)


async def _run_call(box: ToolBox, call: ProposedCall, watch: Watcher) -> ToolAnswer:
    await watch(AgentEvent("call", {"id": call.call_id, "name": call.name, "arguments": call.arguments}))
    if call.arguments is None:
        return _malformed(call)

    async def progress(progress: float, total: float | None, message: str | None) -> None:
        await watch(AgentEvent("progress", {"id": call.call_id, "done": progress, "total": total, "message": message}))

    relay: ProgressFnT = progress
    return await box.call(call.name, call.arguments, progress=relay)


async def run_agent(
    conversation: Conversation, box: ToolBox, *, max_turns: int = DEFAULT_MAX_TURNS, watch: Watcher = _ignore
) -> AgentOutcome:
    """Run the loop to a final answer (or ``max_turns`` model replies)."""
    outcome = AgentOutcome()
    started = time.perf_counter()
    try:
        for _ in range(max_turns):
            reply = await conversation.reply()
            outcome.turns += 1
            outcome.input_tokens += reply.input_tokens
            outcome.output_tokens += reply.output_tokens
            if reply.text:
                await watch(AgentEvent("text", {"text": reply.text, "final": not reply.calls}))
            if not reply.calls:
                outcome.final_answer = reply.text
                return outcome
            answered = []
            for call in reply.calls:
                answer = await _run_call(box, call, watch)
                arguments = call.arguments if call.arguments is not None else call.raw_arguments
                outcome.calls.append(CallRecord(call.name, arguments, answer.ms, answer.is_error))
                outcome.answers.append(answer)
                answered.append((call, answer))
                await watch(AgentEvent("answer", _answer_event(call, answer)))
            conversation.add_answers(answered)
        outcome.stopped = f"no final answer within {max_turns} turns"
        return outcome
    finally:
        outcome.latency_s = time.perf_counter() - started


def _answer_event(call: ProposedCall, answer: ToolAnswer) -> dict[str, Any]:
    images = [{"mime_type": i.mime_type, "data": i.data_base64} for i in answer.images]
    return {
        "id": call.call_id,
        "name": call.name,
        "ms": round(answer.ms, 1),
        "is_error": answer.is_error,
        "text": answer.text[:4000],
        "structured": answer.structured,
        "images": images,
    }
