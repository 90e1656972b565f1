"""TF edges of one TF topic: each parent->child pair with its count, first and last stamp and mean rate, from
the index's transform rows, by get_tf_tree's rules: frame names without leading slashes, samples with an
empty frame, a frame as its own parent or a non-finite transform left out, static when any sample is."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from bagmcp_shared.index import TransformRows
from bagmcp_shared.index.transforms import is_finite_sample, normalize_frame

Columns = dict[str, npt.NDArray[np.generic] | Sequence[object]]


def _samples(rows: TransformRows) -> tuple[npt.NDArray[np.str_], npt.NDArray[np.int64], npt.NDArray[np.bool_]]:
    """(parent, child) names, stamps and static flags of one topic's usable samples."""
    frames = [normalize_frame(f) for f in rows.frames]
    pairs = [(frames[p], frames[c]) for p, c in zip(rows.parent.tolist(), rows.child.tolist(), strict=True)]
    transforms = zip(rows.translation.tolist(), rows.rotation.tolist(), strict=True)
    kept = np.asarray(
        [
            bool(p) and bool(c) and p != c and is_finite_sample(t, r)
            for (p, c), (t, r) in zip(pairs, transforms, strict=True)
        ],
        dtype=bool,
    )
    names = np.asarray(pairs, dtype=str).reshape(-1, 2)
    return names[kept], rows.t_ns[kept], rows.static[kept]


def tf_edge_rows(topics: Sequence[TransformRows]) -> Columns:
    """One row per edge over every TF topic of a bag."""
    found = [_samples(rows) for rows in topics]
    pairs = np.concatenate([f[0] for f in found]) if found else np.zeros((0, 2), dtype=str)
    t_ns = np.concatenate([f[1] for f in found]) if found else np.zeros(0, dtype=np.int64)
    static = np.concatenate([f[2] for f in found]) if found else np.zeros(0, dtype=bool)
    edges, inverse = np.unique(pairs, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse, minlength=len(edges))
    first = np.full(len(edges), np.iinfo(np.int64).max)
    last = np.full(len(edges), np.iinfo(np.int64).min)
    any_static = np.zeros(len(edges), dtype=bool)
    np.minimum.at(first, inverse, t_ns)
    np.maximum.at(last, inverse, t_ns)
    np.logical_or.at(any_static, inverse, static)
    span_s = (last - first) / 1e9
    rate = np.where((count > 1) & (span_s > 0), (count - 1) / np.where(span_s > 0, span_s, 1.0), np.nan)
    return {
        "parent": [str(p) for p in edges[:, 0]],
        "child": [str(c) for c in edges[:, 1]],
        "static": any_static,
        "count": count.astype(np.int64),
        "rate_hz": rate,
        "first_t": first / 1e9,
        "last_t": last / 1e9,
    }
