"""Download a stored bag over REST and summarize it with the `bagmcp info` command."""

from __future__ import annotations

import io
import json
import subprocess
import tarfile
from pathlib import Path
from typing import Any

import httpx

from tests.fixtures.processes import BIN


def download_info(base_url: str, token: str | None, bag_id: str, work: Path) -> dict[str, Any]:
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    response = httpx.get(f"{base_url}/api/v1/bags/{bag_id}/download", headers=headers, timeout=60)
    assert response.status_code == 200, response.text
    if response.headers["content-type"] == "application/x-tar":
        with tarfile.open(fileobj=io.BytesIO(response.content)) as tar:
            tar.extractall(work, filter="data")
            target = work / tar.getnames()[0].split("/")[0]
    else:
        target = work / "downloaded.bag"
        target.write_bytes(response.content)
    command = [str(BIN / "bagmcp"), "info", "--json", str(target)]
    result = subprocess.run(command, capture_output=True, text=True, check=False, timeout=60)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)  # type: ignore[no-any-return]
