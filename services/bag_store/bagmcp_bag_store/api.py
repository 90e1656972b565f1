"""REST routes under /api/v1 (thin adapters) and the one place errors become HTTP responses."""

from __future__ import annotations

import tarfile
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import anyio
from fastapi import APIRouter, FastAPI, Query, Request
from fastapi.responses import FileResponse, JSONResponse, Response, StreamingResponse

from bagmcp_bag_store import queries
from bagmcp_bag_store.catalog import resolve_bag
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import (
    AmbiguousBagError,
    ArgumentError,
    BagNotFoundError,
    BagNotReadyError,
    NameTakenError,
    ReadOnlyError,
    UploadError,
    UploadTooLargeError,
)
from bagmcp_bag_store.models import BagRecord
from bagmcp_bag_store.results import BagList
from bagmcp_bag_store.upload import delete_bag, receive, store_upload
from bagmcp_shared.errors import BagError, BagmcpError, StorageError, TimeError, TopicNotFoundError

_STATUS: list[tuple[type[BagmcpError], int, str]] = [
    (BagNotFoundError, 404, "bag_not_found"),
    (TopicNotFoundError, 404, "topic_not_found"),
    (AmbiguousBagError, 409, "ambiguous_bag"),
    (NameTakenError, 409, "name_taken"),
    (UploadTooLargeError, 413, "upload_too_large"),
    (UploadError, 400, "bad_upload"),
    (BagError, 422, "invalid_bag"),
    (ReadOnlyError, 405, "read_only"),
    (BagNotReadyError, 409, "bag_not_ready"),
    (ArgumentError, 400, "bad_argument"),
    (TimeError, 400, "bad_time"),
    (StorageError, 503, "storage_unavailable"),
]


def error_response(err: BagmcpError) -> JSONResponse:
    """``{"error": {"code", "message"}}`` with the status that fits the error."""
    status, code = next(((s, c) for t, s, c in _STATUS if isinstance(err, t)), (400, "error"))
    return JSONResponse({"error": {"code": code, "message": str(err)}}, status_code=status)


def install_error_handler(app: FastAPI) -> None:
    async def handle(_request: Request, err: Exception) -> Response:
        assert isinstance(err, BagmcpError)
        return error_response(err)

    app.add_exception_handler(BagmcpError, handle)


def _tar_stream(root: Path) -> Iterator[bytes]:
    """A ROS 2 bag directory as a tar stream, produced while it is sent (no temporary copy)."""
    for path in sorted(p for p in root.iterdir() if p.is_file()):
        info = tarfile.TarInfo(f"{root.name}/{path.name}")
        info.size = path.stat().st_size
        info.mtime = int(path.stat().st_mtime)
        yield info.tobuf(format=tarfile.PAX_FORMAT)
        with path.open("rb") as file:
            while chunk := file.read(1 << 20):
                yield chunk
        if remainder := info.size % tarfile.BLOCKSIZE:
            yield b"\0" * (tarfile.BLOCKSIZE - remainder)
    yield b"\0" * (2 * tarfile.BLOCKSIZE)


def build_router(deps: BagStoreDeps, *, upload_dir: Path, max_upload_bytes: int) -> APIRouter:
    router = APIRouter(prefix="/api/v1")

    @router.post("/bags", status_code=201)
    async def upload(
        request: Request,
        filename: str,
        name: str | None = None,
        tags: Annotated[list[str] | None, Query()] = None,
    ) -> JSONResponse:
        if deps.store is None or not deps.uploads:
            raise ReadOnlyError("this server serves a read-only folder of bags; uploads are disabled")
        received = await receive(request.stream(), upload_dir, max_bytes=max_upload_bytes)
        record, created = await anyio.to_thread.run_sync(
            lambda: store_upload(
                deps,
                received,
                filename=filename,
                name=name,
                tags=tags or [],
                staging_root=upload_dir,
                max_bytes=max_upload_bytes,
            )
        )
        body = {"bag": record.model_dump(mode="json", exclude={"summary"}), "duplicate": not created}
        return JSONResponse(body, status_code=201 if created else 200)

    @router.get("/bags")
    def list_all(name: str | None = None, tag: str | None = None, offset: int = 0, limit: int = 50) -> BagList:
        return queries.list_bags(deps, name=name, tag=tag, offset=offset, limit=limit)

    @router.get("/bags/{ref}")
    def get_one(ref: str) -> BagRecord:
        return resolve_bag(deps.catalog, ref)

    @router.get("/bags/{ref}/download")
    def download(ref: str) -> Response:
        record = resolve_bag(deps.catalog, ref)
        path = deps.files.path_for(record)
        if path.is_file():
            return FileResponse(path, filename=path.name, media_type="application/octet-stream")
        headers = {"Content-Disposition": f'attachment; filename="{record.name}.tar"'}
        return StreamingResponse(_tar_stream(path), media_type="application/x-tar", headers=headers)

    @router.delete("/bags/{ref}", status_code=204)
    def delete(ref: str) -> Response:
        delete_bag(deps, resolve_bag(deps.catalog, ref))
        return Response(status_code=204)

    return router
