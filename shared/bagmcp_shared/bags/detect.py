"""Tell what kind of input a path is from its content, not only its name."""

from __future__ import annotations

from pathlib import Path

from bagmcp_shared.bags.models import BagFormat
from bagmcp_shared.errors import BagError, EmptyFileError, UnsupportedFormatError

_LEGACY = "a ROS bag in the legacy format 1.x (before 2010); convert it to format 2.0 with ROS 1's `rosbag` tools first"
_MAGICS: tuple[tuple[bytes, BagFormat | str], ...] = (
    (b"#ROSBAG V2.0", BagFormat.ROS1),
    (b"\x89MCAP0\r\n", BagFormat.MCAP),
    (b"SQLite format 3\x00", BagFormat.ROS2_SQLITE3),
    (b"#ROSRECORD V1.", _LEGACY),
    (b"ULog\x01\x12\x35", BagFormat.ULOG),
    (b"\xa3\x95\x80", BagFormat.DATAFLASH),  # a DataFlash log opens with FMT records (message id 128)
    (b"\x28\xb5\x2f\xfd", "a zstd-compressed file; decompress it first"),
    (b"PK\x03\x04", "a zip archive; unpack it (or upload it, which unpacks ROS 2 bag directories)"),
)


def format_of_head(head: bytes) -> BagFormat | None:
    """The bag format the first bytes of a file announce, or None (unknown, or not a format read as is)."""
    return next((kind for magic, kind in _MAGICS if head.startswith(magic) and isinstance(kind, BagFormat)), None)


def sniff_file(path: Path) -> BagFormat:
    """The bag format of a single file, from its first bytes."""
    try:
        with path.open("rb") as file:
            head = file.read(16)
    except OSError as err:
        raise BagError(f"{path}: cannot be read ({err.strerror})") from err
    if not head:
        raise EmptyFileError(f"{path}: the file is empty (0 bytes)")
    for magic, kind in _MAGICS:
        if head.startswith(magic):
            if isinstance(kind, BagFormat):
                return kind
            raise UnsupportedFormatError(f"{path}: this is {kind}")
    raise UnsupportedFormatError(
        f"{path}: not a ROS bag or flight log (unknown file signature {head[:8]!r}); bagmcp reads ROS 1 .bag, "
        "ROS 2 .db3/.mcap bag directories, bare .mcap files, PX4 .ulg and ArduPilot DataFlash .bin logs"
    )


def is_dataflash(path: Path) -> bool:
    """A ``.bin`` file that starts like a DataFlash log (other ``.bin`` files in a folder are not bags)."""
    try:
        return sniff_file(path) is BagFormat.DATAFLASH
    except BagError:
        return False
