"""Protobuf messages (MCAP ``protobuf`` channels) as plain types.

The definition is the schema's FileDescriptorSet, base64-encoded (MCAP stores it as bytes; connection
definitions are text). Scalars map to their widths, enums to int32, ``bytes`` to a uint8 sequence,
repeated fields to sequences and messages nest; a message type that contains itself (``Struct``) stops
nesting after ``MAX_DEPTH`` levels and is shown as protobuf text. Decoding is protobuf's own parser
plus one object per nested message.
"""

from __future__ import annotations

import base64
from collections.abc import Callable

import numpy as np
from google.protobuf import descriptor_pb2, descriptor_pool, message_factory, text_format  # type: ignore[import-untyped]
from google.protobuf.descriptor import Descriptor, FieldDescriptor  # type: ignore[import-untyped]
from google.protobuf.message import Message  # type: ignore[import-untyped]

from bagmcp_shared.bags.plain_types import Builder, ForeignCodec, PlainField, field_name, plain_store, type_name

MAX_DEPTH = 8
_SCALARS = {
    FieldDescriptor.TYPE_DOUBLE: "float64",
    FieldDescriptor.TYPE_FLOAT: "float32",
    FieldDescriptor.TYPE_INT64: "int64",
    FieldDescriptor.TYPE_SINT64: "int64",
    FieldDescriptor.TYPE_SFIXED64: "int64",
    FieldDescriptor.TYPE_UINT64: "uint64",
    FieldDescriptor.TYPE_FIXED64: "uint64",
    FieldDescriptor.TYPE_INT32: "int32",
    FieldDescriptor.TYPE_SINT32: "int32",
    FieldDescriptor.TYPE_SFIXED32: "int32",
    FieldDescriptor.TYPE_UINT32: "uint32",
    FieldDescriptor.TYPE_FIXED32: "uint32",
    FieldDescriptor.TYPE_BOOL: "bool",
    FieldDescriptor.TYPE_STRING: "string",
    FieldDescriptor.TYPE_ENUM: "int32",
}
Convert = Callable[[object], object]


class _Types:
    def __init__(self) -> None:
        self.types: dict[str, tuple[PlainField, ...]] = {}

    def message(self, descriptor: Descriptor, depth: int) -> Convert:
        name = type_name(descriptor.full_name)
        fields: list[PlainField] = []
        converters: list[tuple[str, str, Convert]] = []
        for field in descriptor.fields:
            fname = field_name(field.name, [f.name for f in fields])
            plain, convert = self._field(fname, field, depth)
            fields.append(plain)
            converters.append((field.name, fname, convert))
        self.types.setdefault(name, tuple(fields))

        def to_values(value: object) -> object:
            assert isinstance(value, Message)
            return {fname: conv(getattr(value, key)) for key, fname, conv in converters}

        return to_values

    def _field(self, fname: str, field: FieldDescriptor, depth: int) -> tuple[PlainField, Convert]:
        repeated = _repeated(field)
        size = 0 if repeated else None
        if field.type == FieldDescriptor.TYPE_MESSAGE and field.message_type is not None:
            if depth >= MAX_DEPTH:
                return PlainField(fname, "string", size), _each(_as_text) if repeated else _as_text
            inner = self.message(field.message_type, depth + 1)
            return PlainField(fname, type_name(field.message_type.full_name), size), _each(inner) if repeated else inner
        if field.type == FieldDescriptor.TYPE_BYTES:
            if repeated:
                return PlainField(fname, "string", 0), _each(_bytes_note)
            return PlainField(fname, "uint8", 0), _as_bytes
        kind = _SCALARS[field.type]
        if repeated:
            return PlainField(fname, kind, 0), _each(_same) if kind == "string" else _numbers(kind)
        return PlainField(fname, kind), _same


def _repeated(field: FieldDescriptor) -> bool:
    """protobuf 6.31 added ``is_repeated`` and 7 dropped ``label``."""
    if hasattr(field, "is_repeated"):
        return bool(field.is_repeated)
    return bool(field.label == FieldDescriptor.LABEL_REPEATED)


def _same(value: object) -> object:
    return value


def _as_text(value: object) -> object:
    return text_format.MessageToString(value, as_one_line=True)


def _as_bytes(value: object) -> object:
    return np.frombuffer(bytes(value), dtype=np.uint8)  # type: ignore[call-overload]


def _bytes_note(value: object) -> object:
    return f"<{len(bytes(value))} bytes>"  # type: ignore[call-overload]


def _each(convert: Convert) -> Convert:
    def each(values: object) -> object:
        return [convert(v) for v in values]  # type: ignore[attr-defined]

    return each


def _numbers(kind: str) -> Convert:
    dtype = np.dtype(np.bool_ if kind == "bool" else kind)
    return lambda values: np.asarray(list(values), dtype=dtype)  # type: ignore[call-overload]


def protobuf_codec(msgtype: str, definition: str) -> ForeignCodec:
    files = descriptor_pb2.FileDescriptorSet.FromString(base64.b64decode(definition))
    pool = descriptor_pool.DescriptorPool()
    for proto in files.file:
        pool.Add(proto)
    descriptor = _find(pool, files, msgtype)
    cls = message_factory.GetMessageClass(descriptor)
    collected = _Types()
    convert = collected.message(descriptor, 0)
    types = tuple(sorted(collected.types.items()))
    store = plain_store(types)
    builder = Builder(store, types)
    root = type_name(descriptor.full_name)

    def decode(data: bytes) -> object:
        values = convert(cls.FromString(data))
        assert isinstance(values, dict)
        return builder.build(root, values)

    return ForeignCodec(store, decode)


def _find(pool: descriptor_pool.DescriptorPool, files: descriptor_pb2.FileDescriptorSet, msgtype: str) -> Descriptor:
    """The message type whose plain name is ``msgtype`` among every message the files declare."""
    for proto in files.file:
        package = f"{proto.package}." if proto.package else ""
        for message in proto.message_type:
            if type_name(package + message.name) == msgtype:
                return pool.FindMessageTypeByName(package + message.name)
    raise ValueError(f"the descriptor set does not declare {msgtype}")
