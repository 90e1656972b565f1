"""Keeping what flight-log libraries print out of the process's own streams.

pyulog prints warnings about corrupt data to stdout, which carries MCP in ``bagmcp stdio``; pymavlink
prints to both, and its C indexer writes one line to file descriptor 2 for every damaged byte it skips
(thousands for a damaged log). While a log is opened, Python's streams and descriptor 2 go to a
buffer; the caller turns what was printed into a note. Lines the libraries did not write (another thread
logging at the same moment) are passed on to the real stderr afterwards, so nothing else is lost. One log
is opened this way at a time (a lock): two interleaved swaps of descriptor 2 could leave it pointing at a
closed buffer.
"""

from __future__ import annotations

import io
import os
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager, redirect_stderr, redirect_stdout

_ONE_AT_A_TIME = threading.Lock()
PYMAVLINK_BYTE_SKIP = "bad header"
PYMAVLINK_C_LINES = (PYMAVLINK_BYTE_SKIP, "unknown msg type", "Invalid length in FMT message")  # its indexer's


@contextmanager
def library_output() -> Iterator[io.StringIO]:
    """Collects what is printed inside the block (Python's stdout and stderr, and descriptor 2)."""
    printed = io.StringIO()
    with _ONE_AT_A_TIME, tempfile.TemporaryFile() as sink:
        sys.stderr.flush()
        saved = os.dup(2)
        os.dup2(sink.fileno(), 2)
        try:
            with redirect_stdout(printed), redirect_stderr(printed):
                yield printed
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            _sort(sink.read().decode("utf-8", "replace"), printed)


def _sort(text: str, printed: io.StringIO) -> None:
    lines = text.splitlines()
    others = [line for line in lines if not line.startswith(PYMAVLINK_C_LINES)]
    skipped = sum(line.startswith(PYMAVLINK_BYTE_SKIP) for line in lines)
    if skipped:
        printed.write(f"skipped {skipped} damaged bytes\n")
    printed.writelines(f"{line}\n" for line in lines if line.startswith(PYMAVLINK_C_LINES[1:]))
    if others:
        sys.stderr.write("\n".join(others) + "\n")


def printed_note(text: str, *, library: str) -> str | None:
    """One note for what a library printed while reading (None when it printed nothing)."""
    flat = " ".join(text.split())
    return f"{library} reported damage while reading: {flat[:300]}" if flat else None
