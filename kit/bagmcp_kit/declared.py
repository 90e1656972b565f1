"""One declaration per tool: a tool is declared once, beside its query, and the kit derives the rest.

A ``Declared`` names the tool, its one params model (the arguments: their types, descriptions and bounds are
the model's fields, in the order the tool lists them), its result model, annotations, the function doing the
work and the one-line summary of a result. Long work also says how to tell small work (run inline, no job):
``small`` answers yes or no, or ``inline`` does small work itself and answers None for a job (when the
estimate and the work share what they open: one opening of a bag, one plot id).
From it the kit derives the MCP tool function (the signature the SDK reads, so the schemas are those of a
hand-written signature), the job kind (``<service>.<job>``) and its registration bound to the service's
resources, so adding a long-work tool is its declaration and its query function in one service folder.

``S`` is what the work needs from its service (the ``BagAccess``, or a small bundle of it and a store)."""

from __future__ import annotations

import inspect
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass, field
from typing import Annotated, Any, Generic, TypeVar, cast

import anyio
from mcp.server.mcpserver import Context
from mcp.types import CallToolResult, ContentBlock, ToolAnnotations
from pydantic import BaseModel, Field
from pydantic.fields import FieldInfo

from bagmcp_kit.answers import answer, tool_errors
from bagmcp_kit.arguments import READ_ONLY, ToolSpec, params_of
from bagmcp_kit.job_info import LongAnswer
from bagmcp_kit.longwork import LongWork
from bagmcp_shared.jobs import JobKind, JobRegistry, Progress, Unreported
from bagmcp_shared.tasks import TaskRef

S = TypeVar("S")
P = TypeVar("P", bound=BaseModel)
R = TypeVar("R", bound=BaseModel)
View = Callable[[Context, S, P, CallToolResult], Awaitable[CallToolResult]]


@dataclass(frozen=True)
class Declared(Generic[S, P, R]):
    """One tool. ``long``: the work may take long, so it runs as a job unless ``small`` says it is quick;
    ``job``: the job kind's name within its service (default: the tool's name); ``view``: a hook that adds
    what an MCP Apps viewer draws to a finished answer (the tool then points at the service's viewer);
    ``attach``: content added to a finished result, such as its image; ``given``: the values of the fields
    marked ``GIVEN`` that the server sets (from the caller's token or its own settings), never the caller."""

    name: str
    description: str
    params: type[P]
    result: type[R]
    work: Callable[[S, P, Progress], R]
    summary: Callable[[R], str]
    annotations: ToolAnnotations = field(default_factory=lambda: READ_ONLY)
    long: bool = True
    small: Callable[[S, P], bool] | None = None
    inline: Callable[[S, P], R | None] | None = None
    job: str | None = None
    view: View[S, P] | None = None
    attach: Callable[[S, R], list[ContentBlock]] | None = None
    given: Callable[[Context, S], dict[str, Any]] | None = None


class _Given:
    """Marks a params field that is no argument: the server sets it (``Declared.given``) or it keeps its default."""


GIVEN = _Given()


@dataclass(frozen=True)
class ServiceTools(Generic[S]):
    """A service's declared tools, in the order they are listed, and the queue their jobs run on."""

    service: str  # the job kinds' prefix, e.g. "analysis"
    task: TaskRef
    tools: tuple[Declared[S, Any, Any], ...]

    def kind(self, tool: Declared[S, P, R]) -> JobKind[P, R]:
        return JobKind(f"{self.service}.{tool.job or tool.name}", tool.params, tool.result, self.task)

    def registry(self, deps: S) -> JobRegistry:
        """Every long-work tool's job kind, bound to its work on ``deps``."""
        registry = JobRegistry()
        for tool in self.tools:
            if tool.long:
                registry.add(self.kind(tool), _bound(tool.work, deps))
        return registry

    def specs(self, deps: S, work: LongWork) -> list[ToolSpec]:
        """The MCP tools, each a function with the signature its params model describes."""
        return [_spec(tool, deps, self._long(tool, deps, work) if tool.long else None) for tool in self.tools]

    def _long(self, tool: Declared[S, P, R], deps: S, work: LongWork) -> LongRun[P]:
        """A long-work call: inline when small, else a job of the tool's kind."""
        small = None if tool.small is None else (lambda params: tool.small(deps, params))  # type: ignore[misc]
        inline = None if tool.inline is None else (lambda params: tool.inline(deps, params))  # type: ignore[misc]
        attach, kind = _attach(tool, deps), self.kind(tool)
        return lambda ctx, params: work.run(ctx, kind, params, tool.summary, small=small, inline=inline, attach=attach)


