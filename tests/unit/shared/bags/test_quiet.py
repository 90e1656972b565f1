"""What flight-log libraries print while a log opens becomes a note: Python prints and descriptor-2 writes
(pymavlink's C indexer) are kept out of the process's streams; other lines reach stderr afterwards."""

from __future__ import annotations

import os
import threading

import pytest

from bagmcp_shared.bags.quiet import library_output, printed_note


def test_library_prints_and_c_level_writes_are_collected_not_shown(capfd: pytest.CaptureFixture[str]) -> None:
    with library_output() as printed:
        print("Warning: no subscription found for message id 3")
        for offset in range(3):
            os.write(2, f"bad header 0x8c69 at {offset}\n".encode())
        os.write(2, b"unknown msg type 0x83 (131) at 1756\n")
        os.write(2, b"a log line of another thread\n")
    shown = capfd.readouterr()
    text = printed.getvalue()
    assert "no subscription found" in text
    assert "skipped 3 damaged bytes" in text
    assert "unknown msg type 0x83" in text
    assert shown.out == ""
    assert shown.err == "a log line of another thread\n"
    assert (
        printed_note(text, library="pymavlink") == f"pymavlink reported damage while reading: {' '.join(text.split())}"
    )
    assert printed_note("  \n", library="pyulog") is None


def test_two_threads_opening_logs_leave_descriptor_2_where_it_was(capfd: pytest.CaptureFixture[str]) -> None:
    def noisy() -> None:
        for _ in range(20):
            with library_output():
                os.write(2, b"bad header 0x0000 at 1\n")

    threads = [threading.Thread(target=noisy) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    os.write(2, b"still here\n")
    assert capfd.readouterr().err == "still here\n"
