"""TF frames and transforms: TfSample input, TfBuffer with tree summary (TfTree/Edge) and tf2-style lookup."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from bagmcp_analysis.tf.edges import EdgeSeries, nearest_ns, parents_at, rate_hz
from bagmcp_analysis.tf.lookup import Lookup, lookup_transform
from bagmcp_shared.carry import carried
from bagmcp_shared.index.transforms import is_finite_sample, normalize_frame

__all__ = ["Edge", "Lookup", "TfBuffer", "TfSample", "TfTree", "normalize_frame"]


@dataclass(frozen=True)
class TfSample:
    """One transform T_parent_child (child pose in parent); rotation is x, y, z, w."""

    t_ns: int
    parent: str
    child: str
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    static: bool


@dataclass(frozen=True)
class Edge:
    """Summary of one parent -> child edge; rate_hz is None for static edges or fewer than two samples."""

    parent: str
    child: str
    static: bool
    count: int
    rate_hz: float | None
    first_ns: int
    last_ns: int
    nearest_ns: int | None


@dataclass(frozen=True)
class TfTree:
    """Frames, roots, edges (in tree order) and children published under several parents."""

    frames: list[str]
    roots: list[str]
    edges: list[Edge]
    multiple_parents: dict[str, list[str]]
    order: list[str]
    ignored_samples: int


def _series(parent: str, child: str, samples: list[TfSample]) -> EdgeSeries:
    samples.sort(key=lambda s: s.t_ns)
    return EdgeSeries(
        parent=parent,
        child=child,
        static=any(s.static for s in samples),
        t_ns=np.array([s.t_ns for s in samples], dtype=np.int64),
        translations=np.array([s.translation for s in samples], dtype=np.float64).reshape(-1, 3),
        rotations=np.array([s.rotation for s in samples], dtype=np.float64).reshape(-1, 4),
    )


def _depth_order(frames: list[str], parents: dict[str, str]) -> list[str]:
    """Frames sorted by depth below their root, then by name; frames caught in a parent loop come last."""
    depth: dict[str, int] = {}
    for frame in frames:
        path = [frame]
        while path[-1] in parents and path[-1] not in depth and len(path) <= len(frames):
            path.append(parents[path[-1]])
        if len(path) > len(frames):
            continue
        base = depth.get(path[-1], 0)
        for offset, node in enumerate(reversed(path)):
            depth.setdefault(node, base + offset)
    ordered = sorted(depth, key=lambda f: (depth[f], f))
    return ordered + sorted(set(frames) - set(depth))


class TfBuffer:
    """All TF samples of a recording, grouped per edge, answering tree summaries and lookups."""

    def __init__(self, samples: Iterable[TfSample]) -> None:
        grouped: dict[tuple[str, str], list[TfSample]] = defaultdict(list)
        ignored = 0
        for sample in samples:
            parent, child = normalize_frame(sample.parent), normalize_frame(sample.child)
            usable = bool(parent) and bool(child) and parent != child
            if not usable or not is_finite_sample(sample.translation, sample.rotation):
                ignored += 1
            else:
                grouped[(parent, child)].append(sample)
        self._edges = {key: _series(key[0], key[1], group) for key, group in grouped.items()}
        self._frames = sorted({frame for key in self._edges for frame in key})
        self._ignored = ignored

    @property
    def frames(self) -> list[str]:
        """All frame names (normalised, sorted)."""
        return list(self._frames)

    def tree(self, t_ns: int | None = None) -> TfTree:
        """Tree summary; parents of multi-parent children and nearest_ns are chosen at t_ns when given."""
        parents = parents_at(self._edges.values(), t_ns)
        all_parents: dict[str, list[str]] = defaultdict(list)
        for parent, child in self._edges:
            all_parents[child].append(parent)
        order = _depth_order(self._frames, parents)
        rank = {frame: i for i, frame in enumerate(order)}
        edges = [
            carried(Edge, s, rate_hz=rate_hz(s), nearest_ns=None if t_ns is None else nearest_ns(s, t_ns))
            for s in sorted(self._edges.values(), key=lambda s: (rank[s.child], s.parent))
        ]
        return TfTree(
            frames=list(self._frames),
            roots=[frame for frame in self._frames if frame not in all_parents],
            edges=edges,
            multiple_parents={c: sorted(p) for c, p in sorted(all_parents.items()) if len(p) > 1},
            order=order,
            ignored_samples=self._ignored,
        )

    def lookup(self, target: str, source: str, t_ns: int) -> Lookup:
        """T_target_source at t_ns (tf2 semantics): maps points expressed in source into target."""
        return lookup_transform(
            self._edges,
            parents_at(self._edges.values(), t_ns),
            set(self._frames),
            target=normalize_frame(target),
            source=normalize_frame(source),
            t_ns=t_ns,
        )
