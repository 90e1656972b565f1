"""Bounded regexes for search_messages' regex condition.

Regexes run on RE2 (the ``google-re2`` wheel), not on the ``regex`` package: ``regex`` expands counted
repeats when it compiles, about 270 bytes per copy, so ``a{1000000000}`` (13 characters) grew a server to
21.9 GB and ``(?:a{1000}){1000}`` costs 262 MB. RE2 refuses a repeat count over 1000 (nested ones
multiply), holds a compiled pattern and its match cache to ``max_mem`` and matches in time linear in the
text, so no pattern can take a process's memory or hang a match; what it gives up is lookaround and
backreferences, which search_messages does not need. Checking ``regex`` patterns by hand instead would be
a parser of its whole syntax (comments, verbose mode, nested sets) kept in step with the package.
"""

from __future__ import annotations

import re
import time

import re2  # type: ignore[import-untyped]  # google-re2 ships no type hints

from bagmcp_shared.errors import ArgumentError

MAX_PATTERN = 256
REGEX_MEMORY_BYTES = 8 << 20  # RE2's own default: a compiled pattern and its match cache
MAX_REPEAT = 1000  # RE2's own limit on a counted repeat
_COUNTED_REPEAT = re.compile(r"\{(\d+)(?:,(\d*))?\}")
_RE2_LIMITS = f"RE2 allows repeat counts up to {MAX_REPEAT}, nested ones multiplied; use + or * instead"
# The CPU time one search's matches may take, all messages together. CPU time of the matching thread, not wall
# time: on a loaded 2-core host (the test suite running beside a stack) a regex over 300,000 short messages spent
# 1.6 s matching alone here but passed 5 s of wall time, its calls waiting for a core or for the GIL.
REGEX_BUDGET_S = 5.0


def _re2_options() -> object:
    options = re2.Options()
    options.max_mem = REGEX_MEMORY_BYTES
    options.log_errors = False  # a caller's bad pattern is their error, not a line in the server log
    return options


class BoundedRegex:
    """A pattern compiled by RE2 within ``REGEX_MEMORY_BYTES``, with a total CPU-time budget over all matches
    (reading the thread's CPU clock costs about 0.5 us a call against about 4 us for a match of a short string)."""

    def __init__(self, pattern: str, *, budget_s: float = REGEX_BUDGET_S) -> None:
        if len(pattern) > MAX_PATTERN:
            raise ArgumentError(f"regex patterns are limited to {MAX_PATTERN} characters")
        _refuse_large_counts(pattern)
        try:
            self._compiled = re2.compile(pattern, _re2_options())
        except re2.error as err:
            raise ArgumentError(f"invalid regex {pattern!r}: {_reason(err)}") from err
        self._spent = 0.0
        self._budget_s = budget_s

    def search(self, text: str) -> bool:
        began = time.thread_time()
        found = self._compiled.search(text) is not None
        self._spent += time.thread_time() - began
        if self._spent > self._budget_s:
            raise ArgumentError(f"the regex used its {self._budget_s:g} s budget; narrow the time window")
        return found


def _refuse_large_counts(pattern: str) -> None:
    """RE2 reads a repeat count it cannot take (``a{1000000000}``) as literal text, which would quietly match
    nothing; say so instead."""
    for found in _COUNTED_REPEAT.finditer(pattern):
        if any(int(number) > MAX_REPEAT for number in found.groups() if number):
            raise ArgumentError(f"invalid regex {pattern!r}: the repeat {found.group(0)} is too large ({_RE2_LIMITS})")


def _reason(err: Exception) -> str:
    """RE2's reason in words, with what to do about the two a hostile or ambitious pattern meets."""
    reason = err.args[0].decode("utf-8", "replace") if err.args and isinstance(err.args[0], bytes) else str(err)
    if "repetition size" in reason or "too large" in reason:
        return f"{reason} ({_RE2_LIMITS})"
    if "perl operator" in reason or "escape sequence" in reason:
        return f"{reason} (RE2 syntax: no lookaround or backreferences)"
    return reason
