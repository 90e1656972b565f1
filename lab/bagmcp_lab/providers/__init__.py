"""Model providers through their official SDKs: Anthropic's Messages API and OpenAI-compatible chat completions
(OpenAI, Groq, Ollama, vLLM, LM Studio through a base URL)."""

from bagmcp_lab.providers.conversation import Conversation, ModelReply, ProposedCall
from bagmcp_lab.providers.factory import PROVIDERS, ProviderChoice, open_conversation

__all__ = ["PROVIDERS", "Conversation", "ModelReply", "ProposedCall", "ProviderChoice", "open_conversation"]
