"""Every command takes the server's URL in either form people paste: its base or its /mcp endpoint."""

from __future__ import annotations

import subprocess
import sys

import pytest

from bagmcp_cli.main import build_parser
from bagmcp_cli.urls import base_url, mcp_url

FORMS = ["http://h:8080", "http://h:8080/", "http://h:8080/mcp", "http://h:8080/mcp/", " http://h:8080/mcp "]


@pytest.mark.parametrize("pasted", FORMS)
def test_either_form_gives_the_base_and_the_endpoint(pasted: str) -> None:
    assert (base_url(pasted), mcp_url(pasted)) == ("http://h:8080", "http://h:8080/mcp")


@pytest.mark.parametrize("pasted", FORMS)
def test_upload_token_and_config_take_either_form(pasted: str) -> None:
    parser = build_parser()
    assert parser.parse_args(["upload", "x.bag", "--url", pasted]).url == "http://h:8080"
    assert parser.parse_args(["token", "list", "--url", pasted]).url == "http://h:8080"
    assert parser.parse_args(["config", "--client", "cursor", "--url", pasted]).url == "http://h:8080/mcp"


def test_help_imports_no_sdk_bag_or_plot_code() -> None:
    """`bagmcp --help` and starting a command cost what argparse costs (0.3 s), not the SDK's 2 s."""
    code = (
        "import sys; from bagmcp_cli.main import build_parser; build_parser(); "
        "print(sorted({m.split('.')[0] for m in sys.modules} & "
        "{'mcp', 'pydantic', 'numpy', 'rosbags', 'mcap', 'matplotlib', 'httpx', 'fastapi', 'redis', 'celery'}))"
    )
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert loaded.stdout.strip() == "[]"
