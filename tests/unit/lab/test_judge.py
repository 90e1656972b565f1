"""The judge: which calls meet a requirement, which numbers and words an answer states, and the reasons it gives."""

from __future__ import annotations

import pytest

from bagmcp_lab.agent import AgentOutcome
from bagmcp_lab.judge import fact_stated, judge, numbers_in, requirement_met
from bagmcp_lab.tasks.model import Requirement, Task, number_fact, verdict_fact, word_fact
from bagmcp_lab.toolbox import ToolAnswer


def _answer(name: str, *, is_error: bool = False, **arguments: object) -> ToolAnswer:
    return ToolAnswer(name, dict(arguments), "text", (), None, is_error, 12.0)


def test_numbers_are_read_as_models_write_them() -> None:
    assert numbers_in("1,201 messages, -0.5 m/s at t=21.3 s, 1.2e-3 rad, (4, 2), .5") == [
        1201.0, -0.5, 21.3, 1.2e-3, 4.0, 2.0, 0.5,
    ]  # fmt: skip


@pytest.mark.parametrize(
    ("text", "stated"),
    [("drove 18.02 m", True), ("drove 18.5 m", False), ("drove 17.7 m", True), ("drove 1,800 cm", False)],
)
def test_a_number_counts_within_its_tolerance(text: str, stated: bool) -> None:
    assert fact_stated(number_fact("distance", 18.0, relative=0.02), text) is stated


def test_words_match_whole_words_in_any_case() -> None:
    assert fact_stated(word_fact("frame", "base_link"), "frames: map -> odom -> Base_Link")
    assert not fact_stated(word_fact("frame", "odom"), "frames: odometry")
    assert fact_stated(word_fact("node", "controller"), "from /controller and /planner")
    assert fact_stated(verdict_fact("passed", yes=False), "No, it never came closer than 0.6 m.")
    assert not fact_stated(verdict_fact("passed", yes=True), "No, it never came closer than 0.6 m.")


def test_a_requirement_needs_a_successful_call_with_the_named_arguments() -> None:
    plot = Requirement(("plot_timeseries",), {"start": 10.0, "paths": "linear.x"})
    good = _answer("plot_timeseries", start=10.2, end=30, paths=["/cmd_vel.linear.x"])
    assert requirement_met(plot, [good])
    assert not requirement_met(plot, [_answer("plot_timeseries", start=12, paths=["/cmd_vel.linear.x"])])
    assert not requirement_met(plot, [_answer("plot_timeseries", start=10, paths=["/odom.twist"])])
    assert not requirement_met(plot, [_answer("plot_timeseries", is_error=True, start=10, paths=["linear.x"])])
    assert requirement_met(
        Requirement(("search_messages", "get_messages_in_range")), [_answer("get_messages_in_range")]
    )


def test_a_failure_names_every_missed_requirement_and_fact() -> None:
    task = Task(
        "t", "T", "?", (Requirement(("analyze_trajectory",)),), (number_fact("distance (m)", 18.0, tolerance=0.1),)
    )
    outcome = AgentOutcome(final_answer="It drove 39 m in 60 s.", answers=[_answer("bag_info", bag="drive")])
    verdict = judge(task, outcome)
    assert not verdict.success
    assert verdict.reason == (
        "did not call analyze_trajectory (called bag_info); "
        "answer does not state distance (m) = 18 ± 0.1 (numbers stated: 39, 60)"
    )


def test_running_out_of_turns_is_a_reason_and_success_says_what_was_used() -> None:
    task = Task("t", "T", "?", (Requirement(("list_bags",)),), (word_fact("bag", "drive"),))
    calls = [_answer("list_bags")]
    assert judge(task, AgentOutcome(answers=calls, stopped="no final answer within 3 turns")).reason == (
        "no final answer within 3 turns"
    )
    done = judge(task, AgentOutcome(final_answer="One bag: drive.", answers=calls))
    assert (done.success, done.reason) == (True, "called list_bags; stated 1 reference facts")
