"""How the gateway exposes and routes upstream resources (the prefix rule of tools), who may read them
(the read scope and one enabled tool of their upstream), and answers cut in their wire form."""

from __future__ import annotations

from mcp.server.auth.provider import AccessToken
from mcp.types import Resource, ResourceTemplate, Tool, ToolAnnotations

from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_gateway.mcp_front.wire_answers import cap_answer, error_result, text_characters
from bagmcp_gateway.upstreams.resource_routes import ResourceRoutes, UpstreamResources, with_exposed_links
from bagmcp_gateway.upstreams.upstream import Upstream

PLOTTING = Upstream(name="plotting", url="http://plotting/mcp")
WEATHER = Upstream(name="weather", url="http://weather/mcp", prefix="wx")
COPY = Upstream(name="copy", url="http://copy/mcp")
PLOTS = ResourceTemplate(name="plot", uri_template="bagmcp://artifacts/{artifact}", mime_type="image/png")
FORECAST = Resource(name="forecast", uri="weather://today")
STATIONS = ResourceTemplate(name="station", uri_template="weather://stations/{id}")


def _routes() -> ResourceRoutes:
    return ResourceRoutes.build(
        [
            (PLOTTING, UpstreamResources(templates=[PLOTS])),
            (WEATHER, UpstreamResources([FORECAST], [STATIONS])),
            (COPY, UpstreamResources(templates=[PLOTS])),
        ]
    )


def test_an_unprefixed_upstream_keeps_its_uris_and_the_first_of_two_serves_a_shared_template() -> None:
    routes = _routes()
    found = routes.route("bagmcp://artifacts/4db3d9a9")
    assert found is not None
    assert (found.upstream.name, found.uri) == ("plotting", "bagmcp://artifacts/4db3d9a9")
    assert routes.route("bagmcp://elsewhere/4db3d9a9") is None


def test_a_prefixed_upstream_s_uris_and_names_carry_its_prefix_and_route_back_to_its_own() -> None:
    routes = _routes()
    assert [(u.name, r.uri, r.name) for u, r in routes.resources] == [("weather", "wx+weather://today", "wx__forecast")]
    templates = [(u.name, t.uri_template, t.name) for u, t in routes.templates]
    assert ("weather", "wx+weather://stations/{id}", "wx__station") in templates
    today = routes.route("wx+weather://today")
    station = routes.route("wx+weather://stations/42")
    assert today is not None
    assert station is not None
    assert (today.upstream.name, today.uri) == ("weather", "weather://today")
    assert (station.upstream.name, station.uri) == ("weather", "weather://stations/42")
    assert routes.route("weather://today") is None  # only under its exposed name


def test_links_in_a_prefixed_upstream_s_answer_are_rewritten_and_others_left_alone() -> None:
    answer = {
        "content": [
            {"type": "text", "text": "see the link"},
            {"type": "resource_link", "uri": "weather://stations/42", "name": "42"},
            {"type": "resource", "resource": {"uri": "weather://today", "text": "sunny"}},
        ]
    }
    exposed = with_exposed_links(answer, WEATHER)
    assert [b.get("uri") or b.get("resource", {}).get("uri") for b in exposed["content"][1:]] == [
        "wx+weather://stations/42",
        "wx+weather://today",
    ]
    assert with_exposed_links(answer, PLOTTING) is answer


def _tool(name: str) -> Tool:
    return Tool(name=name, input_schema={"type": "object"}, annotations=ToolAnnotations(read_only_hint=True))


def _token(scopes: list[str], **claims: object) -> AccessToken:
    return AccessToken(token="-", client_id="someone", scopes=scopes, claims=claims)


def test_resources_are_readable_with_the_read_scope_and_one_enabled_tool_of_their_upstream() -> None:
    policy, plotting = ToolPolicy(), [_tool("plot_2d"), _tool("plot_timeseries")]
    assert policy.may_read(plotting, None)
    assert policy.may_read(plotting, _token(["read"]))
    assert policy.may_read(plotting, _token(["read"], allow=["plot_2d"]))
    assert not policy.may_read(plotting, _token(["upload"]))
    assert not policy.may_read(plotting, _token(["read"], deny=["plot_*"]))
    assert not policy.may_read(plotting, _token(["read"], profile="core", allow=["bag_info"]))
    assert not ToolPolicy(disabled=("plot_*",)).may_read(plotting, _token(["read"]))
    assert not policy.may_read([], _token(["read"]))  # an upstream with no tools has nothing to read here


def test_an_answer_is_cut_at_the_cap_in_its_wire_form_with_a_note_and_whole_structured_content() -> None:
    answer = {
        "content": [
            {"type": "text", "text": "a" * 30},
            {"type": "image", "data": "xx"},
            {"type": "text", "text": "b" * 30},
        ],
        "structuredContent": {"rows": list(range(50))},
    }
    cut = cap_answer(answer, max_chars=40)
    texts = [b["text"] for b in cut["content"] if b["type"] == "text"]
    assert texts[:2] == ["a" * 30, "b" * 10]
    assert "answer cut at 40 of 60 characters" in texts[2]
    assert cut["structuredContent"] == {"rows": list(range(50))}
    assert cap_answer(answer, max_chars=60) is answer
    assert text_characters(error_result("nope", retryAfterSeconds=1.5)) == 4
    assert error_result("nope", retryAfterSeconds=1.5)["structuredContent"] == {"retryAfterSeconds": 1.5}
