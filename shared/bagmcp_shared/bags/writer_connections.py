"""Output connections of a filtered bag: definitions, ROS 1 latching, ROS 2 QoS and payload
conversion between the ROS 1 and ROS 2 families."""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

from rosbags.interfaces import (
    Nodetype,
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)
from rosbags.interfaces.typing import FieldDesc, Typesdict
from rosbags.rosbag2 import ReaderError as Ros2ReaderError
from rosbags.rosbag2.metadata import parse_qos
from rosbags.serde import SerdeError
from rosbags.typesys import Stores, TypesysError, get_typestore
from rosbags.typesys.store import Typestore

from bagmcp_shared.bags.models import Connection, Encoding
from bagmcp_shared.bags.reader import BagReader
from bagmcp_shared.bags.user_yaml import refuse_aliases
from bagmcp_shared.errors import BagmcpError, DecodeError

_HEADER = "std_msgs/msg/Header"
_IDL_SEPARATOR = "=" * 80 + "\n"
# For a type whose hash cannot be computed: what rosidl_stringify_type_hash prints for the
# zero-initialized (unset) hash. rosbag2 itself writes "" then, which rosbags' writer refuses.
_UNSET_RIHS01 = "RIHS01_" + "0" * 64
_FOREVER = QosTime(2147483647, 4294967295)
# What ``rosbags convert`` offers for a latched ROS 1 topic: reliable, transient local.
_LATCHED_QOS = (
    Qos(
        QosHistory.UNKNOWN,
        0,
        QosReliability.RELIABLE,
        QosDurability.TRANSIENT_LOCAL,
        _FOREVER,
        _FOREVER,
        QosLiveliness.AUTOMATIC,
        _FOREVER,
        avoid_ros_namespace_conventions=False,
    ),
)


class FilterError(BagmcpError):
    """A filter request is invalid, or the filtered bag could not be written."""


Convert = Callable[[bytes], bytes | memoryview]


@dataclass(frozen=True)
class OutConn:
    """Everything an output connection is made of; equal values share one output connection."""

    topic: str
    msgtype: str
    msgdef: str
    digest: str  # md5 for ROS 1, RIHS01 for ROS 2
    callerid: str | None = None
    latching: int | None = None
    qos: tuple[Qos, ...] = ()
    metadata: tuple[tuple[str, str], ...] = ()  # MCAP channel metadata (JSON MCAP output)


def _typestore(reader: BagReader, conn: Connection, why: str) -> Typestore:
    """The source typestore of ``conn``; FilterError naming the topic when there is none."""
    try:
        return reader.decoder.typestore(conn.msgtype)
    except DecodeError as err:
        raise FilterError(f"{conn.topic} ({conn.msgtype}) cannot be {why}: {err}") from err


def _meta(conn: Connection, key: str) -> str:
    return dict(conn.metadata).get(key, "")


def _qos(conn: Connection) -> tuple[Qos, ...]:
    """The offered QoS profiles stored with a ROS 2 connection."""
    text = _meta(conn, "offered_qos_profiles")
    try:
        return tuple(parse_qos(refuse_aliases(text)))
    except (Ros2ReaderError, KeyError, TypeError, ValueError) as err:  # UserYamlError is a ValueError
        raise FilterError(f"{conn.topic}: its offered QoS profiles cannot be parsed ({err})") from err


def _subtype(desc: FieldDesc) -> str:
    """The message type a field refers to ('' for base types)."""
    if desc[0] == Nodetype.NAME:
        return desc[1]
    if desc[0] in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        inner = desc[1][0]
        return inner[1] if inner[0] == Nodetype.NAME else ""
    return ""


def _closure(store: Typestore, conn: Connection) -> Typesdict:
    """The connection's type and every type it uses, as rosbags field definitions."""
    found: Typesdict = {}
    todo = [conn.msgtype]
    while todo:
        name = todo.pop()
        if name in found:
            continue
        if name not in store.fielddefs:
            raise FilterError(f"{conn.topic} ({conn.msgtype}) cannot be converted: it uses {name}, which is undefined")
        found[name] = store.fielddefs[name]
        todo += [sub for _, desc in found[name][1] if (sub := _subtype(desc))]
    return found


