"""How several time series share axes: one axis, twin y axes, or stacked panels.

Lines are grouped by unit; within a unit, lines whose magnitudes (max |y|) differ by more than
MAGNITUDE_RATIO_LIMIT go to separate groups. One group -> "single"; two groups of similar magnitude ->
"twin"; otherwise -> "stacked" (one panel per group).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

from bagmcp_plotting.drawing.lines import Line, magnitude_of

Layout = Literal["single", "twin", "stacked"]
MAGNITUDE_RATIO_LIMIT = 20.0


def group_indices(lines: Sequence[Line]) -> list[list[int]]:
    """Indices of lines drawn on the same axis, groups ordered by their first line."""
    magnitudes = [magnitude_of(line) for line in lines]
    by_unit: dict[str | None, list[int]] = {}
    for index, line in enumerate(lines):
        by_unit.setdefault(line.unit, []).append(index)
    groups: list[list[int]] = []
    for members in by_unit.values():
        groups.extend(_split_by_magnitude(members, magnitudes))
    return sorted(groups, key=min)


def layout_for(lines: Sequence[Line]) -> Layout:
    """'single', 'twin' or 'stacked' for these lines (see the module docstring)."""
    groups = group_indices(lines)
    if len(groups) <= 1:
        return "single"
    if len(groups) >= 3:
        return "stacked"
    magnitudes = [_group_magnitude(group, lines) for group in groups]
    low, high = magnitudes
    if low is not None and high is not None and max(low, high) > MAGNITUDE_RATIO_LIMIT * min(low, high):
        return "stacked"
    return "twin"


def _split_by_magnitude(members: list[int], magnitudes: list[float | None]) -> list[list[int]]:
    """Clusters of one unit's lines whose magnitudes stay within the ratio limit of the cluster's smallest."""
    known = sorted((index for index in members if magnitudes[index] is not None), key=lambda i: magnitudes[i] or 0.0)
    clusters: list[list[int]] = []
    base = 0.0
    for index in known:
        magnitude = magnitudes[index] or 0.0
        if clusters and magnitude <= MAGNITUDE_RATIO_LIMIT * base:
            clusters[-1].append(index)
        else:
            clusters.append([index])
            base = magnitude
    unknown = [index for index in members if magnitudes[index] is None]
    if not clusters:
        return [sorted(unknown)]
    clusters[0].extend(unknown)
    return [sorted(cluster) for cluster in clusters]


def _group_magnitude(group: list[int], lines: Sequence[Line]) -> float | None:
    known = [m for m in (magnitude_of(lines[index]) for index in group) if m is not None]
    return max(known) if known else None
