"""Automatic, explained judging: the required tools were called without error (or an accepted alternative, with
the arguments the task names), and the final answer states every reference fact (numbers within tolerance).
Each failure says which requirement or fact was missed and what the answer said instead."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass

from bagmcp_lab.agent import AgentOutcome
from bagmcp_lab.tasks.model import Fact, Requirement, Task
from bagmcp_lab.toolbox import ToolAnswer

# Numbers as models write them: 1,201 / -0.5 / 1.2e-3 / .5 (thousands separators dropped before matching).
_NUMBER = re.compile(r"(?<![\w.])[-+−]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


@dataclass(frozen=True)
class Verdict:
    success: bool
    reason: str


def numbers_in(text: str) -> list[float]:
    plain = re.sub(r"(?<=\d),(?=\d{3}\b)", "", text)
    return [float(m.group().replace("−", "-")) for m in _NUMBER.finditer(plain)]


def _argument_matches(value: object, expected: float | str, tolerance: float) -> bool:
    if isinstance(expected, str):
        return expected.lower() in json.dumps(value).lower()
    try:
        return abs(float(value) - expected) <= tolerance  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return False


def requirement_met(requirement: Requirement, answers: list[ToolAnswer]) -> bool:
    for answer in answers:
        if answer.name not in requirement.tools or answer.is_error:
            continue
        if all(
            key in answer.arguments and _argument_matches(answer.arguments[key], expected, requirement.tolerance)
            for key, expected in requirement.arguments.items()
        ):
            return True
    return False


def fact_stated(fact: Fact, answer: str) -> bool:
    if fact.number is not None:
        return any(abs(n - fact.number) <= fact.allowed_error() + 1e-9 for n in numbers_in(answer))
    lowered = answer.lower()
    return any(re.search(rf"(?<!\w){re.escape(word.lower())}(?!\w)", lowered) for word in fact.words)


def _why_not(requirement: Requirement, answers: list[ToolAnswer]) -> str:
    tried = [a for a in answers if a.name in requirement.tools]
    if not tried:
        called = sorted({a.name for a in answers}) or ["no tool"]
        return f"did not call {requirement.describe()} (called {', '.join(called)})"
    if all(a.is_error for a in tried):
        return f"every call of {' or '.join(requirement.tools)} failed: {tried[-1].text[:160]}"
    return f"did not call {requirement.describe()} (arguments were {json.dumps(tried[-1].arguments)[:160]})"


def judge(task: Task, outcome: AgentOutcome) -> Verdict:
    """Success, or every reason it failed (joined by '; ')."""
    reasons = [_why_not(r, outcome.answers) for r in task.requires if not requirement_met(r, outcome.answers)]
    if outcome.stopped:
        reasons.append(outcome.stopped)
    elif not outcome.final_answer.strip():
        reasons.append("gave no final answer")
    else:
        stated = numbers_in(outcome.final_answer)
        for fact in task.facts:
            if not fact_stated(fact, outcome.final_answer):
                said = (
                    f" (numbers stated: {', '.join(f'{n:g}' for n in stated[:8])})" if fact.number is not None else ""
                )
                reasons.append(f"answer does not state {fact.label} = {fact.expected()}{said}")
    if reasons:
        return Verdict(False, "; ".join(reasons))
    used = ", ".join(sorted({a.name for a in outcome.answers})) or "no tool"
    return Verdict(True, f"called {used}; stated {len(task.facts)} reference facts")
