"""What a team process leaves for later: a service imports no Celery until it sends its first task
(``bagmcp_kit.runtime.sender``), and neither the plotting service nor its worker imports matplotlib until it
first draws (``bagmcp_plotting.drawing``). Each costs start-up CPU in every process of a stack (about 0.045 s
and 0.43 s), so a module that imports them again at the top shows here rather than only in a slower stack."""

from __future__ import annotations

import json
import os
import subprocess
import sys

ENTRY_POINTS = (
    "bagmcp_bag_store.__main__",
    "bagmcp_plotting.__main__",
    "bagmcp_plotting.worker",
)
# The worker reads its settings on import; nothing is connected to. (The analysis service is built like the
# bag-store's: one subprocess each, 1.5 s of CPU, is spent only where the answer differs.)
TEAM_ENV = {
    "BAGMCP_REDIS_URL": "redis://127.0.0.1:1/0",
    "BAGMCP_S3_ENDPOINT": "127.0.0.1:1",
    "BAGMCP_S3_ACCESS_KEY": "key",
    "BAGMCP_S3_SECRET_KEY": "a-secret-that-is-long-enough",
    "BAGMCP_SERVICE_TOKEN": "a-service-token-that-is-long-enough",
}


def _loaded_after_import(module: str, watched: tuple[str, ...]) -> list[str]:
    code = f"import json, sys, {module}; print(json.dumps([m for m in {list(watched)!r} if m in sys.modules]))"
    done = subprocess.run(
        [sys.executable, "-c", code], env={**os.environ, **TEAM_ENV}, capture_output=True, text=True, check=True
    )
    loaded: list[str] = json.loads(done.stdout.splitlines()[-1])
    return loaded


def test_services_and_the_plotting_worker_start_without_what_they_load_later() -> None:
    found = {
        module: _loaded_after_import(module, ("celery", "matplotlib", "fastapi", "mcp")) for module in ENTRY_POINTS
    }
    assert found == {
        "bagmcp_bag_store.__main__": ["fastapi", "mcp"],
        "bagmcp_plotting.__main__": ["fastapi", "mcp"],
        "bagmcp_plotting.worker": ["celery", "fastapi", "mcp"],  # a worker runs tasks: Celery from the start
    }
