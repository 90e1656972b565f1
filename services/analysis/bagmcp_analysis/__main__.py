"""``python -m bagmcp_analysis``: the analysis service in team mode (settings from BAGMCP_*)."""

from __future__ import annotations

from bagmcp_analysis.app import create_app
from bagmcp_analysis.settings import analysis_settings
from bagmcp_kit.service_app import serve


def main() -> None:
    settings = analysis_settings()
    serve(create_app(settings), settings.http)


if __name__ == "__main__":
    main()
