"""Named tool profiles: the built-in ``full`` and ``core`` (for small models), as plain data.

Kept apart from policy.py, which needs the MCP types, so the command line can offer the profile names
without importing the SDK (`bagmcp --help` in 0.3 s instead of 2.3 s)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

CORE_TOOLS = (  # the paper's ten tasks, each in one or two calls (tests/checks/paper_tasks.py)
    "list_bags",
    "bag_info",
    "search_messages",
    "filter_bag",
    "analyze_trajectory",
    "analyze_lidar_scan",
    "get_tf_tree",
    "plot_timeseries",
    "plot_2d",
    "plot_lidar_scan",
    "plot_histogram",
    "get_job",  # core tools may answer with a job: follow it (cancel_job is in full)
)


@dataclass(frozen=True)
class Profile:
    """A named set of tools (globs); ``lean`` lists them as lean.py says, for small models."""

    tools: tuple[str, ...]
    lean: bool = False


NO_TOOLS = Profile(())  # what a profile name this server does not know grants: nothing (a typo is not "full")
DEFAULT_PROFILES: Mapping[str, Profile] = {"full": Profile(("*",)), "core": Profile(CORE_TOOLS, lean=True)}
PROFILE_NAMES = tuple(DEFAULT_PROFILES)

__all__ = ["CORE_TOOLS", "DEFAULT_PROFILES", "NO_TOOLS", "PROFILE_NAMES", "Profile"]
