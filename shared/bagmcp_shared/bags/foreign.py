"""Decoding messages that are not ROS messages: one codec per encoding, chosen from the connection.

A codec turns a connection's stored definition (a ULog format, a DataFlash FMT record, a JSON schema, a
protobuf descriptor set, a data_tamer schema) into a typestore of plain types, a decode function and the
units the definition states. Codecs are kept per definition (at most 512), like ROS definitions.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Callable
from typing import cast

from bagmcp_shared.bags.models import Connection, Encoding
from bagmcp_shared.bags.plain_types import ForeignCodec

# Imported when first needed: pymavlink and protobuf take about 0.3 s to import, which every `bagmcp`
# command and every service start would otherwise pay for formats it may never see.
_MAKERS = {
    Encoding.ULOG: ("ulog_types", "ulog_codec"),
    Encoding.DATAFLASH: ("dataflash_types", "dataflash_codec"),
    Encoding.JSON: ("json_types", "json_codec"),
    Encoding.PROTOBUF: ("protobuf_types", "protobuf_codec"),
    Encoding.DATA_TAMER: ("data_tamer_types", "data_tamer_codec"),
}


def _maker(encoding: Encoding) -> Callable[[str, str], ForeignCodec]:
    module, name = _MAKERS[encoding]
    return cast(
        Callable[[str, str], ForeignCodec], getattr(importlib.import_module(f"bagmcp_shared.bags.{module}"), name)
    )


@functools.lru_cache(maxsize=512)
def _codec(encoding: Encoding, msgtype: str, definition: str) -> ForeignCodec | str:
    try:
        return _maker(encoding)(msgtype, definition)
    except Exception as err:  # parsers of several libraries, each with its own errors
        first_line = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        return f"its stored {encoding.value} definition could not be read ({first_line})"


def foreign_codec(conn: Connection) -> ForeignCodec | str:
    """The codec of a non-ROS connection, or why there is none."""
    return _codec(conn.encoding, conn.msgtype, conn.definition)
