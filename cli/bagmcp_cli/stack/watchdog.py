"""The watchdog of a `make stack` supervisor: it waits until the supervisor is gone, however it went (Ctrl-C,
SIGHUP, SIGTERM, SIGKILL, a crash), and then stops every process the supervisor started in its directory
that still runs (TERM, then KILL after 10 s). Without it, a killed supervisor left all its processes running.

The supervisor starts it in a session of its own (so the terminal's signals do not reach it) with a pipe on
its stdin that only the supervisor holds: the end of that pipe is the supervisor's death, with no polling.
After a clean stop it finds nothing and says nothing.

``python -m bagmcp_cli.stack.watchdog STACK_DIR``
"""

from __future__ import annotations

import contextlib
import signal
import sys
from pathlib import Path

from bagmcp_cli.stack.leftovers import stop_leftovers


def _say(text: str) -> None:
    with contextlib.suppress(OSError):  # the terminal it printed to is gone
        print(f"bagmcp stack watchdog: {text}", file=sys.stderr, flush=True)


def main(argv: list[str]) -> int:
    for sig in (signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, signal.SIG_IGN)
    stack_dir = Path(argv[1])
    while sys.stdin.buffer.read(4096):
        pass
    stop_leftovers(stack_dir, _say, whose="the stack whose supervisor ended")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
