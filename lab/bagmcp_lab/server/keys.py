"""Which key and model server a page request uses: the key the page sent (for this request only), or the
operator's key with the operator's base URL. A caller's base URL must match the configured prefixes, so the
server never posts a key (or anything) to a host the operator did not allow."""

from __future__ import annotations

from pydantic import BaseModel, Field

from bagmcp_lab.errors import KeyMissingError, LabError
from bagmcp_lab.providers import PROVIDERS, ProviderChoice
from bagmcp_lab.settings import ANY_BASE_URL, LabSettings


class ModelRequest(BaseModel):
    """What the page sends to choose a model. ``api_key`` is used for this request and dropped."""

    provider: str = Field(description="anthropic or openai")
    model: str = Field(min_length=1, max_length=200)
    base_url: str | None = Field(default=None, max_length=500)
    api_key: str | None = Field(default=None, max_length=500, repr=False)
    images: bool = True


def _allowed(base_url: str, prefixes: tuple[str, ...]) -> bool:
    return any(p == ANY_BASE_URL or base_url.startswith(p) for p in prefixes)


def choose_model(request: ModelRequest, settings: LabSettings) -> ProviderChoice:
    if request.provider not in PROVIDERS:
        raise LabError(f"unknown provider {request.provider!r}; use one of {', '.join(PROVIDERS)}")
    if request.api_key:
        if request.base_url is not None and not _allowed(request.base_url, settings.base_urls):
            allowed = ", ".join(settings.base_urls) or "none"
            raise LabError(f"this server may not call {request.base_url}; allowed base URLs start with: {allowed}")
        return ProviderChoice(request.provider, request.model, request.api_key, request.base_url, request.images)
    operator = settings.operator_keys.get(request.provider)
    if operator is None:
        raise KeyMissingError(f"type your {request.provider} API key: this server has no operator key for it")
    if request.base_url is not None and request.base_url != operator.base_url:
        raise LabError("the operator's key is used only with the operator's model server; leave the base URL empty")
    return ProviderChoice(request.provider, request.model, operator.api_key, operator.base_url, request.images)
