"""Opening and reading bags of every supported format through one interface."""

from bagmcp_shared.bags.decoding import Decoder
from bagmcp_shared.bags.models import (
    BagFormat,
    BagSummary,
    Compression,
    Connection,
    Encoding,
    RawMessage,
    TopicSummary,
)
from bagmcp_shared.bags.reader import BagReader, open_bag, open_directory_stream, open_stream

__all__ = [
    "BagFormat",
    "BagReader",
    "BagSummary",
    "Compression",
    "Connection",
    "Decoder",
    "Encoding",
    "RawMessage",
    "TopicSummary",
    "open_bag",
    "open_directory_stream",
    "open_stream",
]
