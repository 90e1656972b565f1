"""OpenAI-compatible chat completions with tools, through the ``openai`` SDK (OpenAI, Groq, Ollama, vLLM, LM
Studio via ``base_url``). Tool messages carry text only, so images follow in a user message as image parts
(``images=False`` for servers whose models take no images)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import openai
from mcp.types import Tool

from bagmcp_lab.errors import ProviderError
from bagmcp_lab.providers.conversation import (
    Chat,
    ModelReply,
    ProposedCall,
    parse_arguments,
    refusal,
    system_prompt,
)
from bagmcp_lab.providers.factory import Opening
from bagmcp_lab.toolbox import ToolAnswer


def tool_specs(tools: Sequence[Tool]) -> list[dict[str, Any]]:
    return [
        {
            "type": "function",
            "function": {"name": t.name, "description": t.description or "", "parameters": t.input_schema},
        }
        for t in tools
    ]


def _image_message(answers: list[tuple[ProposedCall, ToolAnswer]]) -> dict[str, Any] | None:
    parts: list[dict[str, Any]] = []
    for call, answer in answers:
        for image in answer.images:
            parts.append({"type": "text", "text": f"Image returned by {call.name} (call {call.call_id}):"})
            url = f"data:{image.mime_type};base64,{image.data_base64}"
            parts.append({"type": "image_url", "image_url": {"url": url}})
    return {"role": "user", "content": parts} if parts else None


class OpenAIConversation(Chat[openai.AsyncOpenAI]):
    async def reply(self) -> ModelReply:
        try:
            response = await self.client.chat.completions.create(
                model=self.model,
                messages=self.messages,  # type: ignore[arg-type]
                tools=self.tools,  # type: ignore[arg-type]
            )
        except openai.APIStatusError as err:
            said = refusal(err.body, err.message)
            raise ProviderError(f"the model server answered {err.status_code}: {said}") from None
        except openai.APIError as err:
            raise ProviderError(f"cannot reach the model server ({err.message}); check --base-url") from None
        if not response.choices:
            raise ProviderError(f"the model server sent no choices for model {self.model!r}")
        message = response.choices[0].message
        raw_calls = [c.model_dump(mode="json") for c in message.tool_calls or []]
        self.messages.append(
            {"role": "assistant", "content": message.content or "", **({"tool_calls": raw_calls} if raw_calls else {})}
        )
        calls = tuple(
            ProposedCall(
                c["id"], c["function"]["name"], parse_arguments(c["function"]["arguments"]), c["function"]["arguments"]
            )
            for c in raw_calls
        )
        usage = response.usage
        return ModelReply(
            message.content or "", calls, usage.prompt_tokens if usage else 0, usage.completion_tokens if usage else 0
        )

    def add_answers(self, answers: list[tuple[ProposedCall, ToolAnswer]]) -> None:
        for call, answer in answers:
            self.messages.append({"role": "tool", "tool_call_id": call.call_id, "content": answer.text or "(no text)"})
        if self.images and (images := _image_message(answers)) is not None:
            self.messages.append(images)


def openai_conversation(opening: Opening) -> OpenAIConversation:
    choice = opening.choice
    client = openai.AsyncOpenAI(api_key=choice.api_key, base_url=choice.base_url, max_retries=2)
    system = {"role": "system", "content": system_prompt(opening.instructions)}
    messages = [system, *({"role": r, "content": t} for r, t in opening.history)]
    return OpenAIConversation(client, choice.model, tool_specs(opening.tools), messages, choice.images)
