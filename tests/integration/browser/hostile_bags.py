"""Bags whose texts are markup, to show the console renders them as text: a ROS 1 bag with log records
whose message and node name are HTML that would run script if a page inserted it as markup, and a topic
whose name is such HTML."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_typestore

from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import make

SCRIPT_TEXT = "<script>alert(1)</script> obstacle"
IMG_NODE = "<img src=x onerror=alert(1)>"
IMG_TOPIC = "/<img src=x onerror=alert(3)>"
LOG_TYPE = "rosgraph_msgs/msg/Log"


def write_hostile_log_bag(directory: Path, *, name: str = "hostile_logs") -> Path:
    store = get_typestore(Stores.ROS1_NOETIC)
    path = directory / f"{name}.bag"
    with Writer(path) as writer:
        connection = writer.add_connection(sc.LOG_TOPIC, LOG_TYPE, typestore=store)
        for i, text in enumerate((SCRIPT_TEXT, "plain line", SCRIPT_TEXT)):
            stamp = sc.stamp_ns(i * 0.5)
            sec, nanosec = divmod(stamp, 1_000_000_000)
            header = {"seq": np.uint32(i), "stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": ""}
            log = make(store, LOG_TYPE, header=header, level=np.uint8(8), name=IMG_NODE, msg=text, file="x.py")
            writer.write(connection, stamp, store.serialize_ros1(log, LOG_TYPE))
        named = writer.add_connection(IMG_TOPIC, "std_msgs/msg/String", typestore=store)
        note = make(store, "std_msgs/msg/String", data="a topic named as markup")
        writer.write(named, sc.stamp_ns(0.25), store.serialize_ros1(note, "std_msgs/msg/String"))
    return path
