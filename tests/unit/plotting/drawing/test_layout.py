"""Tests for bagmcp_plotting.drawing.layout: which lines share an axis and single/twin/stacked choice."""

from __future__ import annotations

import numpy as np

from bagmcp_plotting.drawing.layout import group_indices, layout_for
from bagmcp_plotting.drawing.lines import Line

T = np.linspace(0.0, 10.0, 50)


def flat(label: str, unit: str | None, peak: float) -> Line:
    return Line(label, unit, T, np.full(T.shape, peak))


def test_lines_with_one_unit_and_similar_scale_share_one_axis() -> None:
    lines = [flat("v", "m/s", 1.0), flat("cmd", "m/s", 15.0)]
    assert layout_for(lines) == "single"
    assert group_indices(lines) == [[0, 1]]


def test_two_units_of_similar_scale_use_twin_axes() -> None:
    lines = [flat("v", "m/s", 1.0), flat("yaw rate", "rad/s", 0.5), flat("cmd", "m/s", 2.0)]
    assert layout_for(lines) == "twin"
    assert group_indices(lines) == [[0, 2], [1]]


def test_three_units_use_stacked_panels() -> None:
    lines = [flat("v", "m/s", 1.0), flat("w", "rad/s", 1.0), flat("u", "V", 1.0)]
    assert layout_for(lines) == "stacked"


def test_same_unit_with_magnitudes_over_20x_apart_is_stacked() -> None:
    lines = [flat("small", "m", 1.0), flat("large", "m", 21.0)]
    assert layout_for(lines) == "stacked"
    assert group_indices(lines) == [[0], [1]]


def test_two_units_with_magnitudes_over_20x_apart_are_stacked() -> None:
    lines = [flat("v", "m/s", 1.0), flat("battery", "V", 48.0)]
    assert layout_for(lines) == "stacked"


def test_magnitudes_exactly_20x_apart_stay_together() -> None:
    assert layout_for([flat("a", "m", 1.0), flat("b", "m", 20.0)]) == "single"


def test_all_zero_line_joins_its_unit_group() -> None:
    lines = [flat("zero", "m", 0.0), flat("ten", "m", 10.0)]
    assert layout_for(lines) == "single"


def test_lines_without_unit_form_their_own_group() -> None:
    lines = [flat("count", None, 3.0), flat("v", "m/s", 2.0)]
    assert layout_for(lines) == "twin"
    assert group_indices(lines) == [[0], [1]]


def test_a_single_line_is_single() -> None:
    assert layout_for([flat("v", "m/s", 1.0)]) == "single"