def short_specs(deps: S, tools: Sequence[Declared[S, Any, Any]]) -> list[ToolSpec]:
    """Tools that never run as jobs, outside any service's queue (the bag-store's reading tools on their own
    bundle, the jobs tools on the job store): each call runs in a worker thread."""
    if long := [tool.name for tool in tools if tool.long]:
        raise ValueError(f"{', '.join(long)}: long work needs a job kind; declare it in the service's ServiceTools")
    return [_spec(tool, deps, None) for tool in tools]


def _bound(work: Callable[[S, P, Progress], R], deps: S) -> Callable[[P, Progress], R]:
    return lambda params, progress: work(deps, params, progress)


Run = Callable[[Context, dict[str, object]], Awaitable[CallToolResult]]
LongRun = Callable[[Context, P], Awaitable[CallToolResult]]


def _attach(tool: Declared[S, P, R], deps: S) -> Callable[[R], list[ContentBlock]] | None:
    return None if tool.attach is None else (lambda result: tool.attach(deps, result))  # type: ignore[misc]


def _spec(tool: Declared[S, P, R], deps: S, long: LongRun[P] | None) -> ToolSpec:
    return ToolSpec(_function(tool, _runner(tool, deps, long)), tool.annotations, view=tool.view is not None)


def _runner(tool: Declared[S, P, R], deps: S, long: LongRun[P] | None) -> Run:
    """What a call does: its arguments (and the given fields) become the typed params; long work runs through
    ``long``, short work in a thread; then the view hook."""
    attach = _attach(tool, deps)

    async def run(ctx: Context, arguments: dict[str, object]) -> CallToolResult:
        with tool_errors():
            given = tool.given(ctx, deps) if tool.given is not None else {}
            typed = params_of(tool.params, **{**arguments, **given})
        if long is not None:
            done = await long(ctx, typed)
        else:
            done = await anyio.to_thread.run_sync(_short, tool, deps, typed, attach)
        return done if tool.view is None else await tool.view(ctx, deps, typed, done)

    return run


def _short(
    tool: Declared[S, P, R], deps: S, params: P, attach: Callable[[R], list[ContentBlock]] | None
) -> CallToolResult:
    with tool_errors():
        result = tool.work(deps, params, Unreported())
        extra = attach(result) if attach is not None else []
    return answer(result, tool.summary(result), extra=extra)


def _function(tool: Declared[Any, P, R], run: Run) -> Callable[..., Awaitable[CallToolResult]]:
    """An async function named after the tool whose signature (``ctx`` and one keyword per field of the params
    model, with the field's type, bounds and description) is what the SDK turns into the input schema."""
    fields = {name: info for name, info in tool.params.model_fields.items() if GIVEN not in info.metadata}

    async def call(ctx: Context, **arguments: object) -> CallToolResult:
        return await run(ctx, arguments)

    output = LongAnswer[tool.result] if tool.long else tool.result  # type: ignore[name-defined]
    returns = Annotated[CallToolResult, output]
    parameters = [inspect.Parameter("ctx", inspect.Parameter.POSITIONAL_OR_KEYWORD, annotation=Context)]
    parameters += [_parameter(info.alias or name, info) for name, info in fields.items()]
    call.__name__ = call.__qualname__ = tool.name
    call.__doc__ = tool.description
    call.__signature__ = inspect.Signature(parameters, return_annotation=returns)  # type: ignore[attr-defined]
    call.__annotations__ = {p.name: p.annotation for p in parameters} | {"return": returns}
    return call


def _parameter(name: str, info: FieldInfo) -> inspect.Parameter:
    """The field as a keyword parameter: its bounds and description in ``Annotated``, its default as the
    parameter's (pydantic refuses a default inside ``Annotated``)."""
    described = Field(description=info.description) if info.description else Field()
    annotation = cast(Any, Annotated)[(info.annotation, *info.metadata, described)]
    default = inspect.Parameter.empty if info.is_required() else info.get_default(call_default_factory=True)
    return inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, annotation=annotation, default=default)
