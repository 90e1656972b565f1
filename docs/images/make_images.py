"""Regenerate the example plots in docs/images (``make docs-images``): one PNG of each kind, made by the
plotting tools over generated bags (the drive of tests/fixtures and a slower second run of it).

Run from the repository root: ``PYTHONPATH=. .venv/bin/python docs/images/make_images.py``.
"""

from __future__ import annotations

import base64
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import anyio
from mcp import Client
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.store import Typestore

from tests.fixtures import drive_lidar as lidar
from tests.fixtures import drive_scenario as drive
from tests.fixtures.bagfactory import make
from tests.fixtures.drive_bags import write_drive_bag
from tests.fixtures.drive_motion_messages import header, quaternion
from tests.fixtures.drive_tf import yaw_quaternion
from tests.fixtures.inprocess import in_process

OUT = Path(__file__).resolve().parent
SLOWER = 1.25  # the second run drives the same course at 0.4 m/s instead of 0.5 m/s
Arguments = dict[str, object]
PLOTS: dict[str, tuple[str, Arguments]] = {
    "timeseries": (
        "plot_timeseries",
        {
            "bag": "drive",
            "paths": ["/cmd_vel.linear.x", "/odom.twist.twist.linear.x", "/imu.angular_velocity.z"],
            "start": 0,
            "end": 30,
        },
    ),
    "trajectory": ("plot_2d", {"bag": "drive", "color_by_time": True}),
    "lidar_scan": ("plot_lidar_scan", {"bag": "drive", "time": lidar.CLOSEST_S, "within": 0.5}),
    "histogram": ("plot_histogram", {"bag": "drive", "path": "/scan.ranges[0]", "bins": 40}),
    "compare_runs": (
        "compare_runs",
        {"bags": ["drive", "drive_slower"], "path": "/odom.twist.twist.linear.x", "align": "motion"},
    ),
}


def _slower_run(store: Typestore) -> Iterator[tuple[str, str, int, bytes]]:
    """/odom and /cmd_vel of the drive played SLOWER times slower."""
    end_s = drive.DURATION_S * SLOWER
    for offset_ns in drive.tick_offsets_ns(drive.ODOM_HZ, end_s=end_s):
        course_s = offset_ns / 1e9 / SLOWER
        x, y, yaw = drive.pose_at(course_s)
        linear, angular = (v / SLOWER for v in drive.twist_at(course_s))
        odom = make(
            store,
            "nav_msgs/msg/Odometry",
            header=header(ros1=False, offset_ns=offset_ns, frame="odom"),
            child_frame_id="base_link",
            pose={"pose": {"position": {"x": x, "y": y}, "orientation": quaternion(yaw_quaternion(yaw))}},
            twist={"twist": {"linear": {"x": linear}, "angular": {"z": angular}}},
        )
        yield "/odom", "nav_msgs/msg/Odometry", offset_ns, bytes(store.serialize_cdr(odom, "nav_msgs/msg/Odometry"))
        if offset_ns % (1_000_000_000 // drive.CMD_HZ) == 0:
            twist = make(store, "geometry_msgs/msg/Twist", linear={"x": linear}, angular={"z": angular})
            yield (
                "/cmd_vel",
                "geometry_msgs/msg/Twist",
                offset_ns,
                bytes(store.serialize_cdr(twist, "geometry_msgs/msg/Twist")),
            )


def write_slower_run(directory: Path) -> Path:
    store = get_typestore(Stores.ROS2_HUMBLE)
    path = directory / "drive_slower"
    with Ros2Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        connections: dict[str, object] = {}
        for topic, msgtype, offset_ns, data in _slower_run(store):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=store)
            writer.write(connections[topic], drive.START_NS + offset_ns, data)  # type: ignore[arg-type]
    return path


async def _render(client: Client, tool: str, arguments: Arguments) -> bytes:
    answer = await client.call_tool(tool, arguments)
    if answer.is_error or answer.structured_content is None or "result" not in answer.structured_content:
        raise RuntimeError(f"{tool} did not answer with a plot: {answer.content}")
    return base64.b64decode(next(c for c in answer.content if c.type == "image").data)


def main() -> int:
    with tempfile.TemporaryDirectory() as work:
        bags, data = Path(work) / "bags", Path(work) / "data"
        bags.mkdir()
        write_drive_bag("ros1", bags)
        write_slower_run(bags)
        with in_process(bags, data) as services:

            async def render_all() -> None:
                async with Client(services.service("plotting"), cache=None) as client:
                    for name, (tool, arguments) in PLOTS.items():
                        png = await _render(client, tool, arguments)
                        (OUT / f"{name}.png").write_bytes(png)
                        print(f"docs/images/{name}.png: {len(png):,} bytes")

            anyio.run(render_all)
    return 0


if __name__ == "__main__":
    sys.exit(main())
