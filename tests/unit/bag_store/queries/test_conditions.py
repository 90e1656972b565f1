"""search_messages values are checked per condition, and regexes cannot hang a worker."""

from __future__ import annotations

import time

import pytest

from bagmcp_bag_store.queries.bounded_regex import BoundedRegex
from bagmcp_bag_store.queries.conditions import NearPosition, parse_between, parse_condition, parse_near
from bagmcp_shared.errors import ArgumentError


def test_near_position_accepts_an_object_or_a_string() -> None:
    assert parse_near({"x": 1, "y": -2, "radius": 0.5}) == NearPosition(1.0, -2.0, 0.5)
    assert parse_near("1, -2, 0.5") == NearPosition(1.0, -2.0, 0.5)


@pytest.mark.parametrize("value", ["1,2", {"x": 1, "y": 2}, [1, 2, 3], {"x": "a", "y": 1, "radius": 1}, "1,2,-1"])
def test_bad_near_position_values_say_what_is_accepted(value: object) -> None:
    with pytest.raises(ArgumentError, match=r"near_position|radius"):
        parse_near(value)  # type: ignore[arg-type]


def test_between_needs_an_ordered_pair_of_numbers() -> None:
    assert parse_between([0.5, 1]) == (0.5, 1.0)
    for bad in ([2, 1], [1], "1,2", [True, 2]):
        with pytest.raises(ArgumentError):
            parse_between(bad)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("condition", "value", "phrase"),
    [
        ("similar", 1, "use one of"),
        ("greater_than", "fast", "needs a number"),
        ("contains", 3, "takes a string"),
        ("equals", [1], "number, string or boolean"),
    ],
)
def test_wrong_conditions_and_values_are_refused_with_the_accepted_forms(
    condition: str, value: object, phrase: str
) -> None:
    with pytest.raises(ArgumentError, match=phrase):
        parse_condition(condition, value)  # type: ignore[arg-type]


def test_a_catastrophic_backtracking_regex_answers_quickly() -> None:
    """RE2 matches in linear time: the pattern that backtracks 2**40 times in a backtracking engine."""
    pattern = BoundedRegex(r"(a|aa)+$")
    began = time.monotonic()
    assert not pattern.search("a" * 10_000 + "!")
    assert time.monotonic() - began < 1


def test_a_regex_past_its_cpu_budget_is_an_error_that_says_what_to_do() -> None:
    pattern = BoundedRegex(r"[a-z]+9$", budget_s=0.02)
    text = "a" * 100_000
    with pytest.raises(ArgumentError, match=r"^the regex used its 0\.02 s budget; narrow the time window$"):
        any(pattern.search(text) for _ in range(10_000))  # nothing matches: searches go on until the budget ends


def test_lookaround_is_refused_naming_re2_syntax() -> None:
    with pytest.raises(ArgumentError, match="RE2 syntax"):
        BoundedRegex(r"(?<=x)y")


def test_patterns_are_limited_in_length_and_must_compile() -> None:
    with pytest.raises(ArgumentError, match="limited"):
        BoundedRegex("a" * 300)
    with pytest.raises(ArgumentError, match="invalid regex"):
        BoundedRegex("(unclosed")
    assert BoundedRegex(r"battery \d+").search("battery 80 percent")
