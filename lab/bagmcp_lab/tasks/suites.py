"""Which tasks a run asks: ``paper`` (the ten), ``all`` (the ten and ours), or a YAML file of tasks."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from bagmcp_lab.errors import LabError
from bagmcp_lab.tasks.bag_probe import probe_bag
from bagmcp_lab.tasks.model import Task
from bagmcp_lab.tasks.ours import OUR_TASKS
from bagmcp_lab.tasks.paper import PAPER_TASKS
from bagmcp_lab.tasks.taskfile import file_tasks
from bagmcp_lab.toolbox import ToolBox

SUITES = ("paper", "all")


@dataclass
class Suite:
    tasks: list[Task] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)  # builder name -> why the bag cannot pose it


def check_suite_name(suite: str) -> None:
    if suite not in SUITES and not suite.endswith((".yaml", ".yml")):
        raise LabError(f"--tasks takes paper, all or a YAML file (FILE.yaml), not {suite!r}")


async def build_suite(box: ToolBox, bag: str, suite: str) -> Suite:
    """The tasks over ``bag`` with their references (the tools are called here, before any model runs)."""
    check_suite_name(suite)
    if suite not in SUITES:
        path = Path(suite)
        if not path.is_file():
            raise LabError(f"no task file at {path}; give a YAML file or paper/all")
        return Suite(await file_tasks(box, path, bag))
    probe = await probe_bag(box, bag)
    built = Suite()
    for builder in PAPER_TASKS + (OUR_TASKS if suite == "all" else ()):
        try:
            task = await builder(box, probe)
        except LabError as err:  # e.g. the token may not call a tool the reference needs
            task = str(err)
        except (KeyError, IndexError, TypeError, ValueError) as err:  # an answer of another shape than expected
            task = f"the tools' answers lack what the reference needs ({type(err).__name__}: {err})"
        if isinstance(task, Task):
            built.tasks.append(task)
        else:
            built.skipped[builder.__name__] = task
    return built
