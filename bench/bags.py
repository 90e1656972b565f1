"""Writing the benchmark bags once (cached under the bench directory), in the three formats."""

from __future__ import annotations

import heapq
import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys.store import Typestore

from bench import drive
from tests.fixtures.bagfactory import BAG_KINDS, BagKind
from tests.fixtures.drive_bags import STATIC_TF_QOS, drive_typestore
from tests.fixtures.drive_motion_messages import Message
from tests.fixtures.drive_scenario import START_NS

IMAGE_BYTES = drive.IMAGE_SIDE**2
NAMES: dict[BagKind, str] = {"ros1": "drive.bag", "ros2-sqlite3": "drive_db3", "ros2-mcap": "drive_mcap"}


@dataclass(frozen=True)
class BenchBag:
    kind: BagKind
    path: Path
    size_bytes: int
    duration_s: float

    @property
    def name(self) -> str:
        """The name the catalog gives it (the file or directory name without a bag suffix)."""
        return self.path.stem if self.path.is_file() else self.path.name


def duration_for(size_gb: float) -> float:
    """Seconds of drive whose images (10 Hz, 1 MB each) add up to ``size_gb``."""
    return round(size_gb * 1e9 / IMAGE_BYTES / drive.IMAGE_HZ, 1)


def messages(store: Typestore, *, ros1: bool, duration_s: float) -> Iterator[Message]:
    """Every message of the drive in log-time order."""
    parts = (
        drive.motion(store, ros1=ros1, duration_s=duration_s),
        drive.sensors(store, ros1=ros1, duration_s=duration_s),
        drive.records(store, ros1=ros1, duration_s=duration_s),
    )
    return heapq.merge(*parts, key=lambda message: message[2])


def _write(kind: BagKind, path: Path, duration_s: float) -> None:
    ros1 = kind == "ros1"
    store = drive_typestore(ros1=ros1)
    serialize = store.serialize_ros1 if ros1 else store.serialize_cdr
    connections: dict[str, object] = {}
    if ros1:
        with Ros1Writer(path) as writer1:
            for topic, msgtype, offset_ns, message in messages(store, ros1=True, duration_s=duration_s):
                if topic not in connections:
                    latching = 1 if topic == "/tf_static" else None
                    connections[topic] = writer1.add_connection(topic, msgtype, typestore=store, latching=latching)
                writer1.write(connections[topic], START_NS + offset_ns, serialize(message, msgtype))  # type: ignore[arg-type]
        return
    plugin = StoragePlugin.SQLITE3 if kind == "ros2-sqlite3" else StoragePlugin.MCAP
    with Ros2Writer(path, version=9, storage_plugin=plugin) as writer2:
        for topic, msgtype, offset_ns, message in messages(store, ros1=False, duration_s=duration_s):
            if topic not in connections:
                qos = [STATIC_TF_QOS] if topic == "/tf_static" else []
                connections[topic] = writer2.add_connection(topic, msgtype, typestore=store, offered_qos_profiles=qos)
            writer2.write(connections[topic], START_NS + offset_ns, serialize(message, msgtype))  # type: ignore[arg-type]


def _size(path: Path) -> int:
    return sum(f.stat().st_size for f in path.iterdir()) if path.is_dir() else path.stat().st_size


def bench_bags(directory: Path, *, size_gb: float, kinds: tuple[BagKind, ...] = BAG_KINDS) -> list[BenchBag]:
    """The drive of about ``size_gb`` in each kind under ``directory/<size>gb/``, written only when missing
    (a bag is written under a temporary name and renamed when complete)."""
    folder = directory / f"bags-{size_gb:g}gb"
    folder.mkdir(parents=True, exist_ok=True)
    duration_s = duration_for(size_gb)
    found = []
    for kind in kinds:
        path = folder / NAMES[kind]
        if not path.exists():
            partial = folder.parent / f".partial-{size_gb:g}gb" / NAMES[kind]  # ROS 2 names its files after it
            shutil.rmtree(partial.parent, ignore_errors=True)
            partial.parent.mkdir(parents=True)
            _write(kind, partial, duration_s)
            partial.rename(path)
        found.append(BenchBag(kind, path, _size(path), duration_s))
    return found
