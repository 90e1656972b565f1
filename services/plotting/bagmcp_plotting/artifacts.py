"""Plot artifacts in object storage: named by what was asked (so the same request reuses its image),
the PNG next to the report that describes it, and the REST route that serves them."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable

from fastapi import APIRouter
from fastapi.responses import Response
from pydantic import BaseModel

from bagmcp_plotting.reports import PlotReport
from bagmcp_shared import keys
from bagmcp_shared.errors import ObjectNotFoundError
from bagmcp_shared.storage import ObjectStore

ARTIFACT_URI = "bagmcp://artifacts/{artifact}"  # the MCP resource of a stored plot
ARTIFACT_FORMAT = 2  # bump when rendering changes, so old images are not reused


def artifact_id(kind: str, params: BaseModel, bag_ids: list[str]) -> str:
    """The same plot of the same bag contents always gets the same id."""
    request = {"v": ARTIFACT_FORMAT, "kind": kind, "params": params.model_dump(mode="json"), "bags": bag_ids}
    return hashlib.sha256(json.dumps(request, sort_keys=True).encode()).hexdigest()[:24]


class Artifacts:
    """``base_url`` is where callers reach the REST API (the gateway), "" for a relative link."""

    def __init__(self, store: ObjectStore, *, base_url: str = "") -> None:
        self._store = store
        self._base = base_url.rstrip("/")

    def url(self, artifact: str) -> str:
        return f"{self._base}/api/v1/artifacts/{artifact}"

    def find(self, artifact: str) -> PlotReport | None:
        """The report of a stored artifact, or None (the image is stored first, the report last)."""
        try:
            with self._store.open_read(keys.artifact(artifact, "json")) as stream:
                return PlotReport.model_validate_json(stream.read())
        except ObjectNotFoundError:
            return None

    def save(self, artifact: str, png: bytes, report: PlotReport) -> None:
        self._store.put_bytes(keys.artifact(artifact, "png"), png)
        self._store.put_bytes(keys.artifact(artifact, "json"), report.model_dump_json().encode())

    def png(self, artifact: str) -> bytes:
        """The stored PNG; ObjectNotFoundError (saying what to do) for an id that names none."""
        missing = f"no plot artifact {artifact!r}; use the artifact id of a plot's answer, or plot again"
        if not artifact.isalnum():
            raise ObjectNotFoundError(missing)
        try:
            with self._store.open_read(keys.artifact(artifact, "png")) as stream:
                return stream.read()
        except ObjectNotFoundError as err:
            raise ObjectNotFoundError(missing) from err

    def cached(self, artifact: str, make: Callable[[], PlotReport]) -> PlotReport:
        """The stored report of ``artifact``, or ``make`` (which renders and saves it)."""
        return self.find(artifact) or make()


def build_artifact_router(artifacts: Artifacts) -> APIRouter:
    router = APIRouter(prefix="/api/v1")

    @router.get("/artifacts/{artifact}", response_class=Response)
    def download(artifact: str) -> Response:
        return Response(artifacts.png(artifact), media_type="image/png")

    return router
