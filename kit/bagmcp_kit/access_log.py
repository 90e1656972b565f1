"""Logs without secrets: a token sent in a query string (``?token=...``) never reaches a log, neither in the
access log of a server nor in the request log of the HTTP client that forwards it."""

from __future__ import annotations

import logging
import re

_SECRET_PARAMETER = re.compile(r"([?&][^=&#]*(?:token|key|secret|password|auth)[^=&#]*=)[^&#\s\"]*", re.IGNORECASE)
LOGGERS_WITH_URLS = ("uvicorn.access", "httpx")


def redacted(target: str) -> str:
    """``target`` (a URL or a path with its query) with the values of secret-looking parameters replaced."""
    return _SECRET_PARAMETER.sub(r"\1REDACTED", target)


class RedactSecrets(logging.Filter):
    """Rewrites a record's arguments that hold a query string (uvicorn logs the path, httpx the URL)."""

    def filter(self, record: logging.LogRecord) -> bool:
        if isinstance(record.args, tuple):
            record.args = tuple(redacted(str(a)) if "?" in str(a) else a for a in record.args)
        return True


def redact_access_log() -> None:
    """Install the filter on the loggers that print URLs (idempotent)."""
    for name in LOGGERS_WITH_URLS:
        logger = logging.getLogger(name)
        if not any(isinstance(f, RedactSecrets) for f in logger.filters):
            logger.addFilter(RedactSecrets())
