"""One exception root for the shared library; every failure a user can see is one of these."""

from __future__ import annotations


class BagmcpError(Exception):
    """Root of every error raised on purpose by bagmcp code.

    ``str(err)`` is a complete, human-readable sentence that says what went wrong and,
    where possible, what to do next. It never contains a traceback.
    """


MAX_SENTENCE_CHARS = 1_500  # what a caller sees of one error; the head says what, the tail what to do
_TAIL_CHARS = 400


def sentence(err: BagmcpError) -> str:
    """``str(err)`` as callers see it (HTTP, MCP, a failed job): cut in the middle past MAX_SENTENCE_CHARS.
    Errors quote the caller's arguments (a bag name, a value, a path), and a 10 KB argument was echoed back
    whole; the cut keeps the start (what went wrong) and the end (what to do)."""
    text = str(err)
    if len(text) <= MAX_SENTENCE_CHARS:
        return text
    head = MAX_SENTENCE_CHARS - _TAIL_CHARS
    return f"{text[:head]} … ({len(text) - head - _TAIL_CHARS:,} characters left out) … {text[-_TAIL_CHARS:]}"


class BagError(BagmcpError):
    """A bag could not be opened or read."""


class UnsupportedFormatError(BagError):
    """The input is not a bag format bagmcp reads (e.g. PX4 ULog, ROS bag format 1.2)."""


class DamagedBagError(BagError):
    """The input looks like a supported bag but its contents are damaged or truncated."""


class EmptyFileError(DamagedBagError):
    """The input file has no bytes at all."""


class DecodeError(BagError):
    """A message could not be decoded (missing or broken message definition)."""


class TopicNotFoundError(BagmcpError):
    """A topic named by the caller is not in the bag."""


class MessagePathError(BagmcpError):
    """A message path does not resolve on the topic's message type."""


class TimeError(BagmcpError):
    """A time argument cannot be parsed or lies outside the bag."""


class StorageError(BagmcpError):
    """The object store failed or refused an operation."""


class ObjectNotFoundError(StorageError):
    """The object store has no object under the requested key."""


class InvalidKeyError(StorageError):
    """An object key is malformed or tries to escape the store (e.g. ``..``)."""


class ArgumentError(BagmcpError):
    """A tool or route argument is out of range or of the wrong kind."""


class SettingsError(BagmcpError):
    """A setting is missing or unsafe; the process refuses to start."""


class BagNotFoundError(BagmcpError):
    """No bag matches the id, name or prefix the caller gave."""


class AmbiguousBagError(BagmcpError):
    """A prefix matches more than one bag."""


class NameTakenError(BagmcpError):
    """Another bag already has this name."""


class BagNotReadyError(BagmcpError):
    """The bag is still being ingested, or its ingest failed."""


class JobNotFoundError(BagmcpError):
    """No job with this id belongs to the caller."""


class JobCancelledError(BagmcpError):
    """The job's owner cancelled it; the work stops at its next progress report."""
