"""Anthropic's Messages API with tools, through the ``anthropic`` SDK. Tool answers go back as ``tool_result``
blocks holding the text and the images themselves (Claude sees plots)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import anthropic
from mcp.types import Tool

from bagmcp_lab.errors import ProviderError
from bagmcp_lab.providers.conversation import Chat, ModelReply, ProposedCall, refusal, system_prompt
from bagmcp_lab.providers.factory import Opening
from bagmcp_lab.toolbox import ToolAnswer

MAX_OUTPUT_TOKENS = 4096


def tool_specs(tools: Sequence[Tool]) -> list[dict[str, Any]]:
    return [{"name": t.name, "description": t.description or "", "input_schema": t.input_schema} for t in tools]


def _result_block(call: ProposedCall, answer: ToolAnswer, *, images: bool) -> dict[str, Any]:
    content: list[dict[str, Any]] = [{"type": "text", "text": answer.text or "(no text)"}]
    content += [
        {"type": "image", "source": {"type": "base64", "media_type": image.mime_type, "data": image.data_base64}}
        for image in (answer.images if images else ())
    ]
    return {"type": "tool_result", "tool_use_id": call.call_id, "content": content, "is_error": answer.is_error}


@dataclass
class AnthropicConversation(Chat[anthropic.AsyncAnthropic]):
    system: str = ""

    async def reply(self) -> ModelReply:
        try:
            response = await self.client.messages.create(
                model=self.model,
                max_tokens=MAX_OUTPUT_TOKENS,
                system=self.system,
                messages=self.messages,  # type: ignore[arg-type]
                tools=self.tools,  # type: ignore[arg-type]
            )
        except anthropic.APIStatusError as err:
            raise ProviderError(f"Anthropic answered {err.status_code}: {refusal(err.body, err.message)}") from None
        except anthropic.APIError as err:
            raise ProviderError(f"cannot reach Anthropic ({err.message}); check --base-url and the network") from None
        blocks = [block.model_dump(mode="json", exclude_none=True) for block in response.content]
        self.messages.append({"role": "assistant", "content": blocks})
        text = "\n".join(b["text"] for b in blocks if b.get("type") == "text")
        calls = tuple(
            ProposedCall(b["id"], b["name"], b["input"] if isinstance(b.get("input"), dict) else None, str(b["input"]))
            for b in blocks
            if b.get("type") == "tool_use"
        )
        usage = response.usage
        return ModelReply(text, calls, usage.input_tokens, usage.output_tokens)

    def add_answers(self, answers: list[tuple[ProposedCall, ToolAnswer]]) -> None:
        blocks = [_result_block(call, answer, images=self.images) for call, answer in answers]
        self.messages.append({"role": "user", "content": blocks})


def anthropic_conversation(opening: Opening) -> AnthropicConversation:
    choice = opening.choice
    client = anthropic.AsyncAnthropic(api_key=choice.api_key, base_url=choice.base_url, max_retries=2)
    messages = [{"role": role, "content": text} for role, text in opening.history]
    prompt = system_prompt(opening.instructions)
    return AnthropicConversation(client, choice.model, tool_specs(opening.tools), messages, choice.images, prompt)
