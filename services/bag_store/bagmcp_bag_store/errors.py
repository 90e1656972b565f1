"""Bag-store errors; mapped to HTTP in api.py and to MCP tool errors in tools.py, nowhere else."""

from __future__ import annotations

from bagmcp_shared.errors import BagmcpError


class BagNotFoundError(BagmcpError):
    """No bag matches the id, name or prefix the caller gave."""


class AmbiguousBagError(BagmcpError):
    """A prefix matches more than one bag."""


class NameTakenError(BagmcpError):
    """Another bag already has this name."""


class UploadError(BagmcpError):
    """An upload is empty, too large, not a bag, or an unsafe archive."""


class UploadTooLargeError(UploadError):
    """An upload exceeds the configured size limit."""


class ReadOnlyError(BagmcpError):
    """The store serves a read-only folder; uploads and deletes are refused."""


class BagNotReadyError(BagmcpError):
    """The bag is still being ingested, or its ingest failed."""


class ArgumentError(BagmcpError):
    """A tool or route argument is out of range or of the wrong kind."""
