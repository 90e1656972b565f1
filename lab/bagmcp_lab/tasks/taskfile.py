"""Tasks from a YAML file: a prompt, the tools a good answer calls (or accepted alternatives), and the facts it
must state, either written out or taken from a tool's answer (so a reference is computed, not typed)::

    tasks:
      - id: odom-count
        title: Messages on /odom
        prompt: How many messages are on /odom in {bag}?
        requires: [[bag_info, list_bags]]        # each item: one tool, or a list of accepted alternatives
        facts:
          - label: /odom messages
            tool: bag_info                        # the reference: this tool's answer ...
            arguments: {bag: "{bag}"}
            path: topics[name=/odom].count        # ... at this path
            tolerance: 0                          # absolute (or relative: 0.02); default exact
          - {label: a word, words: [odom]}
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import yaml

from bagmcp_lab.errors import TaskFileError
from bagmcp_lab.tasks.model import Fact, Requirement, Task
from bagmcp_lab.toolbox import ToolBox

_STEP = re.compile(r"([^.\[\]]+)|\[(\d+)\]|\[([^=\]]+)=([^\]]*)\]")


def pick(value: Any, path: str) -> Any:
    """``a.b[0].c`` or ``topics[name=/odom].count`` in a JSON value."""
    for match in _STEP.finditer(path):
        key, index, field, wanted = match.groups()
        if key is not None:
            value = value[key]
        elif index is not None:
            value = value[int(index)]
        else:
            value = next(item for item in value if str(item.get(field)) == wanted)
    return value


def _filled(value: Any, bag: str) -> Any:
    if isinstance(value, str):
        return value.replace("{bag}", bag)
    if isinstance(value, dict):
        return {k: _filled(v, bag) for k, v in value.items()}
    if isinstance(value, list):
        return [_filled(v, bag) for v in value]
    return value


def _requirement(item: Any) -> Requirement:
    if isinstance(item, str):
        return Requirement((item,))
    if isinstance(item, list) and item and all(isinstance(i, str) for i in item):
        return Requirement(tuple(item))
    if isinstance(item, dict) and "tools" in item:
        return Requirement(tuple(item["tools"]), dict(item.get("arguments") or {}))
    raise TaskFileError(f"a requirement must be a tool name, a list of names or {{tools, arguments}}, not {item!r}")


async def _fact(box: ToolBox, raw: dict[str, Any], bag: str) -> Fact:
    label = str(raw.get("label", "fact"))
    if "words" in raw:
        return Fact(label, words=tuple(str(w) for w in raw["words"]))
    if "tool" in raw:
        answer = await box.reference(str(raw["tool"]), **_filled(dict(raw.get("arguments") or {}), bag))
        try:
            value = pick(answer, str(raw["path"]))
        except (KeyError, IndexError, StopIteration, TypeError) as err:
            raise TaskFileError(f"fact {label!r}: path {raw.get('path')!r} is not in the {raw['tool']} answer") from err
    elif "value" in raw:
        value = raw["value"]
    else:
        raise TaskFileError(f"fact {label!r} needs value, words, or tool + path")
    if isinstance(value, bool) or not isinstance(value, int | float):
        return Fact(label, words=(str(value),))
    return Fact(
        label, number=float(value), tolerance=float(raw.get("tolerance", 0)), relative=float(raw.get("relative", 0.0))
    )


def read_task_file(path: Path) -> list[dict[str, Any]]:
    try:
        document = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as err:
        raise TaskFileError(f"cannot read the task file {path}: {err}") from None
    items = document.get("tasks") if isinstance(document, dict) else None
    if not isinstance(items, list) or not all(isinstance(i, dict) and "prompt" in i for i in items):
        raise TaskFileError(f"{path} must hold `tasks:`, a list of items each with at least a prompt")
    return items


async def file_tasks(box: ToolBox, path: Path, bag: str) -> list[Task]:
    tasks = []
    for number, raw in enumerate(read_task_file(path), start=1):
        task_id = str(raw.get("id", f"{path.stem}-{number}"))
        prompt = _filled(str(raw["prompt"]), bag)
        requires = tuple(_requirement(item) for item in raw.get("requires") or [])
        facts = tuple([await _fact(box, dict(f), bag) for f in raw.get("facts") or []])
        tasks.append(Task(task_id, str(raw.get("title", task_id)), prompt, requires, facts, suite=path.stem))
    return tasks
