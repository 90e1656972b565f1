"""Closed sets of argument values are enums in the schema, and they match what the code accepts."""

from __future__ import annotations

from typing import get_args

from bagmcp_bag_store.filtering import Format
from bagmcp_shared.bags.writer_storage import OutputFormat


def test_filter_bag_offers_exactly_the_formats_a_filtered_bag_can_be_written_as() -> None:
    assert set(get_args(Format)) == {f.value for f in OutputFormat}
