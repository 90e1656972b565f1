"""The rosbags decode floor: what the same work costs when a script opens the bag with rosbags and decodes
the messages itself (no server, no index). Each floor opens the bag anew, as a first call must."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from bench.stats import Timing, repeat
from tests.fixtures.drive_scenario import START_NS

ONE_S_NS = 1_000_000_000
FULL_DECODE = "all"


def read_topic(path: Path, topic: str | None, *, start_s: float | None = None, window_s: float | None = None) -> int:
    """Open the bag, decode every message of ``topic`` (of every topic when None; in the window when
    given); the count."""
    start = START_NS + round(start_s * ONE_S_NS) if start_s is not None else None
    stop = start + round((window_s or 0) * ONE_S_NS) + 1 if start is not None else None
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        connections = [c for c in reader.connections if topic is None or c.topic == topic]
        count = 0
        for connection, _, raw in reader.messages(connections=connections, start=start, stop=stop):
            reader.deserialize(raw, connection.msgtype)
            count += 1
    return count


@dataclass(frozen=True)
class Floor:
    """One floor: a name the report shows, and the work."""

    key: str
    label: str
    work: Callable[[Path, float], int]  # (bag path, bag duration s) -> messages decoded


FLOORS = (
    Floor("open_1s", "open + decode 1 s of /odom", lambda p, d: read_topic(p, "/odom", start_s=d / 2, window_s=1.0)),
    Floor("odom", "open + decode all /odom", lambda p, d: read_topic(p, "/odom")),
    Floor("scan", "open + decode all /scan", lambda p, d: read_topic(p, "/scan")),
    Floor("image", "open + decode 1 image", lambda p, d: read_topic(p, "/camera/image_raw", start_s=d / 2, window_s=0)),
    Floor("tf", "open + decode all /tf", lambda p, d: read_topic(p, "/tf")),
    Floor("logs", "open + decode all /rosout", lambda p, d: read_topic(p, "/rosout")),
    # what an upload to ready is held against (issue 21: under 3x this)
    Floor(FULL_DECODE, "open + decode every message", lambda p, d: read_topic(p, None)),
)


def measure_floors(path: Path, duration_s: float, *, repeats: int) -> dict[str, Timing]:
    """Every floor of one bag, each the median of ``repeats`` runs (after one untimed run that warms the
    page cache, as the server's bags are warm too)."""
    found = {}
    for floor in FLOORS:
        if floor.work(path, duration_s) == 0:
            raise RuntimeError(f"the floor {floor.label} decoded nothing in {path}")
        found[floor.key] = repeat(lambda f=floor: f.work(path, duration_s), repeats)  # type: ignore[misc]
    return found
