"""The container and compression of a filtered bag, and the rosbags writer that produces them.

Written in the source's own format, a filtered bag keeps the source's compression (ROS 1 bz2/lz4
chunks, MCAP zstd/lz4 chunks, rosbag2's per-file or per-message zstd), so a copy with fewer
messages is not larger than its source. Converted to another format, a compressed source gets
that format's usual compression and an uncompressed one stays uncompressed.
"""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from types import MappingProxyType
from typing import cast

from lz4.frame import compress as lz4_frame  # type: ignore[import-untyped]
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
from rosbags.rosbag2.storage_mcap import McapWriter

from bagmcp_shared.bags.models import BagFormat, Compression
from bagmcp_shared.bags.writer_json_mcap import JsonMcapWriter

AnyWriter = Ros1Writer | Ros2Writer | JsonMcapWriter


class OutputFormat(StrEnum):
    """The container a filtered copy is written as."""

    ROS1 = "ros1"
    ROS2_SQLITE3 = "ros2-sqlite3"
    ROS2_MCAP = "ros2-mcap"
    MCAP_JSON = "mcap-json"  # a bare MCAP of JSON messages: what flight logs and non-ROS MCAP are copied to


# The format a source is copied to when nothing else is asked for (a bare MCAP file is ROS 2's).
_HOME = {
    BagFormat.ROS1: OutputFormat.ROS1,
    BagFormat.ROS2_SQLITE3: OutputFormat.ROS2_SQLITE3,
    BagFormat.ROS2_MCAP: OutputFormat.ROS2_MCAP,
    BagFormat.MCAP: OutputFormat.ROS2_MCAP,
    BagFormat.ULOG: OutputFormat.MCAP_JSON,
    BagFormat.DATAFLASH: OutputFormat.MCAP_JSON,
}
# What each output format can store, and what it uses for a compressed source of another format:
# ROS 1 has bz2 and lz4 (bz2 is the one that stays small), MCAP's usual choice is zstd chunks,
# and sqlite3 rows are best compressed as a whole file.
_KEEPS: dict[OutputFormat, frozenset[Compression]] = {
    OutputFormat.ROS1: frozenset({Compression.NONE, Compression.BZ2, Compression.LZ4}),
    OutputFormat.ROS2_MCAP: frozenset(
        {Compression.NONE, Compression.LZ4, Compression.ZSTD, Compression.ZSTD_FILE, Compression.ZSTD_MESSAGE}
    ),
    OutputFormat.ROS2_SQLITE3: frozenset({Compression.NONE, Compression.ZSTD_FILE, Compression.ZSTD_MESSAGE}),
    OutputFormat.MCAP_JSON: frozenset({Compression.ZSTD}),
}
_USUAL = {
    OutputFormat.ROS1: Compression.BZ2,
    OutputFormat.ROS2_MCAP: Compression.ZSTD,
    OutputFormat.ROS2_SQLITE3: Compression.ZSTD_FILE,
    OutputFormat.MCAP_JSON: Compression.ZSTD,
}
_ROS2_MODES = {
    Compression.ZSTD: CompressionMode.STORAGE,
    Compression.ZSTD_FILE: CompressionMode.FILE,
    Compression.ZSTD_MESSAGE: CompressionMode.MESSAGE,
}


def output_compression(source_format: BagFormat, source: Compression, fmt: OutputFormat) -> tuple[Compression, str]:
    """The compression a filtered copy in ``fmt`` uses, and a few words saying why."""
    if fmt is OutputFormat.MCAP_JSON:
        return Compression.ZSTD, "zstd chunks of JSON messages"
    same_format = _HOME[source_format] is fmt and source in _KEEPS[fmt]
    if same_format or source is Compression.NONE:
        return source, f"{source.label}, as in the source"
    chosen = _USUAL[fmt]
    return chosen, f"{chosen.label}, the {fmt.value} counterpart of the source's {source.label}"


class _Lz4McapStorage(McapWriter):
    """rosbags' MCAP storage with LZ4-frame chunks (rosbags itself writes zstd or plain chunks)."""

    def __init__(self, path: Path, compression: CompressionMode) -> None:
        super().__init__(path, CompressionMode.NONE)
        self.compression = "lz4"
        self.compressor = _lz4


def _lz4(data: bytes) -> bytes:
    return cast(bytes, lz4_frame(data))


class _Lz4McapWriter(Ros2Writer):
    """A rosbag2 writer whose MCAP storage compresses chunks with LZ4."""

    STORAGE_PLUGINS = MappingProxyType({**Ros2Writer.STORAGE_PLUGINS, StoragePlugin.MCAP: _Lz4McapStorage})


def new_writer(target: Path, fmt: OutputFormat, compression: Compression) -> AnyWriter:
    """An unopened writer for ``target`` in ``fmt`` with ``compression`` (one ``fmt`` can store)."""
    if compression not in _KEEPS[fmt]:
        raise ValueError(f"{fmt.value} cannot store {compression.label}")
    if fmt is OutputFormat.MCAP_JSON:
        return JsonMcapWriter(target)
    if fmt is OutputFormat.ROS1:
        ros1 = Ros1Writer(target)
        if compression is not Compression.NONE:
            ros1.set_compression(Ros1Writer.CompressionFormat[compression.name])
        return ros1
    if fmt is OutputFormat.ROS2_SQLITE3:
        ros2 = Ros2Writer(target, version=9, storage_plugin=StoragePlugin.SQLITE3)
    elif compression is Compression.LZ4:
        return _Lz4McapWriter(target, version=9, storage_plugin=StoragePlugin.MCAP)
    else:
        ros2 = Ros2Writer(target, version=9, storage_plugin=StoragePlugin.MCAP)
    if compression in _ROS2_MODES:
        ros2.set_compression(_ROS2_MODES[compression], CompressionFormat.ZSTD)
    return ros2
