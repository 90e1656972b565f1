"""Thinning a series for layout=columns keeps every column's peaks and uses the points it is given."""

from __future__ import annotations

import numpy as np

from bagmcp_bag_store.queries.column_range import keep_extremes


def test_spikes_in_any_column_survive_thinning_to_a_few_points() -> None:
    count = 100_000
    smooth = np.sin(np.linspace(0, 20, count))
    spiky = np.zeros(count)
    spiky[31_337], spiky[77_777] = 50.0, -40.0
    kept = keep_extremes([smooth, spiky], 200)
    assert len(kept) <= 200
    assert len(kept) >= 180
    assert {31_337, 77_777} <= set(kept.tolist())
    assert smooth[kept].max() == smooth.max()
    assert np.all(np.diff(kept) > 0)


def test_short_series_are_returned_whole() -> None:
    values = [np.arange(10.0)]
    assert keep_extremes(values, 50).tolist() == list(range(10))
