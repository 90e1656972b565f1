"""One structured record per tool call (who, tool, upstream, duration, outcome, sizes; argument values
only when configured), written as JSON lines by a background thread, off the request path."""

from __future__ import annotations

import json
import logging
import logging.handlers
import queue
import sys
import time
from dataclasses import asdict, dataclass, field
from typing import Literal

Outcome = Literal["ok", "error", "denied", "rate_limited", "unavailable", "unknown_tool"]
AUDIT_LOGGER = "bagmcp.audit"


@dataclass
class AuditRecord:
    token: str
    tool: str
    upstream: str | None
    outcome: Outcome = "ok"
    duration_ms: float = 0.0
    request_bytes: int = 0
    response_bytes: int = 0
    arguments: dict[str, object] | None = None
    ts: float = field(default_factory=time.time)


class _JsonLines(logging.Formatter):
    def format(self, record: logging.LogRecord) -> str:
        body = getattr(record, "audit", None)
        return json.dumps(body, default=str, separators=(",", ":")) if isinstance(body, dict) else record.getMessage()


class AuditLog:
    """``stream`` None writes to stderr. ``close`` flushes what is queued."""

    def __init__(self, *, stream: object | None = None) -> None:
        self._queue: queue.SimpleQueue[logging.LogRecord] = queue.SimpleQueue()
        handler = logging.StreamHandler(stream or sys.stderr)  # type: ignore[arg-type]
        handler.setFormatter(_JsonLines())
        self._listener = logging.handlers.QueueListener(self._queue, handler)
        self._logger = logging.getLogger(f"{AUDIT_LOGGER}.{id(self)}")
        self._logger.propagate = False
        self._logger.setLevel(logging.INFO)
        self._logger.addHandler(logging.handlers.QueueHandler(self._queue))
        self._listener.start()

    def write(self, record: AuditRecord) -> None:
        body = {k: v for k, v in asdict(record).items() if v is not None}
        self._logger.info("audit", extra={"audit": body})

    def close(self) -> None:
        self._listener.stop()
