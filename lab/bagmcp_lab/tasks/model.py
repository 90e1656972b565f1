"""What a task is: a prompt, the tools a good answer calls, and the facts its final answer states.

Facts are references: numbers (with a tolerance) or words, worked out by calling the tools directly before any
model runs, so a judge compares a model's answer with what the tools themselves say."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

YES_WORDS = ("yes", "did pass", "passed within", "came within", "does show", "detected", "it did")
NO_WORDS = ("no", "never", "did not", "didn't", "does not", "not within")


@dataclass(frozen=True)
class Requirement:
    """One of ``tools`` called without error; when ``arguments`` are given, one such call had them (numbers
    within ``tolerance``, strings contained in the argument's JSON, e.g. a path in a list of paths)."""

    tools: tuple[str, ...]
    arguments: Mapping[str, float | str] = field(default_factory=dict)
    tolerance: float = 0.51

    def describe(self) -> str:
        names = " or ".join(self.tools)
        if not self.arguments:
            return names
        shown = ", ".join(f"{key}={value}" for key, value in self.arguments.items())
        return f"{names} with {shown}"


@dataclass(frozen=True)
class Fact:
    """A number the answer states (within ``tolerance`` absolute or ``relative`` of it), or one of ``words``."""

    label: str
    number: float | None = None
    tolerance: float = 0.0
    relative: float = 0.0
    words: tuple[str, ...] = ()

    def allowed_error(self) -> float:
        return max(self.tolerance, abs(self.number or 0.0) * self.relative)

    def expected(self) -> str:
        if self.number is not None:
            return f"{self.number:g} ± {self.allowed_error():g}"
        if len(self.words) > 2:
            return f"{self.words[0]!r} (or a word like it)"
        return " or ".join(repr(w) for w in self.words)


def number_fact(label: str, value: float, *, tolerance: float = 0.0, relative: float = 0.0) -> Fact:
    """A number within ``tolerance`` (absolute) or ``relative`` of ``value``, whichever is larger."""
    return Fact(label, number=float(value), tolerance=tolerance, relative=relative)


def word_fact(label: str, *words: str) -> Fact:
    return Fact(label, words=tuple(words))


def verdict_fact(label: str, *, yes: bool) -> Fact:
    """A yes/no answer, as the words a model uses to say it."""
    return word_fact(label, *(YES_WORDS if yes else NO_WORDS))


@dataclass(frozen=True)
class Task:
    """``id`` names the task in results; ``title`` is the row of the report's table (the paper's phrase)."""

    id: str
    title: str
    prompt: str
    requires: tuple[Requirement, ...]
    facts: tuple[Fact, ...] = ()
    suite: str = "paper"

    @property
    def required_tools(self) -> set[str]:
        return {name for requirement in self.requires for name in requirement.tools}
