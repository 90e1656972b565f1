"""Bag-store errors; mapped to HTTP in api.py's status table and to tool errors by the kit."""

from __future__ import annotations

from bagmcp_kit.http_errors import StatusTable
from bagmcp_shared.errors import BagmcpError


class UploadError(BagmcpError):
    """An upload is empty, too large, not a bag, or an unsafe archive."""


class UploadTooLargeError(UploadError):
    """An upload exceeds the configured size limit."""


class ReadOnlyError(BagmcpError):
    """The store serves a read-only folder; uploads and deletes are refused."""


STATUSES: StatusTable = [
    (UploadTooLargeError, 413, "upload_too_large"),
    (UploadError, 400, "bad_upload"),
    (ReadOnlyError, 405, "read_only"),
]
