"""Turn raw payloads into message objects, using the definitions stored in the bag itself.

Each message type is registered on its own, so one broken or missing definition makes only
that type undecodable (with a reason) instead of failing the whole bag.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable

from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_types_from_idl, get_types_from_msg, get_typestore
from rosbags.typesys.msg import normalize_msgtype
from rosbags.typesys.store import Typestore

from bagmcp_shared.bags.foreign import foreign_codec
from bagmcp_shared.bags.models import Connection, Encoding, RawMessage
from bagmcp_shared.bags.plain_types import ForeignCodec
from bagmcp_shared.errors import DecodeError

_IDL_SEPARATOR = "=" * 80 + "\n"


def _types_from_definition(conn: Connection) -> dict[str, object]:
    """Parse one connection's stored definition into rosbags' type dictionary."""
    if conn.definition_format == "idl":
        text = conn.definition
        if text.startswith(f"{_IDL_SEPARATOR}IDL: "):
            typs: dict[str, object] = {}
            for part in text.split(_IDL_SEPARATOR)[1:]:
                typs.update(get_types_from_idl(part.split("\n", 1)[1]))
            return typs
        return dict(get_types_from_idl(text))
    return dict(get_types_from_msg(conn.definition, conn.msgtype))


def _referenced(store: Typestore, root: str) -> list[str]:
    """Every message type ``root`` uses, directly or through fields, that the store can see so far."""
    seen: list[str] = []
    pending = [root]
    while pending:
        name = pending.pop()
        if name in seen:
            continue
        seen.append(name)
        if name not in store.fielddefs:
            continue
        for _field, (kind, detail) in store.fielddefs[name][1]:
            inner = detail[0] if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE) else (kind, detail)
            if inner[0] == Nodetype.NAME:
                pending.append(str(inner[1]))
    return seen[1:]


@functools.cache
def standard_store(encoding: Encoding) -> Typestore:
    """The standard ROS types of a family (Noetic for ROS 1, the latest distribution for ROS 2)."""
    return get_typestore(Stores.ROS1_NOETIC if encoding is Encoding.ROS1 else Stores.LATEST)


def _deserialize(store: Typestore, raw: RawMessage) -> object:
    if raw.connection.encoding is Encoding.ROS1:
        return store.deserialize_ros1(raw.data, raw.connection.msgtype)
    return store.deserialize_cdr(raw.data, raw.connection.msgtype)


@functools.lru_cache(maxsize=512)
def definition_store(
    msgtype: str, encoding: Encoding, definition_format: str, definition: str, digest: str
) -> Typestore | str:
    """The typestore of one stored definition, or why there is none. Kept per process (at most 512
    definitions): building a typestore and compiling its (de)serializers costs tens of milliseconds, paid
    once per definition instead of once per opened reader. A store is not changed once built."""
    conn = Connection(0, "", msgtype, encoding, definition, definition_format, 0, digest)
    store = get_typestore(Stores.EMPTY)
    try:
        store.register(_types_from_definition(conn))  # type: ignore[arg-type]
    except Exception as err:  # parser errors are of many kinds
        first_line = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        return f"its stored definition could not be parsed ({first_line})"
    if missing := _complete(store, conn):
        return f"its stored definition uses {missing}, which it does not define"
    if encoding is Encoding.ROS1 and digest:
        have = store.generate_msgdef(msgtype)[1]
        if have != digest:
            return f"its stored definition does not match its md5 ({have} != {digest})"
    return store


def _complete(store: Typestore, conn: Connection) -> str | None:
    """Fill in types a stored definition uses but leaves out (recorders sometimes do) from the standard
    ROS types; returns a type that stays missing, if any."""
    standard = standard_store(conn.encoding)
    while missing := [n for n in _referenced(store, conn.msgtype) if n not in store.fielddefs]:
        name = missing[0]
        if name not in standard.fielddefs:
            return name
        store.register({name: standard.fielddefs[name]})
    return None


class Decoder:
    """Decodes messages of a bag's connections; knows which types it can decode and why not.

    Non-ROS types are set up when first used: a ULog has about a hundred formats and registering them all
    costs about 0.5 s, while a question reads one or two topics.
    """

    def __init__(self, connections: Iterable[Connection]) -> None:
        self._stores: dict[str, Typestore] = {}
        self._foreign: dict[str, ForeignCodec] = {}
        self._pending: dict[str, Connection] = {}
        self._problems: dict[str, str] = {}
        for conn in connections:
            if not conn.encoding.is_ros:
                self._pending.setdefault(conn.msgtype, conn)
            elif conn.msgtype not in self._stores and conn.msgtype not in self._problems:
                self._add(conn)

    def _ready(self, msgtype: str) -> None:
        conn = self._pending.pop(msgtype, None)
        if conn is not None:
            self._add(conn)

    @property
    def problems(self) -> dict[str, str]:
        """Message types that cannot be decoded, with the reason for each."""
        for msgtype in list(self._pending):
            self._ready(msgtype)
        return dict(self._problems)

    def typestore(self, msgtype: str) -> Typestore:
        """The typestore that decodes ``msgtype`` (raises DecodeError when there is none)."""
        self._ready(msgtype)
        store = self._stores.get(msgtype)
        if store is None:
            reason = self._problems.get(msgtype, "the type is not used in this bag")
            raise DecodeError(f"cannot decode messages of type {msgtype}: {reason}")
        return store

    def units(self, msgtype: str) -> dict[str, str]:
        """Units of field paths that the type's own definition states (DataFlash FMTU); empty for ROS types."""
        self._ready(msgtype)
        codec = self._foreign.get(msgtype)
        return dict(codec.units) if codec is not None else {}

    def decode(self, raw: RawMessage) -> object:
        """Deserialize one raw message.

        When a stored definition does not fit the data (some recorders store stubs) and the type is a
        standard ROS type that does fit, the standard definition is used from then on.
        """
        conn = raw.connection
        if not conn.encoding.is_ros:
            return self._decode_foreign(raw)
        try:
            return _deserialize(self.typestore(conn.msgtype), raw)
        except DecodeError:
            raise
        except Exception as err:  # rosbags raises SerdeError, struct.error, IndexError...
            if (message := self._with_standard_type(raw)) is not None:
                return message
            raise DecodeError(
                f"message of {conn.topic} ({conn.msgtype}) at {raw.log_time_ns} ns could not be decoded: {err}"
            ) from err

    def _decode_foreign(self, raw: RawMessage) -> object:
        conn = raw.connection
        self._ready(conn.msgtype)
        codec = self._foreign.get(conn.msgtype)
        if codec is None:
            self.typestore(conn.msgtype)  # raises with the reason
            raise DecodeError(f"cannot decode messages of type {conn.msgtype}")
        try:
            return codec.decode(raw.data)
        except Exception as err:  # struct, json, protobuf and value errors of a payload that does not fit
            raise DecodeError(
                f"message of {conn.topic} ({conn.msgtype}) at {raw.log_time_ns} ns could not be decoded: {err}"
            ) from err

    def _with_standard_type(self, raw: RawMessage) -> object | None:
        conn = raw.connection
        standard = standard_store(conn.encoding)
        if self._stores.get(conn.msgtype) is standard or conn.msgtype not in standard.fielddefs:
            return None
        try:
            message = _deserialize(standard, raw)
        except Exception:  # the standard type does not fit either
            return None
        self._stores[conn.msgtype] = standard
        return message

    def _add(self, conn: Connection) -> None:
        if not conn.encoding.is_ros:
            found = foreign_codec(conn)
            if isinstance(found, str):
                self._problems[conn.msgtype] = found
            else:
                self._foreign[conn.msgtype] = found
                self._stores[conn.msgtype] = found.store
        elif conn.definition.strip():
            self._add_from_definition(conn)
        else:
            self._add_from_standard_types(conn)

    def _add_from_definition(self, conn: Connection) -> None:
        found = definition_store(conn.msgtype, conn.encoding, conn.definition_format, conn.definition, conn.digest)
        if isinstance(found, str):
            self._problems[conn.msgtype] = found
        else:
            self._stores[conn.msgtype] = found

    def _add_from_standard_types(self, conn: Connection) -> None:
        store = standard_store(conn.encoding)
        msgtype = normalize_msgtype(conn.msgtype)
        if msgtype not in store.fielddefs:
            self._problems[conn.msgtype] = "the bag stores no definition and it is not a standard ROS type"
            return
        if conn.encoding is Encoding.ROS1 and conn.digest and store.generate_msgdef(msgtype)[1] != conn.digest:
            self._problems[conn.msgtype] = (
                "the bag stores no definition and the standard type's md5 differs from the bag's"
            )
            return
        self._stores[conn.msgtype] = store
