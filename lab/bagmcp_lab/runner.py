"""A benchmark run: build the suite (references from the tools), then for every task and repeat run the agent
loop with a fresh conversation, judge it, and hand each record to ``on_record`` as soon as it is judged."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from dataclasses import dataclass

import httpx2

from bagmcp_lab.agent import AgentOutcome, Watcher, run_agent
from bagmcp_lab.judge import judge
from bagmcp_lab.providers import ProviderChoice, open_conversation
from bagmcp_lab.results import RunRecord, ToolCallOut
from bagmcp_lab.tasks.model import Task
from bagmcp_lab.tasks.suites import Suite, build_suite
from bagmcp_lab.toolbox import ToolBox, open_toolbox

OnRecord = Callable[[RunRecord, int, int], Awaitable[None]]  # the record, runs done, runs planned
OnSuite = Callable[[Suite], Awaitable[None]]


@dataclass(frozen=True)
class BenchmarkPlan:
    url: str
    token: str | None
    choice: ProviderChoice
    bag: str
    tasks: str = "paper"
    repeat: int = 1
    max_turns: int = 10
    transport: httpx2.AsyncBaseTransport | None = None


def record_of(task: Task, plan: BenchmarkPlan, repeat: int, outcome: AgentOutcome) -> RunRecord:
    verdict = judge(task, outcome)
    return RunRecord(
        task=task.id,
        model=plan.choice.model,
        provider=plan.choice.provider,
        repeat=repeat,
        success=verdict.success,
        reason=verdict.reason,
        tool_calls=[ToolCallOut.model_validate(c.as_json()) for c in outcome.calls],
        n_tool_calls=len(outcome.calls),
        latency_s=round(outcome.latency_s, 3),
        input_tokens=outcome.input_tokens,
        output_tokens=outcome.output_tokens,
        final_answer=outcome.final_answer,
    )


async def run_task(
    box: ToolBox, task: Task, plan: BenchmarkPlan, repeat: int, watch: Watcher | None = None
) -> RunRecord:
    conversation = open_conversation(plan.choice, box.tools, [("user", task.prompt)], instructions=box.instructions)
    if watch is None:
        outcome = await run_agent(conversation, box, max_turns=plan.max_turns)
    else:
        outcome = await run_agent(conversation, box, max_turns=plan.max_turns, watch=watch)
    return record_of(task, plan, repeat, outcome)


async def run_benchmark(
    plan: BenchmarkPlan, *, on_record: OnRecord, on_suite: OnSuite | None = None
) -> list[RunRecord]:
    records: list[RunRecord] = []
    async with open_toolbox(plan.url, token=plan.token, transport=plan.transport) as box:
        suite = await build_suite(box, plan.bag, plan.tasks)
        if on_suite is not None:
            await on_suite(suite)
        planned = len(suite.tasks) * plan.repeat
        for task in suite.tasks:
            for repeat in range(1, plan.repeat + 1):
                record = await run_task(box, task, plan, repeat)
                records.append(record)
                await on_record(record, len(records), planned)
    return records