def _family_store(store: Typestore, conn: Connection, family: Stores) -> Typestore:
    """The types of ``conn`` with the Header of the target family (ROS 1's has ``seq``)."""
    typs = _closure(store, conn)
    if _HEADER in typs:
        typs[_HEADER] = get_typestore(family).fielddefs[_HEADER]
    target = get_typestore(Stores.EMPTY)
    target.register(typs)
    return target


def _guard(convert: Convert, conn: Connection, target: str) -> Convert:
    """``convert`` with conversion errors turned into FilterError naming the topic."""

    def run(data: bytes) -> bytes | memoryview:
        try:
            return convert(data)
        except (SerdeError, struct.error, ValueError, IndexError) as err:
            raise FilterError(
                f"a message of {conn.topic} ({conn.msgtype}) cannot be converted to {target}: {err}"
            ) from err

    return run


def ros1_output(reader: BagReader, conn: Connection) -> tuple[OutConn, Convert | None]:
    """The ROS 1 connection for ``conn`` and the payload conversion (None within ROS 1)."""
    if conn.encoding is Encoding.ROS1:
        msgdef, digest = conn.definition, conn.digest
        if not digest:  # e.g. a bare MCAP with the ros1 profile stores no md5
            msgdef, digest = _typestore(reader, conn, "written to ROS 1").generate_msgdef(conn.msgtype)
        callerid = _meta(conn, "callerid") or None
        latching = 1 if _meta(conn, "latching") == "1" else None
        return OutConn(conn.topic, conn.msgtype, msgdef, digest, callerid, latching), None
    store = _typestore(reader, conn, "converted to ROS 1")
    msgdef, digest = _family_store(store, conn, Stores.ROS1_NOETIC).generate_msgdef(conn.msgtype)
    latched = any(q.durability is QosDurability.TRANSIENT_LOCAL for q in _qos(conn))
    convert = partial(store.cdr_to_ros1, typename=conn.msgtype)
    out = OutConn(conn.topic, conn.msgtype, msgdef, digest, latching=1 if latched else None)
    return out, _guard(convert, conn, "ROS 1")


def _stored_ros2_definition(conn: Connection) -> str:
    """The stored definition; bare IDL gets the header rosbag2 puts before each IDL file."""
    text = conn.definition if conn.definition.strip() else ""
    if conn.definition_format == "idl" and text and not text.startswith(f"{_IDL_SEPARATOR}IDL: "):
        text = f"{_IDL_SEPARATOR}IDL: {conn.msgtype}\n{text}"
    return text


def _copied_ros2_definition(reader: BagReader, conn: Connection) -> tuple[str, str]:
    """Definition and RIHS01 hash for a ROS 2 -> ROS 2 copy.

    The stored definition is kept as is (the typestore's when there is none). A type that cannot
    be parsed is still copied byte for byte, with its definition text and the unset hash.
    """
    text = _stored_ros2_definition(conn)
    try:
        store = reader.decoder.typestore(conn.msgtype)
        text = text or store.generate_msgdef(conn.msgtype, ros_version=2)[0]
        return text, store.hash_rihs01(conn.msgtype)
    except (DecodeError, TypesysError, KeyError):
        return text, _UNSET_RIHS01


def ros2_output(reader: BagReader, conn: Connection) -> tuple[OutConn, Convert | None]:
    """The ROS 2 connection for ``conn`` and the payload conversion (None within ROS 2)."""
    if conn.encoding is Encoding.CDR:
        msgdef, digest = _copied_ros2_definition(reader, conn)
        return OutConn(conn.topic, conn.msgtype, msgdef, digest, qos=_qos(conn)), None
    target = _family_store(_typestore(reader, conn, "converted to ROS 2"), conn, Stores.ROS2_FOXY)
    msgdef = target.generate_msgdef(conn.msgtype, ros_version=2)[0]
    qos = _LATCHED_QOS if _meta(conn, "latching") == "1" else ()
    convert = partial(target.ros1_to_cdr, typename=conn.msgtype)
    out = OutConn(conn.topic, conn.msgtype, msgdef, target.hash_rihs01(conn.msgtype), qos=qos)
    return out, _guard(convert, conn, "ROS 2")


# Writing ---------------------------------------------------------------------------------------
