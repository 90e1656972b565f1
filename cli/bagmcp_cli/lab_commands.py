"""``bagmcp lab run|report``: arguments only; the Lab (and its model SDKs) is imported when a command runs, so
``bagmcp --help`` stays fast."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from bagmcp_cli.urls import mcp_url
from bagmcp_shared.settings import Env


def _run(args: argparse.Namespace) -> int:
    from bagmcp_lab.cli import run_command

    return run_command(
        url=args.url,
        token=args.token if args.token is not None else Env().optional("BAGMCP_TOKEN"),
        provider=args.provider,
        model=args.model,
        base_url=args.base_url,
        api_key_env=args.api_key_env,
        bag=args.bag,
        tasks=args.tasks,
        repeat=args.repeat,
        max_turns=args.max_turns,
        out=args.out,
        images=not args.no_images,
    )


def _report(args: argparse.Namespace) -> int:
    from bagmcp_lab.cli import report_command

    return report_command(directories=args.dirs, out=args.out)


def add_lab_commands(commands: Any) -> None:
    lab = commands.add_parser("lab", help="benchmark models on the paper's tasks over an MCP URL (MCP Lab)")
    actions = lab.add_subparsers(dest="lab_command", required=True)
    run = actions.add_parser("run", help="run a task suite against one model and write results.json and report.md")
    run.add_argument(
        "--url",
        required=True,
        type=mcp_url,
        help="the server (its base URL or its /mcp URL), e.g. http://127.0.0.1:8000",
    )
    run.add_argument("--token", default=None, help="bearer token (default: $BAGMCP_TOKEN); its profile sets the tools")
    run.add_argument("--provider", required=True, choices=["anthropic", "openai"])
    run.add_argument("--model", required=True, help="e.g. claude-sonnet-4-5, gpt-4.1-mini, llama-3.1-8b-instant")
    run.add_argument("--base-url", default=None, help="an OpenAI-compatible server (Groq, Ollama, vLLM, LM Studio)")
    run.add_argument(
        "--api-key-env", default=None, help="the variable holding the key (default ANTHROPIC_API_KEY / OPENAI_API_KEY)"
    )
    run.add_argument("--bag", required=True, help="the bag the tasks are about (name or id)")
    run.add_argument("--tasks", default="paper", help="paper (the ten), all (and ours), or FILE.yaml")
    run.add_argument("--repeat", type=int, default=1, help="runs of each task")
    run.add_argument("--max-turns", type=int, default=10, help="model replies per run before giving up")
    run.add_argument("--no-images", action="store_true", help="send tool images as text only (models without vision)")
    run.add_argument("--out", type=Path, required=True, help="directory for results.json, report.md and figures")
    run.set_defaults(handler=_run)
    report = actions.add_parser("report", help="merge the results of several runs into one report.md")
    report.add_argument("dirs", nargs="+", type=Path, help="--out directories of `bagmcp lab run`")
    report.add_argument("--out", type=Path, default=None, help="where the merged report goes (default: the first)")
    report.set_defaults(handler=_report)
