"""``python -m bagmcp_plotting``: the plotting service in team mode (settings from BAGMCP_*)."""

from __future__ import annotations

from bagmcp_kit.service_app import serve
from bagmcp_plotting.app import create_app
from bagmcp_plotting.settings import PlottingSettings


def main() -> None:
    settings = PlottingSettings.from_env()
    serve(create_app(settings), settings.service.http)


if __name__ == "__main__":
    main()
