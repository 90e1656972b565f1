"""The one place errors become HTTP responses, all of one shape: ``{"error": {"code", "message"}}``."""

from __future__ import annotations

import logging
from collections.abc import Sequence

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.requests import ClientDisconnect

from bagmcp_shared.errors import (
    AmbiguousBagError,
    ArgumentError,
    BagError,
    BagmcpError,
    BagNotFoundError,
    BagNotReadyError,
    NameTakenError,
    ObjectNotFoundError,
    StorageError,
    TimeError,
    TopicNotFoundError,
    sentence,
)

StatusTable = Sequence[tuple[type[BagmcpError], int, str]]
SHARED_STATUSES: StatusTable = [
    (BagNotFoundError, 404, "bag_not_found"),
    (TopicNotFoundError, 404, "topic_not_found"),
    (ObjectNotFoundError, 404, "not_found"),
    (AmbiguousBagError, 409, "ambiguous_bag"),
    (NameTakenError, 409, "name_taken"),
    (BagError, 422, "invalid_bag"),
    (BagNotReadyError, 409, "bag_not_ready"),
    (ArgumentError, 400, "bad_argument"),
    (TimeError, 400, "bad_time"),
    (StorageError, 503, "storage_unavailable"),
]
WWW_AUTHENTICATE = 'Bearer error="invalid_token"'
CLIENT_GONE = 499  # nginx's "client closed request": nobody reads it, the access log shows it

log = logging.getLogger(__name__)


class HttpError(Exception):
    """An HTTP error a route raises on purpose (auth, routing), answered in the one shape."""

    def __init__(self, status: int, code: str, message: str, *, bearer: bool = False) -> None:
        super().__init__(message)
        self.status, self.code, self.message, self.bearer = status, code, message, bearer


def error_response(status: int, code: str, message: str, *, bearer: bool = False) -> JSONResponse:
    headers = {"WWW-Authenticate": WWW_AUTHENTICATE} if bearer or status == 401 else None
    return JSONResponse({"error": {"code": code, "message": message}}, status_code=status, headers=headers)


def install_error_handlers(app: FastAPI, statuses: StatusTable = ()) -> None:
    """Map the project's errors (``statuses`` first, then the shared ones), HTTP errors and bad
    requests to the one error shape."""
    table = [*statuses, *SHARED_STATUSES]

    async def project_error(_request: Request, err: Exception) -> Response:
        assert isinstance(err, BagmcpError)
        status, code = next(((s, c) for t, s, c in table if isinstance(err, t)), (400, "error"))
        return error_response(status, code, sentence(err))

    async def http_error(_request: Request, err: Exception) -> Response:
        assert isinstance(err, HttpError)
        return error_response(err.status, err.code, err.message, bearer=err.bearer)

    async def starlette_error(_request: Request, err: Exception) -> Response:
        assert isinstance(err, StarletteHTTPException)
        code = {401: "unauthorized", 403: "forbidden", 404: "not_found", 405: "method_not_allowed"}.get(
            err.status_code, "http_error"
        )
        return error_response(err.status_code, code, str(err.detail))

    async def invalid_request(_request: Request, err: Exception) -> Response:
        assert isinstance(err, RequestValidationError)
        problems = "; ".join(f"{'.'.join(str(p) for p in e['loc'])}: {e['msg']}" for e in err.errors()[:5])
        return error_response(400, "bad_request", f"the request is not valid: {problems}")

    async def unexpected(_request: Request, _err: Exception) -> Response:
        """A bug: the caller gets the one shape and no traceback (Starlette raises the error again after
        this answer, so the server logs the traceback)."""
        message = "the server failed unexpectedly; the details are in its log (retry, or report it if it persists)"
        return error_response(500, "internal_error", message)

    async def client_gone(request: Request, _err: Exception) -> Response:
        """The client closed the connection before its request body was read (an upload cancelled or cut): one
        line, no traceback (there were two per cut upload, gateway and service); what it sent is dropped."""
        log.warning("the client went away during %s %s; what it sent was dropped", request.method, request.url.path)
        return Response(status_code=CLIENT_GONE)

    app.add_exception_handler(BagmcpError, project_error)
    app.add_exception_handler(ClientDisconnect, client_gone)
    app.add_exception_handler(Exception, unexpected)
    app.add_exception_handler(HttpError, http_error)
    app.add_exception_handler(StarletteHTTPException, starlette_error)
    app.add_exception_handler(RequestValidationError, invalid_request)
