"""Decoding messages that are not ROS messages: one codec per encoding, chosen from the connection.

A codec turns a connection's stored definition (a ULog format, a DataFlash FMT record, a JSON schema, a
protobuf descriptor set, a data_tamer schema) into a typestore of plain types, a decode function and the
units the definition states. Codecs are kept per definition (at most 512), like ROS definitions.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

from bagmcp_shared.bags.data_tamer_types import data_tamer_codec
from bagmcp_shared.bags.dataflash_types import dataflash_codec
from bagmcp_shared.bags.json_types import json_codec
from bagmcp_shared.bags.models import Connection, Encoding
from bagmcp_shared.bags.plain_types import ForeignCodec
from bagmcp_shared.bags.protobuf_types import protobuf_codec
from bagmcp_shared.bags.ulog_types import ulog_codec

_MAKERS: dict[Encoding, Callable[[str, str], ForeignCodec]] = {
    Encoding.ULOG: ulog_codec,
    Encoding.DATAFLASH: dataflash_codec,
    Encoding.JSON: json_codec,
    Encoding.PROTOBUF: protobuf_codec,
    Encoding.DATA_TAMER: data_tamer_codec,
}


@functools.lru_cache(maxsize=512)
def _codec(encoding: Encoding, msgtype: str, definition: str) -> ForeignCodec | str:
    try:
        return _MAKERS[encoding](msgtype, definition)
    except Exception as err:  # parsers of several libraries, each with its own errors
        first_line = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        return f"its stored {encoding.value} definition could not be read ({first_line})"


def foreign_codec(conn: Connection) -> ForeignCodec | str:
    """The codec of a non-ROS connection, or why there is none."""
    return _codec(conn.encoding, conn.msgtype, conn.definition)
