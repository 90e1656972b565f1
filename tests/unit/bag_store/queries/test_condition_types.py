"""Each search condition is parsed once into its own type, which tests or masks on its own."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest

from bagmcp_bag_store.queries.conditions import (
    Between,
    Compare,
    Extreme,
    FieldExists,
    NearPosition,
    Text,
    parse_condition,
)
from bagmcp_shared.errors import ArgumentError

VALUES = np.array([1.0, 2.0, np.nan, 3.0, 3.0, np.inf, 2.0 + 1e-12])


@dataclass
class Note:
    text: str


@dataclass
class Record:
    name: str
    notes: list[Note] = field(default_factory=list)
    ranges: list[float] = field(default_factory=list)


RECORD = Record("Battery LOW", [Note("cell 3 at 3.1 V")], [0.5, 1.5])


def _mask(condition: str, value: object) -> list[bool]:
    parsed = parse_condition(condition, value)  # type: ignore[arg-type]
    assert isinstance(parsed, Compare | Between | Extreme)
    return [bool(hit) for hit in parsed.mask(VALUES)]


@pytest.mark.parametrize(
    ("condition", "value", "kind"),
    [
        ("contains", "low", Text),
        ("regex", r"\d+", Text),
        ("equals", "DONE", Text),
        ("not_equals", True, Text),
        ("equals", 2, Compare),
        ("not_equals", 2.5, Compare),
        ("greater_than", 1, Compare),
        ("less_than", 1.5, Compare),
        ("between", [1, 2], Between),
        ("max", None, Extreme),
        ("min", None, Extreme),
        ("near_position", "1,2,0.5", NearPosition),
    ],
)
def test_each_condition_parses_into_its_own_type(condition: str, value: object, kind: type) -> None:
    assert isinstance(parse_condition(condition, value), kind)  # type: ignore[arg-type]


def test_comparisons_mask_a_column_of_numbers() -> None:
    assert _mask("greater_than", 2) == [False, False, False, True, True, True, True]
    assert _mask("less_than", 2) == [True, False, False, False, False, False, False]
    assert _mask("equals", 2) == [False, True, False, False, False, False, True]  # equal within 1e-9
    assert _mask("not_equals", 2) == [True, False, True, True, True, True, False]


def test_between_includes_both_ends() -> None:
    assert _mask("between", [2, 3]) == [False, True, False, True, True, False, True]


def test_max_and_min_mark_every_message_at_the_finite_extreme() -> None:
    assert _mask("max", None) == [False, False, False, True, True, False, False]
    assert _mask("min", None) == [True, False, False, False, False, False, False]
    nothing = parse_condition("max", None)
    assert isinstance(nothing, Extreme)
    assert not nothing.mask(np.array([np.nan, np.inf])).any()


def test_near_position_measures_planar_distance() -> None:
    near = parse_condition("near_position", {"x": 1, "y": 1, "radius": 1})
    assert isinstance(near, NearPosition)
    assert near.distances(np.array([1.0, 4.0]), np.array([1.0, 5.0])).tolist() == [0.0, 5.0]


def test_text_searches_every_text_field_or_the_one_named() -> None:
    contains = parse_condition("contains", "3.1 v")
    assert isinstance(contains, Text)
    assert contains.judge(RECORD, None) == (True, "cell 3 at 3.1 V")  # any case, nested messages too
    assert contains.judge(RECORD, ("name",)) == (False, "")
    regex = parse_condition("regex", r"^Battery")
    assert isinstance(regex, Text)
    assert regex.judge(RECORD, ("name",)) == (True, "Battery LOW")
    assert regex.judge(RECORD, ("ranges", 5)) == (False, None)  # a message without the element does not match


def test_text_equals_compares_whole_strings_and_booleans_as_text() -> None:
    equals = parse_condition("equals", "Battery LOW")
    differs = parse_condition("not_equals", "Battery LOW")
    assert isinstance(equals, Text)
    assert isinstance(differs, Text)
    assert equals.judge(RECORD, ("name",))[0]
    assert not differs.judge(RECORD, ("name",))[0]
    flag = parse_condition("equals", True)
    assert isinstance(flag, Text)
    assert flag.judge(Record("True"), ("name",))[0]


def test_field_exists_needs_a_field_and_finds_non_empty_values() -> None:
    with pytest.raises(ArgumentError, match="needs `field`"):
        parse_condition("field_exists", None)
    exists = parse_condition("field_exists", None, "notes")
    assert isinstance(exists, FieldExists)
    assert exists.judge(RECORD, ("ranges", 1)) == (True, 1.5)
    assert exists.judge(RECORD, ("ranges", 2)) == (False, None)
    assert exists.judge(Record(""), ("name",))[0] is False  # an empty string is not there
    assert exists.judge(Record("x"), ("notes",))[0] is False  # nor is an empty list


@pytest.mark.parametrize(
    ("condition", "value", "phrase"),
    [
        ("max", 1, "leave out `value`"),
        ("between", 3, r"\[low, high\]"),
        ("less_than", True, "needs a number"),
        ("regex", "(unclosed", "invalid regex"),
        ("near_position", {"x": 1}, "near_position"),
    ],
)
def test_a_bad_value_is_refused_when_parsed(condition: str, value: object, phrase: str) -> None:
    with pytest.raises(ArgumentError, match=phrase):
        parse_condition(condition, value)  # type: ignore[arg-type]
