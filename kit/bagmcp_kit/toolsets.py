"""Tool classes for short tools: methods marked with their annotations, found and registered in the order they
are written. Long work is declared instead (declared.py), which derives its tool, job kind and registration."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from mcp.types import ToolAnnotations

from bagmcp_kit.arguments import ToolSpec

F = TypeVar("F", bound=Callable[..., object])
_MARK = "__bagmcp_tool__"
_VIEW = "__bagmcp_view__"


def tool(annotations: ToolAnnotations, *, view: bool = False) -> Callable[[F], F]:
    """Mark a method as a tool with these annotations (its docstring is the description); ``view``: its
    answers carry view data, and it points MCP Apps clients at the service's viewer (kit/web/viewers.py)."""

    def mark(fn: F) -> F:
        setattr(fn, _MARK, annotations)
        setattr(fn, _VIEW, view)
        return fn

    return mark


def tools_of(*groups: object) -> list[ToolSpec]:
    """The marked methods of each object, bound to it, in the order the classes define them (a ``ToolSpec``,
    such as a declared tool's, is taken as it is)."""
    specs = []
    for group in groups:
        if isinstance(group, ToolSpec):
            specs.append(group)
            continue
        for cls in reversed(type(group).__mro__):
            for name, member in vars(cls).items():
                if isinstance(annotations := getattr(member, _MARK, None), ToolAnnotations):
                    specs.append(ToolSpec(getattr(group, name), annotations, view=getattr(member, _VIEW, False)))
    return specs
