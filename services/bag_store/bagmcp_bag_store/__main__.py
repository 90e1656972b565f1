"""``python -m bagmcp_bag_store``: the bag-store service in team mode (settings from BAGMCP_*)."""

from __future__ import annotations

import os

import uvicorn

from bagmcp_bag_store.app import create_app
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_bag_store.wiring import team_deps


def main() -> None:
    settings = BagStoreSettings.from_env()
    settings.upload_dir.mkdir(parents=True, exist_ok=True)
    app = create_app(
        team_deps(settings),
        upload_dir=settings.upload_dir,
        max_upload_bytes=settings.max_upload_bytes,
        service_token=settings.service_token,
        allowed_hosts=settings.allowed_hosts,
    )
    uvicorn.run(
        app,
        host=os.environ.get("BAGMCP_HOST", "127.0.0.1"),
        port=int(os.environ.get("BAGMCP_PORT", "8001")),
        log_level="info",
    )


if __name__ == "__main__":
    main()
