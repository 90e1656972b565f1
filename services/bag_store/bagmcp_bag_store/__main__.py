"""``python -m bagmcp_bag_store``: the bag-store service in team mode (settings from BAGMCP_*)."""

from __future__ import annotations

from bagmcp_bag_store.app import create_app
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_kit.service_app import serve


def main() -> None:
    settings = BagStoreSettings.from_env()
    serve(create_app(settings), settings.service.http)


if __name__ == "__main__":
    main()
