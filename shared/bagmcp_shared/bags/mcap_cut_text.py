"""The sentences that say where an MCAP file is cut short or damaged, and what was or can be recovered.

Each names the record (its kind and what its first bytes tell: compression, topic, name), the
byte it starts at, how long it claims to be and the size of the file, e.g. "the zstd chunk that
starts at byte 58 claims to be 362,459 bytes long (to byte 362,517) and runs past the end of the
303,237-byte file; it holds all the messages, ...".
"""

from __future__ import annotations

from mcap.opcode import Opcode
from mcap.records import Channel

from bagmcp_shared.bags.mcap_records import HEAD_BYTES, Cursor, Piece, RecordError
from bagmcp_shared.bags.mcap_scan import Cut, cut_chunk_head
from bagmcp_shared.timebase import iso_from_ns

_NAME_AT = {Opcode.METADATA: 0, Opcode.SCHEMA: 2, Opcode.CHANNEL: 4, Opcode.ATTACHMENT: 16}
_RECOVER = "can be recovered on request (bagmcp info --recover)"


def _count(number: int, noun: str) -> str:
    return f"{number:,} {noun}" if number == 1 else f"{number:,} {noun}s"


def _topics(cut: Cut, shown: int = 5) -> str:
    more = len(cut.topics) - shown
    return ", ".join(cut.topics[:shown]) + (f" and {_count(more, 'more topic')}" if more > 0 else "")


def _named(piece: Piece, channels: dict[int, Channel]) -> str:
    """The record's kind with what its first bytes name (compression, topic, name), when they are there."""
    fields = Cursor(piece.body)
    try:
        if piece.opcode == Opcode.CHUNK:
            head = cut_chunk_head(piece)
            return f"{head.compression or 'uncompressed'} chunk" if head else "chunk"
        if piece.opcode == Opcode.MESSAGE and (channel := channels.get(fields.uint(2))) is not None:
            return f"message on {channel.topic}"
        if piece.opcode in _NAME_AT:
            fields.take(_NAME_AT[Opcode(piece.opcode)])
            return f"{piece.kind} {fields.text()!r}"
    except RecordError:
        pass
    return piece.kind


def _where(cut: Cut, channels: dict[int, Channel]) -> str:
    piece = cut.piece
    subject = f"the {_named(piece, channels)} that starts at byte {piece.offset:,}"
    if cut.damage:
        return f"{subject} {cut.damage}"
    if piece.claimed_bytes is None:
        return (
            f"{subject} is cut inside its {HEAD_BYTES}-byte head (opcode and length) "
            f"by the end of the {cut.size_bytes:,}-byte file"
        )
    record_bytes = HEAD_BYTES + piece.claimed_bytes
    return (
        f"{subject} claims to be {record_bytes:,} bytes long (to byte "
        f"{piece.offset + record_bytes:,}) and runs past the end of the {cut.size_bytes:,}-byte file"
    )


def _holds(cut: Cut) -> str:
    piece = cut.piece
    if piece.opcode == Opcode.CHUNK:
        head = cut_chunk_head(piece)
        if head is None:
            return "what it holds is unknown"
        which = "all the messages," if cut.before == 0 and not cut.damage else "the messages"
        return f"it holds {which} logged from {iso_from_ns(head.start_ns)} to {iso_from_ns(head.end_ns)}"
    if piece.opcode == Opcode.MESSAGE:
        if len(piece.body) >= 14:
            return f"it holds one message, logged at {iso_from_ns(Cursor(piece.body[6:14]).uint(8))}"
        return "it holds one message"
    return "it holds no messages"


def _rescue(cut: Cut) -> str:
    inside = f"the first {cut.inside:,} inside it (on {_topics(cut)})" if cut.inside else ""
    before = f"the {_count(cut.before, 'message')} before it" if cut.before else ""
    if not inside and not before:
        return "no message before it is complete, so nothing can be recovered"
    ready = f"{'is' if cut.before + cut.inside == 1 else 'are'} complete and {_RECOVER}"
    if not before:
        return f"its first {_count(cut.inside, 'message')} (on {_topics(cut)}) {ready}"
    none = "none of its messages can be read; " if cut.damage else "none of its messages is complete; "
    lost = none if cut.piece.opcode == Opcode.CHUNK and not inside else ""
    return f"{lost}{before}{' and ' + inside if inside else ''} {ready}"


def _state(cut: Cut) -> str:
    return "damaged" if cut.damage else "cut short"


def cut_error(cut: Cut, channels: dict[int, Channel]) -> str:
    """Why the file cannot be read as it is: which record is cut and where, what can be recovered."""
    return f"the MCAP file is {_state(cut)}: {_where(cut, channels)}; {_holds(cut)}; {_rescue(cut)}"


def cut_note(cut: Cut, channels: dict[int, Channel]) -> str:
    """What a recovery read: how many messages, from where, and that the rest is lost."""
    where = _where(cut, channels)
    if cut.after_data:
        return (
            f"the MCAP file's summary section is {_state(cut)} ({where}); all {_count(cut.before, 'message')} "
            "are complete and were read from start to end"
        )
    parts = [f"{_count(cut.before, 'message')} before it"] if cut.before else []
    if cut.inside:
        parts.append(f"{_count(cut.inside, 'complete message')} from inside it (on {_topics(cut)})")
    rest = "the rest of it, and anything after it, " + ("is not read" if cut.damage else "is lost")
    return f"the MCAP file is {_state(cut)}: {where}; recovered {' and '.join(parts)}; {rest}"
