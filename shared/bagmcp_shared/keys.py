"""Where everything lives in the object store: the one place that knows the key layout.

bags/<id>/<file>                  a bag's files (one file, or a ROS 2 directory's files)
catalog/<id>.json                 the bag's catalog registration (lets the catalog be rebuilt)
indexes/<id>/summary.json         what ingest learned: summary and message definitions
indexes/<id>/columns/<file>       the columnar index
artifacts/<id>.<ext>              plots and exports made for callers
"""

from __future__ import annotations

REGISTRATIONS = "catalog/"


def bag_prefix(bag_id: str) -> str:
    return f"bags/{bag_id}"


def bag_file(bag_id: str, name: str) -> str:
    return f"{bag_prefix(bag_id)}/{name}"


def registration(bag_id: str) -> str:
    return f"{REGISTRATIONS}{bag_id}.json"


def ingest_summary(bag_id: str) -> str:
    return f"indexes/{bag_id}/summary.json"


def index_file(bag_id: str, name: str) -> str:
    return f"indexes/{bag_id}/columns/{name}"


def artifact(artifact_id: str, extension: str) -> str:
    return f"artifacts/{artifact_id}.{extension}"
