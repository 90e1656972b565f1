"""Benchmark: odometry from the columnar index vs decoding it from a ~2 GB bag.

    .venv/bin/python bench/bench_index.py [--size-gb 2] [--repeat 5] [--dir .bench]

Writes (once, cached in --dir) a ROS 2 MCAP bag of camera images plus 100 Hz odometry and
20 Hz cmd_vel, builds the index as ingest does, then times the same question both ways:
odometry x, y, yaw and linear speed over the whole bag. Prints medians and their ratio.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

from bagmcp_bag_store.embedded import start_embedded
from bagmcp_bag_store.job_kinds import SearchParams
from bagmcp_bag_store.query.search import search_messages
from bagmcp_shared.bags import open_bag
from bagmcp_shared.index import ColumnIndex, build_index, read_series
from bagmcp_shared.jobs import Unreported
from bagmcp_shared.resources import embedded_resources

COLUMNS = [
    "pose.pose.position.x",
    "pose.pose.position.y",
    "pose.pose.orientation.yaw",
    "twist.twist.linear.x",
]
IMAGE_BYTES = 1_000_000
IMAGE_HZ, ODOM_HZ, CMD_HZ = 10, 100, 20
START_NS = 1_700_000_000_000_000_000


def _odometry(store: object, t: float) -> object:
    types = store.types  # type: ignore[attr-defined]
    sec, nanosec = divmod(START_NS + round(t * 1e9), 1_000_000_000)
    header = types["std_msgs/msg/Header"](
        stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id="odom"
    )
    yaw = 0.1 * t
    pose = types["geometry_msgs/msg/Pose"](
        position=types["geometry_msgs/msg/Point"](x=math.cos(yaw), y=math.sin(yaw), z=0.0),
        orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)),
    )
    vector = types["geometry_msgs/msg/Vector3"]
    twist = types["geometry_msgs/msg/Twist"](linear=vector(x=0.5, y=0.0, z=0.0), angular=vector(x=0.0, y=0.0, z=0.1))
    return types["nav_msgs/msg/Odometry"](
        header=header,
        child_frame_id="base_link",
        pose=types["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=np.zeros(36)),
        twist=types["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=np.zeros(36)),
    )


def write_bag(path: Path, size_gb: float) -> None:
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = store.types
    frames = int(size_gb * 1e9 / IMAGE_BYTES)
    duration = frames / IMAGE_HZ
    pixels = np.frombuffer(np.random.default_rng(0).bytes(IMAGE_BYTES), dtype=np.uint8)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        image_conn = writer.add_connection("/camera/image_raw", "sensor_msgs/msg/Image", typestore=store)
        odom_conn = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=store)
        cmd_conn = writer.add_connection("/cmd_vel", "geometry_msgs/msg/Twist", typestore=store)
        vector = types["geometry_msgs/msg/Vector3"]
        for tick in range(int(duration * ODOM_HZ)):
            t = tick / ODOM_HZ
            stamp = START_NS + tick * (1_000_000_000 // ODOM_HZ)
            writer.write(odom_conn, stamp, store.serialize_cdr(_odometry(store, t), "nav_msgs/msg/Odometry"))
            if tick % (ODOM_HZ // CMD_HZ) == 0:
                cmd = types["geometry_msgs/msg/Twist"](
                    linear=vector(x=0.5, y=0.0, z=0.0), angular=vector(x=0.0, y=0.0, z=0.1)
                )
                writer.write(cmd_conn, stamp, store.serialize_cdr(cmd, "geometry_msgs/msg/Twist"))
            if tick % (ODOM_HZ // IMAGE_HZ) == 0:
                sec, nanosec = divmod(stamp, 1_000_000_000)
                header = types["std_msgs/msg/Header"](
                    stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id="camera"
                )
                image = types["sensor_msgs/msg/Image"](
                    header=header,
                    height=500,
                    width=2000,
                    encoding="mono8",
                    is_bigendian=0,
                    step=2000,
                    data=pixels,
                )
                writer.write(image_conn, stamp, store.serialize_cdr(image, "sensor_msgs/msg/Image"))


def median_s(run: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        began = time.perf_counter()
        run()
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def time_search_tool(folder: Path, name: str, repeat: int) -> tuple[float, float]:
    """The whole search_messages path (catalog, open, index or decode, answer) with and without the index."""
    with tempfile.TemporaryDirectory() as data:
        embedded = embedded_resources(folder, Path(data))
        start_embedded(embedded)
        access = embedded.resources.access
        while any(r.status == "ingesting" for r in access.catalog.all()):
            time.sleep(0.2)
        params = SearchParams(
            bag=name, topic="/odom", condition="near_position", value={"x": 1.0, "y": 0.0, "radius": 0.2}
        )

        def run(index: bool) -> object:
            return search_messages(access, params, Unreported(), budget_bytes=16_000, use_index=index)

        with_index = median_s(lambda: run(True), repeat)
        without = median_s(lambda: run(False), repeat)
        embedded.runner.shutdown()
    return with_index, without


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size-gb", type=float, default=2.0)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--dir", type=Path, default=Path(".bench"))
    args = parser.parse_args()
    bag = args.dir / f"odom_images_{args.size_gb:g}gb"
    if not bag.exists():
        args.dir.mkdir(parents=True, exist_ok=True)
        began = time.perf_counter()
        write_bag(bag, args.size_gb)
        print(f"wrote {bag} in {time.perf_counter() - began:.1f} s")
    size = sum(f.stat().st_size for f in bag.iterdir())
    with open_bag(bag) as reader, tempfile.TemporaryDirectory() as tmp:
        began = time.perf_counter()
        build_index(reader, Path(tmp) / "columns")
        index_build_s = time.perf_counter() - began
        index = ColumnIndex.load(Path(tmp) / "columns")
        from_index = read_series(reader, "/odom", COLUMNS, index=index)
        from_bag = read_series(reader, "/odom", COLUMNS, index=None)
        assert from_index.source == "index"
        assert from_bag.source == "bag"
        assert all(np.array_equal(from_index.columns[c], from_bag.columns[c]) for c in COLUMNS)
        index_s = median_s(lambda: read_series(reader, "/odom", COLUMNS, index=index), args.repeat)
        bag_s = median_s(lambda: read_series(reader, "/odom", COLUMNS, index=None), args.repeat)
    tool_index_s, tool_bag_s = time_search_tool(args.dir, bag.name, args.repeat)
    report = {
        "bag_bytes": size,
        "odometry_messages": len(from_index.t_ns),
        "repeat": args.repeat,
        "index_build_s": round(index_build_s, 3),
        "median_index_read_s": round(index_s, 6),
        "median_bag_decode_s": round(bag_s, 3),
        "speedup": round(bag_s / index_s, 1),
        "median_search_tool_index_s": round(tool_index_s, 4),
        "median_search_tool_bag_s": round(tool_bag_s, 3),
        "search_tool_speedup": round(tool_bag_s / tool_index_s, 1),
    }
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
