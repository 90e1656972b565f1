"""tf2-style transform lookup through a TF tree: chain resolution, composition and user-facing errors."""

from __future__ import annotations

import difflib
from collections.abc import Collection, Mapping
from dataclasses import dataclass

from bagmcp_analysis.tf.edges import EdgeSeries, value_at
from bagmcp_analysis.tf.quaternions import IDENTITY, Quat, Vec3, canonical, conjugate, multiply, rotate, to_rpy

Transform = tuple[Vec3, Quat]


@dataclass(frozen=True)
class Lookup:
    """T_target_source: maps a point expressed in the source frame into the target frame."""

    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    roll_rad: float
    pitch_rad: float
    yaw_rad: float
    chain: list[str]
    interpolated: bool
    extrapolated_s: float


def compose(a: Transform, b: Transform) -> Transform:
    """a * b: apply b first, then a (T_x_z = T_x_y * T_y_z)."""
    (ta, qa), (tb, qb) = a, b
    moved = rotate(qa, tb)
    return (ta[0] + moved[0], ta[1] + moved[1], ta[2] + moved[2]), multiply(qa, qb)


def invert(a: Transform) -> Transform:
    """Inverse rigid transform (T_y_x from T_x_y)."""
    t, q = a
    q_inv = conjugate(q)
    back = rotate(q_inv, t)
    return (-back[0], -back[1], -back[2]), q_inv


def check_frame(frame: str, frames: Collection[str]) -> None:
    """Raise ValueError naming close matches when frame is not a known TF frame."""
    if frame in frames:
        return
    close = difflib.get_close_matches(frame, sorted(frames), n=3, cutoff=0.5)
    hint = f" Did you mean {', '.join(repr(c) for c in close)}?" if close else ""
    known = ", ".join(sorted(frames)[:20]) or "none"
    raise ValueError(f"Frame {frame!r} is not in the TF tree.{hint} Known frames: {known}.")


def ancestors(frame: str, parents: Mapping[str, str]) -> list[str]:
    """The frame followed by its parent, grandparent, ... up to its root."""
    path = [frame]
    seen = {frame}
    while path[-1] in parents:
        parent = parents[path[-1]]
        if parent in seen:
            loop = " -> ".join([*path[path.index(parent) :], parent])
            raise ValueError(f"The TF frames form a loop ({loop}); check which nodes publish these transforms.")
        path.append(parent)
        seen.add(parent)
    return path


class _Accumulator:
    """Composes edge transforms up a path while tracking interpolation and extrapolation."""

    def __init__(self, edges: Mapping[tuple[str, str], EdgeSeries], t_ns: int) -> None:
        self._edges = edges
        self._t_ns = t_ns
        self.interpolated = False
        self.extrapolated_s = 0.0

    def up_to(self, path: list[str], stop: int) -> Transform:
        """T_{path[stop]}_{path[0]} composed from the edges path[i] -> path[i+1] for i < stop."""
        result: Transform = ((0.0, 0.0, 0.0), IDENTITY)
        for i in range(stop):
            value = value_at(self._edges[(path[i + 1], path[i])], self._t_ns)
            self.interpolated = self.interpolated or value.interpolated
            self.extrapolated_s = max(self.extrapolated_s, value.extrapolated_s)
            result = compose((value.translation, value.rotation), result)
        return result


def _disconnected(target: str, source: str, target_root: str, source_root: str) -> ValueError:
    return ValueError(
        f"Frames {target!r} and {source!r} are not connected: {target!r} belongs to the tree rooted at "
        f"{target_root!r} and {source!r} to the tree rooted at {source_root!r}; no transform links the two trees."
    )


def lookup_transform(
    edges: Mapping[tuple[str, str], EdgeSeries],
    parents: Mapping[str, str],
    frames: Collection[str],
    *,
    target: str,
    source: str,
    t_ns: int,
) -> Lookup:
    """T_target_source at t_ns, chained through the common ancestor of both frames."""
    check_frame(target, frames)
    check_frame(source, frames)
    source_path = ancestors(source, parents)
    target_path = ancestors(target, parents)
    if source_path[-1] != target_path[-1]:
        raise _disconnected(target, source, target_path[-1], source_path[-1])
    in_target = {frame: i for i, frame in enumerate(target_path)}
    source_stop = next(i for i, frame in enumerate(source_path) if frame in in_target)
    target_stop = in_target[source_path[source_stop]]
    acc = _Accumulator(edges, t_ns)
    ancestor_source = acc.up_to(source_path, source_stop)
    ancestor_target = acc.up_to(target_path, target_stop)
    translation, rotation = compose(invert(ancestor_target), ancestor_source)
    rotation = canonical(rotation)
    roll, pitch, yaw = to_rpy(rotation)
    chain = source_path[: source_stop + 1] + target_path[:target_stop][::-1]
    return Lookup(
        translation=(float(translation[0]), float(translation[1]), float(translation[2])),
        rotation=rotation,
        roll_rad=roll,
        pitch_rad=pitch,
        yaw_rad=yaw,
        chain=chain,
        interpolated=acc.interpolated,
        extrapolated_s=acc.extrapolated_s,
    )
