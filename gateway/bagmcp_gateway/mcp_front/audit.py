"""One structured record per tool call or resource read (who, tool, upstream, duration, outcome, sizes;
argument values only when configured), written as JSON lines by a background thread, off the request path."""

from __future__ import annotations

import json
import logging
import queue
import sys
import threading
import time
from dataclasses import asdict, dataclass, field
from typing import Literal, TextIO

Outcome = Literal["ok", "error", "denied", "rate_limited", "unavailable", "unknown_tool", "unknown_resource"]
log = logging.getLogger(__name__)


@dataclass
class AuditRecord:
    token: str
    tool: str
    upstream: str | None
    outcome: Outcome = "ok"
    duration_ms: float = 0.0
    request_bytes: int = 0
    response_bytes: int = 0
    fetched_bytes: int | None = None  # what the upstream fetched from the object store for the call
    arguments: dict[str, object] | None = None
    ts: float = field(default_factory=time.time)


def _line(record: AuditRecord) -> str:
    body = {k: v for k, v in asdict(record).items() if v is not None}
    return json.dumps(body, default=str, separators=(",", ":")) + "\n"


class AuditLog:
    """``stream`` None writes to stderr. ``close`` writes what is queued, then stops the writer.

    The request path only queues the record; a background thread turns it into a JSON line and writes it."""

    def __init__(self, *, stream: TextIO | None = None) -> None:
        self._stream = stream or sys.stderr
        self._queue: queue.SimpleQueue[AuditRecord | None] = queue.SimpleQueue()
        self._writer = threading.Thread(target=self._write_all, name="bagmcp-audit", daemon=True)
        self._writer.start()

    def _write_all(self) -> None:
        while (record := self._queue.get()) is not None:
            try:
                self._stream.write(_line(record))
                self._stream.flush()
            except (OSError, ValueError) as err:  # a closed or full stream: say so once per record, keep going
                log.warning("audit record not written: %s", err)

    def write(self, record: AuditRecord) -> None:
        self._queue.put(record)

    def close(self) -> None:
        self._queue.put(None)
        self._writer.join(timeout=10)
