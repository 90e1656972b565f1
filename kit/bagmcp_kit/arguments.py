"""The argument types and annotations tools share, stated once, and registering a service's tools.

Conventions (bags, times, message paths) are explained once in each server's instructions, so
argument descriptions stay one line.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Annotated, Any, TypeVar

from mcp.server.context import CallNext, HandlerResult, ServerRequestContext
from mcp.server.mcpserver import Context, MCPServer
from mcp.types import CallToolResult, TextContent, ToolAnnotations
from pydantic import BaseModel, Field, ValidationError

from bagmcp_kit.schemas import Schema, lean_input, lean_output
from bagmcp_shared.errors import ArgumentError

BagRef = Annotated[str, Field(description="bag id or name")]
TopicName = Annotated[str, Field(description="e.g. /odom")]
TimeArg = Annotated[float | str, Field(description="s from start, or ISO")]
Offset = Annotated[int, Field(ge=0, description="first item to return (paging)")]
Fields = Annotated[list[str] | None, Field(description="paths to keep, e.g. ['pose.pose.position.x']")]
OptionalTopic = Annotated[str | None, Field(description="default: the obvious one")]

CONVENTIONS = (
    "Bags: `bag` is an id, a name or a unique prefix (see list_bags). "
    "Times: numbers below 1e9 are seconds from the bag start, larger numbers epoch seconds, or ISO-8601; "
    "answers give both offset_s and the absolute stamp, and say which clock they use. "
    "Message paths: field.sub[index], e.g. pose.pose.position.x or ranges[0]; quaternions offer roll/pitch/yaw. "
    "An omitted topic is the obvious one for the tool (the answer names it)."
)

READ_ONLY = ToolAnnotations(read_only_hint=True, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
WRITES = ToolAnnotations(read_only_hint=False, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
STOPS = ToolAnnotations(read_only_hint=False, destructive_hint=True, idempotent_hint=True, open_world_hint=False)


M = TypeVar("M", bound=BaseModel)


def params_of(model: type[M], **values: object) -> M:
    """A tool's arguments as the typed parameters of its work; a value out of range is an ArgumentError."""
    try:
        return model.model_validate(values)
    except ValidationError as err:
        problem = err.errors()[0]
        where = ".".join(str(p) for p in problem["loc"])
        raise ArgumentError(f"{where}: {problem['msg']}") from err


@dataclass(frozen=True)
class ToolSpec:
    """One tool: the function (a bound method whose docstring is the description) and its annotations."""

    fn: Callable[..., object]
    annotations: ToolAnnotations
    view: bool = False  # drawn by the service's MCP Apps viewer


def _argument_names(fn: Callable[..., object]) -> frozenset[str]:
    hints = inspect.get_annotations(fn, eval_str=True)
    return frozenset(n for n in inspect.signature(fn).parameters if hints.get(n) is not Context)


def register(server: MCPServer, specs: Iterable[ToolSpec], *, viewer_meta: dict[str, Any] | None = None) -> None:
    """Add the tools (those with a view carrying ``viewer_meta``), and refuse calls that pass arguments a tool
    does not have (naming the valid ones)."""
    known: dict[str, frozenset[str]] = {}
    for spec in specs:
        description = " ".join((spec.fn.__doc__ or "").split())
        meta = viewer_meta if spec.view else None
        server.add_tool(spec.fn, description=description, annotations=spec.annotations, meta=meta)
        known[spec.fn.__name__] = _argument_names(spec.fn)

    async def unknown_arguments(ctx: ServerRequestContext[Any, Any], call_next: CallNext) -> HandlerResult:
        params = ctx.params if isinstance(ctx.params, dict) else {}
        valid = known.get(str(params.get("name"))) if ctx.method == "tools/call" else None
        arguments = params.get("arguments")
        if valid is not None and isinstance(arguments, dict) and (extra := sorted(set(arguments) - valid)):
            names = ", ".join(sorted(valid)) or "(none)"
            text = f"unknown argument(s) {', '.join(extra)} for {params['name']}; valid arguments: {names}"
            return CallToolResult(content=[TextContent(type="text", text=text)], is_error=True)
        return await call_next(ctx)

    server.middleware.append(unknown_arguments)
    server.middleware.append(_lean_listing())


def _lean_listing() -> Any:
    """Serve tools/list with lean schemas, each computed once."""
    done: dict[str, tuple[Schema, Schema | None]] = {}

    async def lean(ctx: ServerRequestContext[Any, Any], call_next: CallNext) -> HandlerResult:
        result = await call_next(ctx)
        if ctx.method != "tools/list" or not isinstance(result, dict):
            return result
        for tool in result.get("tools", []):
            name = tool["name"]
            if name not in done:
                output = tool.get("outputSchema")
                done[name] = (lean_input(tool["inputSchema"]), lean_output(output) if output else None)
            tool["inputSchema"], output_schema = done[name]
            if output_schema is not None:
                tool["outputSchema"] = output_schema
        return result

    return lean
