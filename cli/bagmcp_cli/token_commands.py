"""`bagmcp token create|list|revoke`: the arguments; what they do is in token_actions.py, imported only when a
token command runs (importing the gateway's token store costs about a second, `--help` should not pay it)."""

from __future__ import annotations

import argparse
from pathlib import Path

from bagmcp_cli.urls import base_url

ACTIONS = "bagmcp_cli.token_actions"


def add_token_commands(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    token = commands.add_parser("token", help="create, list and revoke API tokens")
    actions = token.add_subparsers(dest="action", required=True)
    where = argparse.ArgumentParser(add_help=False)
    where.add_argument("--url", type=base_url, help="a running gateway (with --token, an admin token)")
    where.add_argument("--token", help="admin token for --url")
    where.add_argument("--data", type=Path, help="an embedded server's data directory")
    where.add_argument("--bags", help="the folder an embedded server serves (its default data directory)")
    where.add_argument("--json", action="store_true")
    made = actions.add_parser("create", parents=[where], help="create a token (printed once)")
    made.add_argument("name")
    made.add_argument("--scopes", default="read", help="comma list of read, upload, delete, admin")
    made.add_argument("--profile", help="tool profile, e.g. core (default: every enabled tool)")
    made.add_argument("--allow", action="append", help="tool-name glob the token may use (repeatable)")
    made.add_argument("--deny", action="append", help="tool-name glob the token may not use (repeatable)")
    made.add_argument("--expires", help="lifetime such as 30d, 12h (default: never)")
    made.set_defaults(handler=f"{ACTIONS}:create")
    actions.add_parser("list", parents=[where], help="list tokens (never their secrets)").set_defaults(
        handler=f"{ACTIONS}:listed"
    )
    gone = actions.add_parser("revoke", parents=[where], help="revoke a token")
    gone.add_argument("name")
    gone.set_defaults(handler=f"{ACTIONS}:revoke")
