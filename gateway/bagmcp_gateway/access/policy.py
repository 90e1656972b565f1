"""Which tools a caller sees and may call: the gateway's global enable list, the token's profile and its
allow/deny globs, and the scope a tool needs. Checked in tools/list and again in tools/call. The glob
decisions are pure functions of names and lists, so they are remembered (a call matches no glob again).

Resources follow the tools: an upstream's resources are readable (and listed) for a caller holding the
``read`` scope that may call at least one of that upstream's tools. A token that may not call any plotting
tool cannot read plot artifacts either (REST reads follow the same rule: rest_policy.py).

A profile name this server does not know (a replica configured without it, a JWT claim with a typo) grants no
tool at all, and a call is refused saying so."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fnmatch import fnmatchcase
from functools import lru_cache

import mcp.types as types
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.lean import lean_tools
from bagmcp_gateway.access.profiles import DEFAULT_PROFILES, NO_TOOLS, Profile
from bagmcp_gateway.access.tokens.models import SCOPES


def _any(name: str, globs: Sequence[str]) -> bool:
    return any(fnmatchcase(name, g) for g in globs)


@lru_cache(maxsize=8192)
def _enabled(name: str, enabled: tuple[str, ...], disabled: tuple[str, ...]) -> bool:
    return _any(name, enabled) and not _any(name, disabled)


@lru_cache(maxsize=8192)
def _granted(name: str, profile: tuple[str, ...] | None, allow: tuple[str, ...], deny: tuple[str, ...]) -> bool:
    if profile is not None and not _any(name, profile):
        return False
    return not ((allow and not _any(name, allow)) or _any(name, deny))


def needed_scope(tool: types.Tool) -> str:
    """Tools that create things (not read-only, not destructive: filter_bag) need ``upload``; the rest ``read``."""
    hints = tool.annotations
    creates = hints is not None and hints.read_only_hint is False and hints.destructive_hint is False
    return "upload" if creates else "read"


@dataclass(frozen=True)
class ToolPolicy:
    enabled: tuple[str, ...] = ("*",)
    disabled: tuple[str, ...] = ()
    profiles: Mapping[str, Profile] = field(default_factory=lambda: dict(DEFAULT_PROFILES))

    def profile_of(self, caller: AccessToken | None) -> Profile | None:
        """The caller's profile; None when it names none (every enabled tool); NO_TOOLS for an unknown one."""
        name = (caller.claims or {}).get("profile") if caller is not None else None
        return self.profiles.get(str(name), NO_TOOLS) if name else None

    def unknown_profile(self, caller: AccessToken | None) -> str | None:
        """The profile name ``caller`` carries that this server does not know, or None."""
        name = (caller.claims or {}).get("profile") if caller is not None else None
        return str(name)[:64] if name and str(name) not in self.profiles else None

    def allows(self, tool: types.Tool, caller: AccessToken | None) -> bool:
        """Whether ``caller`` (None: no authentication, a local user) may see and call ``tool``."""
        if not _enabled(tool.name, self.enabled, self.disabled):
            return False
        if caller is None:
            return True
        claims = caller.claims or {}
        profile = self.profile_of(caller)
        allow, deny = tuple(claims.get("allow") or ()), tuple(claims.get("deny") or ())
        if not _granted(tool.name, profile.tools if profile is not None else None, allow, deny):
            return False
        return needed_scope(tool) in caller.scopes

    def refusal(self, tool: types.Tool, caller: AccessToken | None) -> str:
        """Why ``caller`` may not call ``tool``, saying what to do when a scope is all it lacks."""
        if (unknown := self.unknown_profile(caller)) is not None:
            return (
                f"this token's tool profile {unknown!r} is not one this server knows "
                f"({', '.join(sorted(self.profiles))}), so it may call no tool; ask an admin for a token with a "
                "known profile"
            )
        scope = needed_scope(tool)
        if caller is not None and scope not in caller.scopes:
            widened = caller.model_copy(update={"scopes": [*caller.scopes, scope]})
            if self.allows(tool, widened):
                return (
                    f"{tool.name} needs the {scope} scope, which this token lacks; an admin can make a token that "
                    f"has it: bagmcp token create NAME --scopes read,{scope}"
                )
        return f"{tool.name} is not enabled for this token (its profile or allow/deny lists)"

    def may_read(self, upstream_tools: Sequence[types.Tool], caller: AccessToken | None) -> bool:
        """Whether ``caller`` may list and read the resources of the upstream publishing ``upstream_tools``."""
        if caller is not None and "read" not in caller.scopes:
            return False
        return any(self.allows(tool, caller) for tool in upstream_tools)

    def callable_names(self, tools: Sequence[types.Tool], caller: AccessToken | None) -> list[str] | None:
        """The names of ``tools`` ``caller`` may call, or None when that is all of them (services show a
        restricted token only what its tools would: answers across bags leave out what it may not read)."""
        names = [t.name for t in tools if self.allows(t, caller)]
        return None if len(names) == len(tools) else names

    def shown(self, tools: Sequence[types.Tool], caller: AccessToken | None) -> list[types.Tool]:
        """The tools ``caller`` may use, as its profile lists them."""
        lean = (profile := self.profile_of(caller)) is not None and profile.lean
        visible = [t for t in tools if self.allows(t, caller)]
        return lean_tools(visible) if lean else visible

    def profile_listing(self, tools: Sequence[types.Tool], profile: str) -> list[types.Tool]:
        """What a token of ``profile`` holding every scope is shown."""
        claims = {"profile": profile}
        caller = AccessToken(token="-", client_id=f"profile-{profile}", scopes=list(SCOPES), claims=claims)
        return self.shown(tools, caller)


def _wire(tool: types.Tool) -> dict[str, object]:
    return tool.model_dump(mode="json", by_alias=True, exclude_none=True)


def tool_characters(tool: types.Tool) -> int:
    """One tool's size in a tools/list answer (compact JSON)."""
    return len(json.dumps(_wire(tool), separators=(",", ":")))


def listing_characters(tools: Sequence[types.Tool]) -> int:
    """The size of a whole tools/list answer holding ``tools``, as it is sent (compact JSON)."""
    return len(json.dumps({"tools": [_wire(t) for t in tools]}, separators=(",", ":")))
