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


class QueryError(BagmcpError):
    """A fleet query is not one valid read-only SELECT over the views, or names what does not exist."""


class QueryForbiddenError(QueryError):
    """A fleet query reads a view the caller's token may not read."""


class QueryStoppedError(QueryError):
    """A fleet query ran past its time or memory limit, or needs more data than the query cache holds."""


STATUSES: StatusTable = [
    (UploadTooLargeError, 413, "upload_too_large"),
    (UploadError, 400, "bad_upload"),
    (ReadOnlyError, 405, "read_only"),
    (QueryForbiddenError, 403, "query_forbidden"),
    (QueryStoppedError, 422, "query_stopped"),
    (QueryError, 400, "bad_query"),
]
