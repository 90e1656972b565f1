"""REST routes under /api/v1: thin adapters over upload, catalog queries, download and delete."""

from __future__ import annotations

import tarfile
from collections.abc import Callable, Iterator
from typing import Annotated

import anyio
from fastapi import APIRouter, Query, Request
from fastapi.responses import JSONResponse, Response, StreamingResponse

from bagmcp_bag_store.errors import ReadOnlyError
from bagmcp_bag_store.ingest.upload import UploadPolicy, receive, store_upload
from bagmcp_bag_store.queries import catalog_queries
from bagmcp_bag_store.reports import BagList
from bagmcp_shared.access import BagAccess
from bagmcp_shared.access.parts import BagPart
from bagmcp_shared.catalog import BagRecord, exact_bag, resolve_bag


def _tar_stream(name: str, parts: list[BagPart]) -> Iterator[bytes]:
    """A ROS 2 bag directory as a tar stream under ``name``/, produced while it is sent (no temporary copy)."""
    for part in parts:
        info = tarfile.TarInfo(f"{name}/{part.name}")
        info.size = part.size
        yield info.tobuf(format=tarfile.PAX_FORMAT)
        yield from part.chunks()
        if remainder := info.size % tarfile.BLOCKSIZE:
            yield b"\0" * (tarfile.BLOCKSIZE - remainder)
    yield b"\0" * (2 * tarfile.BLOCKSIZE)


def _download(record: BagRecord, parts: list[BagPart]) -> Response:
    """The bag file as it is stored, or a ROS 2 directory as a tar; streamed, with its length when known."""
    if record.layout == "file":
        part = parts[0]
        headers = {"Content-Disposition": f'attachment; filename="{part.name}"', "Content-Length": str(part.size)}
        return StreamingResponse(part.chunks(), media_type="application/octet-stream", headers=headers)
    headers = {"Content-Disposition": f'attachment; filename="{record.name}.tar"'}
    return StreamingResponse(_tar_stream(record.name, parts), media_type="application/x-tar", headers=headers)


def _check_uploads(policy: UploadPolicy) -> None:
    if not policy.uploads:
        raise ReadOnlyError("this server serves a read-only folder of bags; uploads are disabled")


def build_router(
    access: BagAccess, policy: UploadPolicy, *, forget: Callable[[str], None] = lambda _bag_id: None
) -> APIRouter:
    """``forget`` drops a deleted bag from what this process keeps in memory beyond the opened-bag cache."""
    router = APIRouter(prefix="/api/v1")

    @router.post("/bags", status_code=201)
    async def upload(
        request: Request, filename: str, name: str | None = None, tags: Annotated[list[str] | None, Query()] = None
    ) -> JSONResponse:
        _check_uploads(policy)
        received = await receive(request.stream(), policy.upload_dir, max_bytes=policy.max_bytes)
        stored = await anyio.to_thread.run_sync(
            lambda: store_upload(policy, received, filename=filename, name=name, tags=tags or [])
        )
        bag = stored.record.model_dump(mode="json", exclude={"summary"})
        body = {"bag": bag, "duplicate": not stored.created, "notes": stored.notes}
        return JSONResponse(body, status_code=201 if stored.created else 200)

    @router.get("/bags")
    def list_all(name: str | None = None, tag: str | None = None, offset: int = 0, limit: int = 50) -> BagList:
        asked = catalog_queries.ListBagsParams.model_construct(name=name, tag=tag, offset=offset, limit=limit)
        return catalog_queries.list_bags(access.catalog, asked)

    @router.get("/bags/{ref}")
    def get_one(ref: str) -> BagRecord:
        return resolve_bag(access.catalog, ref)

    @router.get("/bags/{ref}/download")
    def download(ref: str) -> Response:
        record = resolve_bag(access.catalog, ref)
        return _download(record, access.files.parts_of(record))

    @router.delete("/bags/{ref}", status_code=204)
    def delete(ref: str) -> Response:
        record = exact_bag(access.catalog, ref)
        policy.shelf.remove(record)
        access.cache.discard(record.id)
        forget(record.id)
        return Response(status_code=204)

    return router
