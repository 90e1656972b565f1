"""Where an MCP resource read goes: the upstreams' resources and resource templates, exposed under the same
rule as their tools, and a URI matched to the upstream that serves it.

An upstream without a prefix keeps its URIs as they are; one with a prefix has them exposed as
``prefix+uri`` (templates ``prefix+template``, names ``prefix__name``), and the resource links in its tool
answers and read results are rewritten to match, so every link a caller is given can be read through the
gateway. A URI (or template) two upstreams publish goes to the first in configuration order.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import mcp.types as types
from mcp.shared.uri_template import InvalidUriTemplate, UriTemplate

from bagmcp_gateway.upstreams.relay import WireResult
from bagmcp_gateway.upstreams.upstream import Upstream

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class UpstreamResources:
    """What one upstream publishes: fixed resources and templates, as it names them."""

    resources: list[types.Resource] = field(default_factory=list)
    templates: list[types.ResourceTemplate] = field(default_factory=list)


@dataclass(frozen=True)
class ResourceRoute:
    upstream: Upstream
    uri: str  # as the upstream knows it


def _parsed(template: str, upstream: Upstream) -> UriTemplate | None:
    try:
        return UriTemplate.parse(template)
    except InvalidUriTemplate as err:
        log.warning("upstream %s publishes a resource template the gateway cannot match: %s", upstream.name, err)
        return None


@dataclass
class ResourceRoutes:
    """The gateway's resource listing (exposed names) and the routes of a read, in configuration order."""

    resources: list[tuple[Upstream, types.Resource]] = field(default_factory=list)
    templates: list[tuple[Upstream, types.ResourceTemplate]] = field(default_factory=list)
    _exact: dict[str, ResourceRoute] = field(default_factory=dict)
    _matchers: list[tuple[Upstream, UriTemplate]] = field(default_factory=list)

    @classmethod
    def build(cls, published: Sequence[tuple[Upstream, UpstreamResources]]) -> ResourceRoutes:
        routes = cls()
        for upstream, found in published:
            for resource in found.resources:
                exposed = upstream.exposed_uri(resource.uri)
                if exposed in routes._exact:
                    log.warning("resource %s of %s is already served by another upstream", exposed, upstream.name)
                    continue
                routes._exact[exposed] = ResourceRoute(upstream, resource.uri)
                update = {"uri": exposed, "name": upstream.exposed(resource.name)}
                routes.resources.append((upstream, resource.model_copy(update=update)))
            for template in found.templates:
                matcher = _parsed(template.uri_template, upstream)
                if matcher is not None:
                    routes._matchers.append((upstream, matcher))
                    update = {"uri_template": upstream.exposed_uri(template.uri_template)}
                    update["name"] = upstream.exposed(template.name)
                    routes.templates.append((upstream, template.model_copy(update=update)))
        return routes

    def route(self, uri: str) -> ResourceRoute | None:
        """The upstream serving ``uri`` (a fixed resource first, then the templates in order), or None."""
        if (exact := self._exact.get(uri)) is not None:
            return exact
        for upstream, matcher in self._matchers:
            original = upstream.original_uri(uri)
            if original is not None and matcher.match(original) is not None:
                return ResourceRoute(upstream, original)
        return None

    def uris(self) -> list[str]:
        """Every exposed URI and template, to notice a change."""
        return [r.uri for _, r in self.resources] + [t.uri_template for _, t in self.templates]


def _exposed_block(block: Any, upstream: Upstream) -> Any:
    if not isinstance(block, dict):
        return block
    if block.get("type") == "resource_link" and isinstance(block.get("uri"), str):
        return {**block, "uri": upstream.exposed_uri(block["uri"])}
    inner = block.get("resource")
    if block.get("type") == "resource" and isinstance(inner, dict) and isinstance(inner.get("uri"), str):
        return {**block, "resource": {**inner, "uri": upstream.exposed_uri(inner["uri"])}}
    return block


def with_exposed_links(result: WireResult, upstream: Upstream) -> WireResult:
    """A tool answer of ``upstream`` whose resource links name the URIs the gateway exposes."""
    content = result.get("content")
    if not upstream.prefix or not isinstance(content, list):
        return result
    return {**result, "content": [_exposed_block(block, upstream) for block in content]}


def with_exposed_contents(result: WireResult, upstream: Upstream) -> WireResult:
    """A read result of ``upstream`` whose contents name the URIs the gateway exposes."""
    contents = result.get("contents")
    if not upstream.prefix or not isinstance(contents, list):
        return result
    exposed = [
        {**item, "uri": upstream.exposed_uri(item["uri"])}
        if isinstance(item, dict) and isinstance(item.get("uri"), str)
        else item
        for item in contents
    ]
    return {**result, "contents": exposed}
