"""TF edges of one TF topic: each parent->child pair (static or not) with its count, first and last stamp
and mean rate, from the index's transform rows."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from bagmcp_shared.index import TransformRows

Columns = dict[str, npt.NDArray[np.generic] | Sequence[object]]


def tf_edge_rows(rows: TransformRows) -> Columns:
    keys = np.stack([rows.parent.astype(np.int64), rows.child.astype(np.int64), rows.static.astype(np.int64)], axis=1)
    edges, inverse = np.unique(keys, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse, minlength=len(edges))
    first = np.full(len(edges), np.iinfo(np.int64).max)
    last = np.full(len(edges), np.iinfo(np.int64).min)
    np.minimum.at(first, inverse, rows.t_ns)
    np.maximum.at(last, inverse, rows.t_ns)
    span_s = (last - first) / 1e9
    rate = np.where((count > 1) & (span_s > 0), (count - 1) / np.where(span_s > 0, span_s, 1.0), np.nan)
    return {
        "parent": [rows.frames[i] for i in edges[:, 0]],
        "child": [rows.frames[i] for i in edges[:, 1]],
        "static": edges[:, 2].astype(bool),
        "count": count.astype(np.int64),
        "rate_hz": rate,
        "first_t": first / 1e9,
        "last_t": last / 1e9,
    }
