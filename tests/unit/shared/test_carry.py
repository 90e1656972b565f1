"""A domain result becomes its report by field name: values from ``more`` first, then from the first source
that has the attribute (a property too); a field found nowhere fails, naming it."""

from __future__ import annotations

from dataclasses import dataclass

import pytest
from pydantic import BaseModel, ValidationError

from bagmcp_shared.carry import carried


@dataclass(frozen=True)
class Span:
    first_ns: int
    last_ns: int
    name: str = "span"

    @property
    def duration_s(self) -> float:
        return (self.last_ns - self.first_ns) / 1e9


class SpanOut(BaseModel):
    name: str
    duration_s: float
    label: str


@dataclass(frozen=True)
class Renamed:
    title: str
    first_ns: int


def test_fields_come_from_more_then_the_first_source_that_has_them() -> None:
    out = carried(SpanOut, Span(1_000_000_000, 3_500_000_000), Renamed("other", 0), label="a")
    assert out == SpanOut(name="span", duration_s=2.5, label="a")
    assert carried(SpanOut, Span(0, 0), label="b", name="given").name == "given"


def test_a_dataclass_target_is_built_too() -> None:
    assert carried(Renamed, Span(7, 9), title="t") == Renamed(title="t", first_ns=7)


def test_a_field_found_nowhere_fails_naming_it() -> None:
    with pytest.raises(ValidationError, match="label"):
        carried(SpanOut, Span(0, 1))
    with pytest.raises(TypeError, match="title"):
        carried(Renamed, Span(0, 1))


def test_a_value_of_the_wrong_type_is_refused() -> None:
    with pytest.raises(ValidationError, match="duration_s"):
        carried(SpanOut, Renamed("x", 0), name="n", label="l", duration_s="soon")
