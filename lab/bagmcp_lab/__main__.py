"""``python -m bagmcp_lab``: the Lab service in team mode (settings from BAGMCP_* variables)."""

from __future__ import annotations

from bagmcp_kit.service_app import serve
from bagmcp_lab.app import create_app
from bagmcp_lab.settings import LabServiceSettings


def main() -> None:
    settings = LabServiceSettings.from_env()
    serve(create_app(settings), settings.http)


if __name__ == "__main__":
    main()
