"""The ``bagmcp`` command."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from bagmcp_shared.bags import open_bag
from bagmcp_shared.bags.report import summary_dict, summary_text
from bagmcp_shared.errors import BagmcpError


def _info(args: argparse.Namespace) -> int:
    with open_bag(args.path, recover_truncated=args.recover) as bag:
        summary = bag.summary()
    print(json.dumps(summary_dict(summary), indent=2) if args.json else summary_text(summary))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="bagmcp", description="Robot bag analysis for LLM agents.")
    commands = parser.add_subparsers(dest="command", required=True)
    info = commands.add_parser("info", help="summarize a bag (ROS 1 .bag, ROS 2 directory, .db3, .mcap)")
    info.add_argument("path", help="bag file or ROS 2 bag directory")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.add_argument(
        "--recover", action="store_true", help="read a truncated MCAP up to the cut instead of refusing it"
    )
    info.set_defaults(handler=_info)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        code: int = args.handler(args)
    except BagmcpError as err:
        print(f"bagmcp: error: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return code


if __name__ == "__main__":
    sys.exit(main())
