"""search_messages conditions, typed: the caller's condition and value are parsed once, into one type per
kind of test, and each type tests or masks on its own.

A condition reads the topic in one of three ways, which it asks of a ``Scan`` (query/search_scan.py): a
column of numbers it masks (``Compare``, ``Between``, ``Extreme``), x/y positions it measures
(``NearPosition``), or each message decoded, which it judges (``Text``, ``FieldExists``). The first two are
answered from the columnar index when the topic has one, so ``columnar`` also tells a quick search.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import ClassVar, Literal, Protocol, TypeVar, get_args

import numpy as np
import numpy.typing as npt
from pydantic import JsonValue

from bagmcp_bag_store.queries.bounded_regex import BoundedRegex
from bagmcp_shared.errors import ArgumentError, MessagePathError
from bagmcp_shared.jsonify import to_json
from bagmcp_shared.paths import Step, extract

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
SHOWN_TEXT = 300  # characters of a matching text shown in a match

Numbers = npt.NDArray[np.float64]
Mask = npt.NDArray[np.bool_]
Steps = tuple[Step, ...]
T_co = TypeVar("T_co", covariant=True)


class Masking(Protocol):
    def mask(self, values: Numbers) -> Mask: ...


class Judging(Protocol):
    def judge(self, message: object, steps: Steps | None) -> tuple[bool, JsonValue]: ...


class Scan(Protocol[T_co]):
    """What a condition asks of the topic it searches (query/search_scan.py reads the bag)."""

    def numbers(self, condition: Masking) -> T_co: ...

    def positions(self, near: NearPosition) -> T_co: ...

    def messages(self, condition: Judging) -> T_co: ...


T = TypeVar("T")


class _Masks(ABC):
    """A test of a column of numbers, which it masks; answered from the columnar index when there is one."""

    columnar: ClassVar[bool] = True

    @abstractmethod
    def mask(self, values: Numbers) -> Mask: ...

    def find(self, scan: Scan[T]) -> T:
        return scan.numbers(self)


class _Judges(ABC):
    """A test of each message decoded, which it judges (the field's value, or every text in the message)."""

    columnar: ClassVar[bool] = False

    @abstractmethod
    def judge(self, message: object, steps: Steps | None) -> tuple[bool, JsonValue]: ...

    def find(self, scan: Scan[T]) -> T:
        return scan.messages(self)


@dataclass(frozen=True)
class Compare(_Masks):
    """greater_than, less_than, equals or not_equals a number (equal within 1e-9)."""

    test: Callable[[Numbers, float], Mask]
    number: float

    def mask(self, values: Numbers) -> Mask:
        return self.test(values, self.number)


@dataclass(frozen=True)
class Between(_Masks):
    """low <= value <= high."""

    low: float
    high: float

    def mask(self, values: Numbers) -> Mask:
        return (values >= self.low) & (values <= self.high)


@dataclass(frozen=True)
class Extreme(_Masks):
    """max or min: the messages holding the window's largest (or smallest) finite value; takes no value."""

    pick: Callable[[Numbers], np.float64]

    def mask(self, values: Numbers) -> Mask:
        finite = np.isfinite(values)
        if not finite.any():
            return finite
        mask: Mask = finite & (values == self.pick(values[finite]))
        return mask


@dataclass(frozen=True)
class NearPosition:
    """Within ``radius`` metres of (x, y) in the plane."""

    x: float
    y: float
    radius: float
    columnar: ClassVar[bool] = True

    def distances(self, xs: Numbers, ys: Numbers) -> Numbers:
        return np.hypot(xs - self.x, ys - self.y)

    def find(self, scan: Scan[T]) -> T:
        return scan.positions(self)


@dataclass(frozen=True)
class Text(_Judges):
    """contains (any case), regex, or a string equals / not_equals, on the field or every text in a message.
    A message without the field does not match."""

    test: Callable[[str], bool]

    def judge(self, message: object, steps: Steps | None) -> tuple[bool, JsonValue]:
        if steps is None:
            texts: Iterator[str] = _texts(message)
        else:
            try:
                texts = iter([str(extract(message, steps))])
            except MessagePathError:
                return False, None
        found = next((text for text in texts if self.test(text)), None)
        return found is not None, (found or "")[:SHOWN_TEXT]


@dataclass(frozen=True)
class FieldExists(_Judges):
    """The message has the field, and it is not empty (an empty string, list or array)."""

    def judge(self, message: object, steps: Steps | None) -> tuple[bool, JsonValue]:
        try:
            picked = extract(message, steps or ())
        except MessagePathError:
            return False, None
        return _present(picked), to_json(picked, max_items=8, max_text=SHOWN_TEXT)


SearchCondition = Compare | Between | Extreme | NearPosition | Text | FieldExists


def _texts(value: object) -> Iterator[str]:
    if isinstance(value, str):
        yield value
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _texts(item)
    elif hasattr(value, "__dataclass_fields__"):
        for name in value.__dataclass_fields__:
            if not name.startswith("__"):
                yield from _texts(getattr(value, name))


def _present(value: object) -> bool:
    return not (isinstance(value, str | list | tuple | bytes | np.ndarray) and len(value) == 0)


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


def _equal(values: Numbers, number: float) -> Mask:
    return np.isclose(values, number, rtol=0.0, atol=1e-9)


_NUMBER_TESTS: dict[str, Callable[[Numbers, float], Mask]] = {
    "greater_than": lambda values, number: values > number,
    "less_than": lambda values, number: values < number,
    "equals": _equal,
    "not_equals": lambda values, number: ~_equal(values, number),
}
_TEXT_TESTS: dict[str, Callable[[str], Callable[[str], bool]]] = {
    "contains": lambda wanted: lambda text: wanted.casefold() in text.casefold(),
    "regex": lambda wanted: BoundedRegex(wanted).search,
    "equals": lambda wanted: lambda text: text == wanted,
    "not_equals": lambda wanted: lambda text: text != wanted,
}


def _text(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
    if not isinstance(value, str):
        raise ArgumentError(f"{condition} takes a string value, got {value!r}")
    return Text(_TEXT_TESTS[condition](value))


def _equality(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
    """A number compares a column of numbers; a string or boolean compares each message's text."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        return Compare(_NUMBER_TESTS[condition], float(value))
    if isinstance(value, str | bool):
        return Text(_TEXT_TESTS[condition](str(value)))
    raise ArgumentError(f"{condition} takes a number, string or boolean, got {value!r}")


def _order(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
    return Compare(_NUMBER_TESTS[condition], _number(value, condition))


def _between(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
    return Between(*parse_between(value))


def _extreme(pick: Callable[[Numbers], np.float64]) -> Callable[[str, JsonValue, str | None], SearchCondition]:
    def parse(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
        if value is not None:
            raise ArgumentError(f"{condition} finds the {condition}imum itself; leave out `value`")
        return Extreme(pick)

    return parse


def _near(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
    return parse_near(value)


def _exists(condition: str, value: JsonValue, field: str | None) -> SearchCondition:
    if field is None:
        raise ArgumentError("field_exists needs `field`, the message path to look for")
    return FieldExists()


_PARSERS: dict[str, Callable[[str, JsonValue, str | None], SearchCondition]] = {
    "contains": _text,
    "regex": _text,
    "equals": _equality,
    "not_equals": _equality,
    "greater_than": _order,
    "less_than": _order,
    "between": _between,
    "max": _extreme(np.max),
    "min": _extreme(np.min),
    "near_position": _near,
    "field_exists": _exists,
}


def parse_condition(condition: str, value: JsonValue, field: str | None = None) -> SearchCondition:
    """The typed condition, or a refusal that says which values ``condition`` accepts."""
    parse = _PARSERS.get(condition)
    if parse is None:
        raise ArgumentError(f"unknown condition {condition!r}; use one of: {', '.join(CONDITIONS)}")
    return parse(condition, value, field)
