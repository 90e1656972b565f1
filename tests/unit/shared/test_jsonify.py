"""Messages become bounded JSON: long arrays, blobs and strings are cut, and fit() meets a byte budget."""

from __future__ import annotations

import json
import math

import numpy as np
from rosbags.typesys import Stores, get_typestore

from bagmcp_shared.jsonify import fit, to_json
from tests.fixtures.bagfactory import make

STORE = get_typestore(Stores.ROS2_HUMBLE)


def test_long_arrays_and_blobs_are_summarized_with_their_length() -> None:
    scan = make(STORE, "sensor_msgs/msg/LaserScan", ranges=np.arange(100, dtype=np.float32))
    shown = to_json(scan, max_items=4)
    assert shown["ranges"] == {"_length": 100, "_first": [0.0, 1.0, 2.0, 3.0], "_truncated": True}  # type: ignore[index, call-overload]
    image = make(STORE, "sensor_msgs/msg/Image", data=np.zeros(5000, dtype=np.uint8))
    assert to_json(image)["data"] == {"_bytes": 5000, "_first": [0] * 16}  # type: ignore[index, call-overload]


def test_long_strings_are_cut_with_a_note_and_non_finite_numbers_become_text() -> None:
    shown = to_json({"text": "x" * 50, "nan": math.nan}, max_text=10)
    assert shown == {"text": "xxxxxxxxxx... (50 characters in all)", "nan": "nan"}


def test_fit_keeps_small_messages_whole_and_shrinks_large_ones_under_the_budget() -> None:
    small = make(STORE, "geometry_msgs/msg/Twist")
    assert fit(small, 16_000) == to_json(small)
    big = make(
        STORE, "sensor_msgs/msg/LaserScan", ranges=np.arange(5000, dtype=np.float32), header={"frame_id": "f" * 20_000}
    )
    shown = fit(big, 2_000)
    assert len(json.dumps(shown)) <= 2_000
    assert shown["ranges"]["_length"] == 5000  # type: ignore[index, call-overload]
    assert fit({"huge": "y" * 10_000}, 20) == {
        "_omitted": "too large to show within 20 bytes; project fields with `fields`"
    }
