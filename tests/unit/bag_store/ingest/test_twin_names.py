"""Bags of one name in a served folder: the first keeps it, the others are named by their format, then their
folder, so a person reads "the MCAP copy" (``talker_mcap``), not a range (``talker-2``)."""

from __future__ import annotations

from pathlib import Path

from bagmcp_bag_store.ingest.folder import catalog_folder
from bagmcp_shared.catalog import MemoryCatalog
from tests.fixtures.bagfactory import write_bag, write_chatter_bag


def _served(tmp_path: Path) -> Path:
    root = tmp_path / "served"
    for folder, kind in (("ros2_db3", "ros2-sqlite3"), ("ros2_mcap", "ros2-mcap")):
        (root / folder).mkdir(parents=True)
        made = write_bag(kind, root / folder, name="talker")  # type: ignore[arg-type]
        made.rename(root / folder / "talker")
    for count, folder in enumerate(("copies", "more", "zz"), start=3):
        (root / folder).mkdir()
        write_chatter_bag(root / folder, count=count, name="talker")  # another content each: not one bag
    return root


def test_twins_are_named_by_their_format_then_their_folder(tmp_path: Path) -> None:
    catalog = MemoryCatalog()
    catalog_folder(catalog, _served(tmp_path))
    names = {r.source: r.name for r in catalog.all()}
    assert names == {
        "copies/talker": "talker",
        "more/talker": "talker_db3",
        "ros2_db3/talker": "talker_ros2_db3",  # its format's name was taken: its folder
        "ros2_mcap/talker": "talker_mcap",
        "zz/talker": "talker_zz",
    }
