"""Benchmark tasks: the paper's ten, harder ones of ours, and tasks from YAML files, each with the tools a good
answer needs and the facts it must state (references computed by calling the tools)."""

from bagmcp_lab.tasks.model import Fact, Requirement, Task

__all__ = ["Fact", "Requirement", "Task"]
