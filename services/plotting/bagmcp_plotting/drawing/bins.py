"""The bins of a histogram and the values it counts: numbers only, no matplotlib, so the viewers' histogram
data (views.py) is made without loading the renderer.

Bins default to the Freedman–Diaconis rule clipped to [MIN_BINS, MAX_BINS]; non-finite values are dropped.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

MIN_BINS = 10
MAX_BINS = 100


def freedman_diaconis_bins(values: npt.NDArray[np.float64]) -> int:
    """Bin count from the Freedman–Diaconis width 2·IQR/n^(1/3), clipped to [MIN_BINS, MAX_BINS]."""
    finite = finite_values(values)
    q25, q75 = np.percentile(finite, [25, 75])
    iqr = float(q75 - q25)
    span = float(finite.max() - finite.min())
    if iqr <= 0 or span <= 0:
        return MIN_BINS
    width = 2.0 * iqr / float(np.cbrt(finite.size))
    return min(MAX_BINS, max(MIN_BINS, math.ceil(span / width)))


def finite_values(values: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The finite values as a flat float array; an error that says what to do when there are none."""
    array = np.asarray(values, dtype=np.float64).reshape(-1)
    finite = array[np.isfinite(array)]
    if finite.size == 0:
        raise ValueError("There are no finite values to draw a histogram of; pick a field or time range with data.")
    return finite
