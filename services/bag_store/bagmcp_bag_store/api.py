"""REST routes under /api/v1: thin adapters over upload, catalog queries, download and delete."""

from __future__ import annotations

import tarfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Annotated

import anyio
from fastapi import APIRouter, Query, Request
from fastapi.responses import FileResponse, JSONResponse, Response, StreamingResponse

from bagmcp_bag_store.errors import ReadOnlyError
from bagmcp_bag_store.ingest.upload import UploadPolicy, receive, store_upload
from bagmcp_bag_store.queries import catalog_queries
from bagmcp_bag_store.reports import BagList
from bagmcp_shared.access import BagAccess
from bagmcp_shared.catalog import BagRecord, exact_bag, resolve_bag


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
        path = access.files.path_for(record)
        if path.is_file():
            return FileResponse(path, filename=path.name, media_type="application/octet-stream")
        headers = {"Content-Disposition": f'attachment; filename="{record.name}.tar"'}
        return StreamingResponse(_tar_stream(path), media_type="application/x-tar", headers=headers)

    @router.delete("/bags/{ref}", status_code=204)
    def delete(ref: str) -> Response:
        record = exact_bag(access.catalog, ref)
        policy.shelf.remove(record)
        access.cache.discard(record.id)
        forget(record.id)
        return Response(status_code=204)

    return router
