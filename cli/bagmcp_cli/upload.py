"""``bagmcp upload``: send a bag file or a ROS 2 bag directory (as a tar stream) to the REST API."""

from __future__ import annotations

import sys
import tarfile
import tempfile
from collections.abc import Iterator
from pathlib import Path

import httpx

from bagmcp_shared.errors import BagmcpError

_CHUNK = 1 << 20


class UploadFailedError(BagmcpError):
    """The server refused the upload or could not be reached."""


def _progress(done: int, total: int, name: str) -> None:
    if not sys.stderr.isatty():
        return
    width = 30
    filled = width * done // max(total, 1)
    sys.stderr.write(f"\r{name} [{'#' * filled}{'.' * (width - filled)}] {done / 2**20:.1f}/{total / 2**20:.1f} MiB")
    if done >= total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _chunks(path: Path, name: str) -> Iterator[bytes]:
    total, done = path.stat().st_size, 0
    with path.open("rb") as file:
        while chunk := file.read(_CHUNK):
            done += len(chunk)
            _progress(done, total, name)
            yield chunk


def upload(path: Path, *, url: str, token: str | None, name: str | None = None) -> dict[str, object]:
    """Upload and return the server's JSON answer (``bag`` and ``duplicate``)."""
    if not path.exists():
        raise UploadFailedError(f"{path}: no such file or directory")
    with tempfile.TemporaryDirectory(prefix="bagmcp-upload-") as tmp:
        body = path
        filename = path.name
        if path.is_dir():
            body = Path(tmp) / f"{path.name}.tar"
            with tarfile.open(body, "w") as tar:
                tar.add(path, arcname=path.name)
            filename = body.name
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        params = {"filename": filename, **({"name": name} if name else {})}
        try:
            response = httpx.post(
                f"{url.rstrip('/')}/api/v1/bags",
                params=params,
                headers=headers,
                content=_chunks(body, path.name),
                timeout=httpx.Timeout(30.0, read=3600.0),
            )
        except httpx.HTTPError as err:
            raise UploadFailedError(f"cannot reach {url}: {err}") from err
    try:
        answer = response.json()
    except ValueError:
        answer = {}
    if response.status_code >= 400:
        error = answer.get("error", {}) if isinstance(answer, dict) else {}
        message = error.get("message") if isinstance(error, dict) else None
        raise UploadFailedError(f"upload refused ({response.status_code}): {message or answer or response.text}")
    if not isinstance(answer, dict):
        raise UploadFailedError(f"unexpected answer from {url}: {response.text[:200]}")
    return answer
