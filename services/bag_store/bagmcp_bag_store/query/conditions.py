"""search_messages conditions: parsing the caller's value for each condition, and bounded regexes."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Literal, get_args

import regex
from pydantic import JsonValue

from bagmcp_shared.errors import ArgumentError

Condition = Literal[
    "contains",
    "regex",
    "equals",
    "not_equals",
    "greater_than",
    "less_than",
    "between",
    "max",
    "min",
    "near_position",
    "field_exists",
]
CONDITIONS: tuple[str, ...] = get_args(Condition)
TEXT_CONDITIONS = ("contains", "regex")
NUMERIC_CONDITIONS = ("greater_than", "less_than", "between", "max", "min")
EXTREME_CONDITIONS = ("max", "min")  # the messages holding the window's largest or smallest value; no value
MAX_PATTERN = 256
REGEX_TIMEOUT_S = 0.05
REGEX_BUDGET_S = 5.0


@dataclass(frozen=True)
class NearPosition:
    x: float
    y: float
    radius: float


def _number(value: JsonValue, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ArgumentError(f"{what} needs a number, got {value!r}")
    return float(value)


def parse_near(value: JsonValue) -> NearPosition:
    """``{"x":..,"y":..,"radius":..}`` or ``"x,y,radius"``."""
    if isinstance(value, str):
        parts = [p.strip() for p in value.split(",")]
        try:
            x, y, radius = (float(p) for p in parts)
        except ValueError as err:
            raise ArgumentError(f"near_position takes 'x,y,radius' or {{x, y, radius}}, got {value!r}") from err
    elif isinstance(value, dict):
        try:
            x, y, radius = (_number(value[k], f"near_position.{k}") for k in ("x", "y", "radius"))
        except KeyError as err:
            raise ArgumentError(f"near_position needs x, y and radius; {err} is missing") from err
    else:
        raise ArgumentError(f"near_position takes {{x, y, radius}} (metres) or 'x,y,radius', got {value!r}")
    if radius < 0:
        raise ArgumentError("near_position radius must not be negative")
    return NearPosition(x, y, radius)


def parse_between(value: JsonValue) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise ArgumentError(f"between takes [low, high], got {value!r}")
    low, high = _number(value[0], "between low"), _number(value[1], "between high")
    if low > high:
        raise ArgumentError(f"between takes [low, high] with low <= high, got {value!r}")
    return low, high


def check_value(condition: str, value: JsonValue) -> None:
    """Refuse a value of the wrong type for ``condition`` with a message saying what is accepted."""
    if condition not in CONDITIONS:
        raise ArgumentError(f"unknown condition {condition!r}; use one of: {', '.join(CONDITIONS)}")
    if condition in TEXT_CONDITIONS and not isinstance(value, str):
        raise ArgumentError(f"{condition} takes a string value, got {value!r}")
    if condition in ("greater_than", "less_than"):
        _number(value, condition)
    if condition in ("equals", "not_equals") and not isinstance(value, str | int | float | bool):
        raise ArgumentError(f"{condition} takes a number, string or boolean, got {value!r}")
    if condition == "between":
        parse_between(value)
    if condition in EXTREME_CONDITIONS and value is not None:
        raise ArgumentError(f"{condition} finds the {condition}imum itself; leave out `value`")
    if condition == "near_position":
        parse_near(value)


class BoundedRegex:
    """A compiled pattern with a per-match timeout and a total time budget."""

    def __init__(self, pattern: str) -> None:
        if len(pattern) > MAX_PATTERN:
            raise ArgumentError(f"regex patterns are limited to {MAX_PATTERN} characters")
        try:
            self._compiled = regex.compile(pattern)
        except regex.error as err:
            raise ArgumentError(f"invalid regex {pattern!r}: {err}") from err
        self._spent = 0.0

    def search(self, text: str) -> bool:
        began = time.monotonic()
        try:
            found = self._compiled.search(text, timeout=REGEX_TIMEOUT_S) is not None
        except TimeoutError as err:
            raise ArgumentError("the regex takes too long on this data; simplify the pattern") from err
        self._spent += time.monotonic() - began
        if self._spent > REGEX_BUDGET_S:
            raise ArgumentError(f"the regex used its {REGEX_BUDGET_S:.0f} s budget; narrow the time window")
        return found
