"""Typestores built from a bag's stored definitions are kept per process, so a second reader of the bag
(or another bag with the same definitions) decodes without building and compiling them again."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from bagmcp_shared.bags import open_bag
from bagmcp_shared.bags.decoding import Decoder, definition_store
from bagmcp_shared.bags.models import Connection, Encoding
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import write_bag


def test_two_readers_of_a_bag_share_the_typestores_and_decode_alike(tmp_path: Path) -> None:
    path = write_bag("ros2-mcap", tmp_path)
    with open_bag(path) as first, open_bag(path) as second:
        odom = first.topic_connections("/odom")[0]
        assert first.decoder.typestore(odom.msgtype) is second.decoder.typestore(odom.msgtype)
        third = sc.ticks(sc.ODOM_HZ)[2]  # the first poses are at the origin: a later one tells more
        for reader in (first, second):
            decoded = reader.decode(list(itertools.islice(reader.messages(["/odom"]), 3))[2])
            position = decoded.pose.pose.position  # type: ignore[attr-defined]
            assert (position.x, position.y) == pytest.approx(sc.pose_at(third)[:2])


def test_a_definition_that_cannot_be_used_is_a_reason_for_every_reader() -> None:
    found = definition_store("pkg/msg/Broken", Encoding.CDR, "msg", "this is not a definition (", "")
    assert found == "its stored definition uses pkg/msg/this, which it does not define"
    broken = Connection(1, "/broken", "pkg/msg/Broken", Encoding.CDR, "this is not a definition (", "msg", 1)
    assert Decoder([broken]).problems == {"pkg/msg/Broken": found}
