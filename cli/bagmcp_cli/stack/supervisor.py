"""Runs the processes of a Procfile (``name: command`` lines) as `make stack` needs: output prefixed with
each name, a process that dies restarted after a growing pause (1 s, doubling to 30 s, back to 1 s once it
has run for a minute) with a line saying so, and the whole stack stopped with the reason when one keeps
dying (8 exits within 5 minutes). Ctrl-C, SIGTERM or SIGHUP (the terminal closed) stops every process
(TERM, then KILL after 10 s); data is never touched. Each process carries the stack directory's member mark
(``leftovers.MEMBER``) and a watchdog in its own session stops whatever still runs once the supervisor is gone,
however it went (SIGKILL included): the stack never runs unsupervised.

``python -m bagmcp_cli.stack.supervisor PROCFILE`` (settings in the environment, see ``environment``).
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import signal
import subprocess
import sys
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, TextIO

from bagmcp_cli.stack.environment import LOCK
from bagmcp_cli.stack.leftovers import MEMBER
from bagmcp_shared.settings import Env

FIRST_PAUSE_S = 1.0
LONGEST_PAUSE_S = 30.0
HEALTHY_AFTER_S = 60.0
GIVE_UP_EXITS = 8
GIVE_UP_WINDOW_S = 300.0
STOP_TIMEOUT_S = 10.0
TICK_S = 0.2


@dataclass
class Program:
    name: str
    command: str
    process: subprocess.Popen[bytes] | None = None
    started_at: float = 0.0
    pause_s: float = FIRST_PAUSE_S
    restart_at: float | None = None
    exits: deque[float] = field(default_factory=deque)


def read_procfile(path: Path) -> list[Program]:
    programs = []
    for line in path.read_text().splitlines():
        name, sep, command = line.partition(":")
        if sep and name.strip() and not line.lstrip().startswith("#"):
            programs.append(Program(name.strip(), command.strip()))
    return programs


def _exit_text(code: int) -> str:
    return f"was killed by signal {-code}" if code < 0 else f"exited with code {code}"


class Supervisor:
    def __init__(self, programs: list[Program], out: TextIO, stack_dir: Path) -> None:
        self._programs = programs
        self._out = out
        self._env = {**os.environ, MEMBER: str(stack_dir)}
        self._width = max(len(p.name) for p in programs)
        self._print_lock = threading.Lock()
        self._stop_reason: str | None = None

    def say(self, name: str, text: str) -> None:
        with self._print_lock, contextlib.suppress(OSError):  # the terminal may be gone (SIGHUP)
            self._out.write(f"{time.strftime('%H:%M:%S')} {name:<{self._width}} | {text}\n")
            self._out.flush()

    def _relay(self, name: str, stream: IO[bytes]) -> None:
        for raw in iter(stream.readline, b""):
            self.say(name, raw.decode(errors="replace").rstrip())

    def _start(self, program: Program) -> None:
        process = subprocess.Popen(
            ["bash", "-c", f"exec {program.command}"],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            env=self._env,
            start_new_session=True,  # its own process group, so what it started goes with it
        )
        program.process, program.started_at, program.restart_at = process, time.monotonic(), None
        assert process.stdout is not None
        threading.Thread(target=self._relay, args=(program.name, process.stdout), daemon=True).start()
        self.say("supervisor", f"started {program.name} (pid {process.pid})")

    def _exited(self, program: Program, code: int) -> None:
        """Schedule the restart of a program that died, or stop the stack when it keeps dying."""
        now = time.monotonic()
        assert program.process is not None
        _kill_group(program.process.pid, signal.SIGKILL)  # what it left running (worker children)
        program.process = None
        if now - program.started_at >= HEALTHY_AFTER_S:
            program.pause_s = FIRST_PAUSE_S
        program.exits.append(now)
        while program.exits and now - program.exits[0] > GIVE_UP_WINDOW_S:
            program.exits.popleft()
        if len(program.exits) >= GIVE_UP_EXITS:
            self._stop_reason = (
                f"{program.name} {_exit_text(code)}, its {len(program.exits)}th exit within "
                f"{GIVE_UP_WINDOW_S:.0f} s; stopping the stack (its data is kept) - see the lines above"
            )
            return
        self.say("supervisor", f"{program.name} {_exit_text(code)}; restarting it in {program.pause_s:.0f} s")
        program.restart_at = now + program.pause_s
        program.pause_s = min(program.pause_s * 2, LONGEST_PAUSE_S)

    def request_stop(self, reason: str) -> None:
        self._stop_reason = self._stop_reason or reason

    def run(self) -> int:
        for program in self._programs:
            self._start(program)
        while self._stop_reason is None:
            time.sleep(TICK_S)
            for program in self._programs:
                if program.process is not None and (code := program.process.poll()) is not None:
                    self._exited(program, code)
                elif program.restart_at is not None and time.monotonic() >= program.restart_at:
                    self._start(program)
        self.say("supervisor", f"stopping every process: {self._stop_reason}")
        self._stop_all()
        return 0 if self._stop_reason.startswith("asked") else 1

    def _stop_all(self) -> None:
        running = [p.process for p in reversed(self._programs) if p.process is not None]
        for process in running:
            _kill_group(process.pid, signal.SIGTERM)
        deadline = time.monotonic() + STOP_TIMEOUT_S
        for process in running:
            try:
                process.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                self.say("supervisor", f"pid {process.pid} did not stop within {STOP_TIMEOUT_S:.0f} s; killing it")
            _kill_group(process.pid, signal.SIGKILL)
            process.wait()


def _kill_group(pid: int, sig: signal.Signals) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.killpg(pid, sig)


def _hold_lock(stack_dir: Path) -> IO[str]:
    """The stack directory's lock, held while the stack runs (another start there is refused)."""
    handle = (stack_dir / LOCK).open("a+")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        raise SystemExit(f"bagmcp stack: a stack runs in {stack_dir} already") from None
    handle.truncate(0)
    handle.write(str(os.getpid()))
    handle.flush()
    return handle


def _start_watchdog(stack_dir: Path) -> subprocess.Popen[bytes]:
    """The watchdog (``watchdog``): in a session of its own, reading a pipe only this process writes to."""
    return subprocess.Popen(
        [sys.executable, "-m", "bagmcp_cli.stack.watchdog", str(stack_dir)],
        stdin=subprocess.PIPE,
        start_new_session=True,
    )


def main(argv: list[str]) -> int:
    stack_dir = Path(Env().text("BAGMCP_STACK_DIR", ".stack")).resolve()
    lock = _hold_lock(stack_dir)
    supervisor = Supervisor(read_procfile(Path(argv[1])), sys.stdout, stack_dir)
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, lambda number, _frame: supervisor.request_stop(f"asked to ({signal.Signals(number).name})"))
    watchdog = _start_watchdog(stack_dir)
    supervisor.say("supervisor", f"started watchdog (pid {watchdog.pid})")
    try:
        return supervisor.run()
    finally:
        lock.close()


if __name__ == "__main__":
    sys.exit(main(sys.argv))
