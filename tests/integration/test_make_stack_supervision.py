"""`make stack` never runs unsupervised: closing the terminal (SIGHUP) or killing the supervisor stops every
process of the stack (SIGTERM too), a second start over a directory whose supervisor is alive is refused with
its pid, and a new start over a directory whose old processes still run says so and stops them, then starts on
the same ports. Before, all processes kept running and the next start crash-looped on their
bound ports for about 90 s."""

from __future__ import annotations

import contextlib
import os
import re
import signal
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.fixtures.make_stack import MakeStack, processes_of
from tests.fixtures.processes import http_ok, wait_until

pytestmark = pytest.mark.integration


@pytest.fixture
def stack(tmp_path: Path) -> Iterator[MakeStack]:
    stack = MakeStack(tmp_path / "supervised")
    stack.start()
    try:
        yield stack
    finally:
        if stack.process is not None and stack.process.poll() is None:
            stack.stop()
        for pid in processes_of(stack.directory):  # a failed test leaves nothing running on the machine
            with contextlib.suppress(ProcessLookupError):
                os.killpg(os.getpgid(pid), signal.SIGKILL)


def _parent(pid: int) -> int | None:
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return None


def _supervisor_gone(stack: MakeStack, sig: signal.Signals) -> None:
    assert stack.process is not None
    os.kill(stack.process.pid, sig)
    stack.process.wait(timeout=40)
    stack.process = None


@pytest.mark.parametrize("sig", [signal.SIGHUP, signal.SIGTERM], ids=["SIGHUP", "SIGTERM"])
def test_closing_the_terminal_or_sigterm_stops_every_process(stack: MakeStack, sig: signal.Signals) -> None:
    assert len(processes_of(stack.directory)) >= 11  # supervisor, watchdog, redis, weed, 3 services, 3 workers, ...
    _supervisor_gone(stack, sig)
    wait_until(lambda: not processes_of(stack.directory), timeout_s=30, what="every stack process to stop")
    assert f"stopping every process: asked to ({sig.name})" in stack.log.read_text()


def test_a_second_start_is_refused_while_the_supervisor_lives_and_a_killed_one_takes_its_processes(
    stack: MakeStack,
) -> None:
    assert stack.process is not None
    running = sorted(processes_of(stack.directory))
    second = stack.command_start()
    assert second.returncode == 1
    said = f"bagmcp stack: a stack runs in {stack.directory} already (pid {stack.process.pid}); stop it or set"
    assert said in second.stderr, second.stderr
    after = processes_of(stack.directory)
    assert set(running) <= set(after)  # nothing stopped
    # nothing started: a worker's pool children come up a few seconds after the stack answers, so a process
    # that is new since then must be a child of the stack's own processes, not of a second supervisor
    assert all(_parent(pid) in running for pid in set(after) - set(running))
    assert http_ok(f"{stack.url}/readyz")()
    _supervisor_gone(stack, signal.SIGKILL)
    wait_until(lambda: not processes_of(stack.directory), timeout_s=30, what="the watchdog to stop every process")
    log = stack.log.read_text()
    assert f"processes of the stack whose supervisor ended in {stack.directory} still run" in log


def test_a_start_over_left_processes_stops_them_and_keeps_its_ports(stack: MakeStack) -> None:
    ports = stack.ports()
    watchdog = int(re.findall(r"started watchdog \(pid (\d+)\)", stack.log.read_text())[-1])
    os.kill(watchdog, signal.SIGKILL)  # as if both went at once: nothing stops the stack's processes now
    _supervisor_gone(stack, signal.SIGKILL)
    left = processes_of(stack.directory)
    assert len(left) >= 9
    stack.start()
    assert f"processes of an earlier stack in {stack.directory} still run" in stack.log.read_text()
    assert not set(left) & set(processes_of(stack.directory))
    assert stack.ports() == ports
