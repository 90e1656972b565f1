"""YAML task files: the paths a fact's reference is read at, and malformed files refused with a sentence."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_lab.errors import TaskFileError
from bagmcp_lab.tasks.taskfile import pick, read_task_file

ANSWER = {"topics": [{"name": "/odom", "count": 1201}, {"name": "/scan", "count": 601}], "frames": ["map", "odom"]}


def test_paths_pick_keys_indexes_and_items_by_field() -> None:
    assert pick(ANSWER, "topics[name=/scan].count") == 601
    assert pick(ANSWER, "topics[0].name") == "/odom"
    assert pick(ANSWER, "frames[1]") == "odom"


@pytest.mark.parametrize("text", ["tasks: 3\n", "- prompt: hi\n", "tasks:\n  - title: no prompt\n", "tasks: [\n"])
def test_a_malformed_task_file_is_refused_with_what_it_must_hold(text: str, tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(TaskFileError, match=r"(must hold `tasks:`|cannot read the task file)"):
        read_task_file(path)
