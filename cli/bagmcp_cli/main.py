"""The ``bagmcp`` command: info, serve (embedded HTTP), stdio, gateway (team mode), upload."""

from __future__ import annotations

import argparse
import importlib
import ipaddress
import json
import logging
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from bagmcp_cli.catalog_commands import add_catalog_commands
from bagmcp_cli.lab_commands import add_lab_commands
from bagmcp_cli.surface_commands import add_surface_commands
from bagmcp_cli.token_commands import add_token_commands
from bagmcp_cli.urls import base_url
from bagmcp_shared.errors import BagmcpError

Handler = Callable[[argparse.Namespace], int]

DATA_HELP = (
    "where indexes and bags made by filter_bag go "
    "(default: one directory per served folder under $BAGMCP_DATA_DIR or ~/.cache/bagmcp)"
)


def _info(args: argparse.Namespace) -> int:
    from bagmcp_shared.bags import open_bag
    from bagmcp_shared.bags.report import summary_text
    from bagmcp_shared.budget import use_input_budget
    from bagmcp_shared.catalog import CatalogSummary
    from bagmcp_shared.settings import Env, InputBudget

    use_input_budget(InputBudget.from_env(Env()))  # the same checks as a server's (BAGMCP_MAX_RECORD_BYTES, ...)
    with open_bag(args.path, recover_truncated=args.recover) as bag:
        summary = bag.summary()
    print(CatalogSummary.of(summary).model_dump_json(indent=2) if args.json else summary_text(summary))
    return 0


def _is_loopback(host: str) -> bool:
    try:
        return host == "localhost" or ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _serve(args: argparse.Namespace) -> int:
    from bagmcp_cli.embedded import create_embedded_app
    from bagmcp_cli.settings import EmbeddedSettings
    from bagmcp_kit.service_app import bound_socket, serve

    if not _is_loopback(args.host) and not args.token:
        print("bagmcp: error: --token is required when serving on a non-loopback address", file=sys.stderr)
        return 2
    bags = Path(args.bags)
    if not bags.is_dir():
        print(f"bagmcp: error: {bags} is not a directory", file=sys.stderr)
        return 2
    url = f"http://{args.host}:{args.port}"
    sock = bound_socket(args.host, args.port)  # a busy port fails here, before the services are composed
    settings = EmbeddedSettings.from_env(bags, args.data)
    http = settings.http(args.host, args.port, allowed_hosts=args.allowed_host)
    app = create_embedded_app(settings, token=args.token, http=http, public_url=url)
    serving = f"bagmcp: serving {bags} at {url}/mcp (answering to {', '.join(http.allowed_hosts)})"
    serve(app, http, log_level="warning", announce=lambda: print(serving, file=sys.stderr, flush=True), sock=sock)
    return 0


def _stdio(args: argparse.Namespace) -> int:
    import anyio
    from mcp.server.stdio import stdio_server

    from bagmcp_cli.embedded import create_embedded_server
    from bagmcp_cli.settings import EmbeddedSettings

    server = create_embedded_server(EmbeddedSettings.from_env(Path(args.bags), args.data))

    async def run() -> None:
        async with stdio_server() as (read, write):
            await server.run(read, write, server.create_initialization_options())

    anyio.run(run)
    return 0


def _gateway(_args: argparse.Namespace) -> int:
    from bagmcp_gateway.__main__ import main as gateway_main

    gateway_main()
    return 0


def _upload(args: argparse.Namespace) -> int:
    from bagmcp_cli.upload import upload

    answer = upload(Path(args.path), url=args.url, token=args.token, name=args.name)
    bag = answer.get("bag")
    assert isinstance(bag, dict)
    note = " (already in the store)" if answer.get("duplicate") else ""
    print(
        json.dumps({"id": bag.get("id"), "name": bag.get("name"), "duplicate": answer.get("duplicate")})
        if args.json
        else f"{bag.get('id')}  {bag.get('name')}{note}"
    )
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="bagmcp", description="Robot bag analysis for LLM agents.")
    commands = parser.add_subparsers(dest="command", required=True)
    info = commands.add_parser(
        "info", help="summarize a bag (ROS 1 .bag, ROS 2 directory, .db3, .mcap, .ulg, DataFlash .bin)"
    )
    info.add_argument("path", help="bag file or ROS 2 bag directory")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.add_argument("--recover", action="store_true", help="read a truncated MCAP up to the cut")
    info.set_defaults(handler=_info)
    serve = commands.add_parser("serve", help="serve a folder of bags over MCP (streamable HTTP) and REST")
    serve.add_argument("--bags", required=True, help="folder of bags (read-only)")
    serve.add_argument("--host", default="127.0.0.1")
    serve.add_argument("--port", type=int, default=8000)
    serve.add_argument("--token", help="require this bearer token (required off loopback)")
    serve.add_argument(
        "--allowed-host",
        action="append",
        default=[],
        metavar="NAME[:PORT]",
        help="a host name or address clients use to reach this server (repeatable; loopback names are always "
        "allowed; also BAGMCP_ALLOWED_HOSTS)",
    )
    serve.add_argument("--data", type=Path, default=None, help=DATA_HELP)
    serve.set_defaults(handler=_serve)
    stdio = commands.add_parser("stdio", help="serve a folder of bags over MCP stdio (Claude Desktop)")
    stdio.add_argument("--bags", required=True, help="folder of bags (read-only)")
    stdio.add_argument("--data", type=Path, default=None, help=DATA_HELP)
    stdio.set_defaults(handler=_stdio)
    gateway = commands.add_parser("gateway", help="run the team gateway (settings from BAGMCP_* variables)")
    gateway.set_defaults(handler=_gateway)
    up = commands.add_parser("upload", help="upload a bag file or ROS 2 bag directory")
    up.add_argument("path")
    up.add_argument("--url", required=True, type=base_url, help="the server, e.g. http://127.0.0.1:8080 (or its /mcp)")
    up.add_argument("--token", default=None, help="bearer token (default: $BAGMCP_TOKEN)")
    up.add_argument("--name", default=None, help="bag name (default: from the file name)")
    up.add_argument("--json", action="store_true")
    up.set_defaults(handler=_upload)
    add_token_commands(commands)
    add_surface_commands(commands)
    add_catalog_commands(commands)
    add_lab_commands(commands)
    return parser


def _handler(args: argparse.Namespace) -> Handler:
    """The command's function; commands name theirs as ``module:function`` so it is imported only when it runs."""
    found = args.handler
    if isinstance(found, str):
        module, _, name = found.partition(":")
        found = getattr(importlib.import_module(module), name)
    return found  # type: ignore[no-any-return]


def main(argv: Sequence[str] | None = None) -> int:
    """``bagmcp --help`` imports no SDK or bag code: 0.2 s instead of 2.3 s (each command imports what it uses)."""
    args = build_parser().parse_args(argv)
    if getattr(args, "token", "unset") is None and args.command == "upload":
        from bagmcp_shared.settings import Env

        args.token = Env().optional("BAGMCP_TOKEN")
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s", stream=sys.stderr)
    try:
        code: int = _handler(args)(args)
    except BagmcpError as err:
        print(f"bagmcp: error: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except Exception as err:  # a bug, still one line for the user (the traceback is logged at debug level)
        logging.getLogger("bagmcp").debug("unexpected failure", exc_info=True)
        print(f"bagmcp: error: unexpected {type(err).__name__}: {err} (please report this)", file=sys.stderr)
        return 1
    return code


if __name__ == "__main__":
    sys.exit(main())
