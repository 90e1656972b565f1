"""`bagmcp catalog rebuild`: list again, in the team catalog (Redis), every bag stored in S3, with the
settings of the team stack (BAGMCP_* variables; for `make stack`: deploy/stack/run.sh bagmcp catalog rebuild)."""

from __future__ import annotations

import argparse

NOT_RESTORED = (
    "API tokens and jobs lived only in Redis and are not rebuilt: make the tokens again (bagmcp token create) "
    "and run lost jobs' tools again"
)


def rebuild(_args: argparse.Namespace) -> int:
    from bagmcp_bag_store.ingest.rebuild import rebuild_catalog  # the bag-store's code: 10 s to import on a busy
    from bagmcp_bag_store.task_refs import QUEUE  # machine, so only when this command runs
    from bagmcp_bag_store.wiring import ingest_queue
    from bagmcp_kit.runtime.resources import team_resources
    from bagmcp_shared.settings import Env, TeamSettings

    resources = team_resources(TeamSettings.from_env(Env()), queue=QUEUE)
    rebuilt = rebuild_catalog(resources.catalog, resources.store)
    queue = ingest_queue(resources)
    for bag_id in rebuilt.to_ingest:
        queue(bag_id)
    print(rebuilt)
    for note in rebuilt.skipped:
        print(f"  skipped {note}")
    print(NOT_RESTORED)
    return 0


def add_catalog_commands(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    catalog = commands.add_parser("catalog", help="maintain the team catalog")
    actions = catalog.add_subparsers(dest="action", required=True)
    again = actions.add_parser(
        "rebuild",
        help="list again every bag stored in S3 that the catalog lacks (settings from BAGMCP_*)",
        description=f"List again every bag stored in S3 that the catalog lacks. {NOT_RESTORED}.",
    )
    again.set_defaults(handler=rebuild)
