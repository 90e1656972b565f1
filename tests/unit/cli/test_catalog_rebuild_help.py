"""`bagmcp catalog rebuild` says what it cannot bring back: API tokens and jobs live only in Redis (the stack
test runs the command and checks it prints the same sentence)."""

from __future__ import annotations

import pytest

from bagmcp_cli.main import build_parser


def test_catalog_rebuild_help_says_tokens_and_jobs_are_not_rebuilt(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        build_parser().parse_args(["catalog", "rebuild", "--help"])
    assert "API tokens and jobs lived only in Redis and are not rebuilt" in " ".join(capsys.readouterr().out.split())
