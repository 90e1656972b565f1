"""The columnar index: what ingest extracts once so later questions avoid decoding the bag
(numeric columns of common types, TF transforms, log records), and reading it back."""

from bagmcp_shared.index.build import build_index
from bagmcp_shared.index.column_index import ColumnIndex, read_series
from bagmcp_shared.index.columns import INDEXED_COLUMNS, column_getter, scan_minimum
from bagmcp_shared.index.logs import LOG_TYPES, RECORD_TYPES, LogRow, decode_logs
from bagmcp_shared.index.series import Series, decode_series, header_rate_hz
from bagmcp_shared.index.transforms import TF_TYPES, TransformRows, decode_transforms, tf_connections

__all__ = [
    "INDEXED_COLUMNS",
    "LOG_TYPES",
    "RECORD_TYPES",
    "TF_TYPES",
    "ColumnIndex",
    "LogRow",
    "Series",
    "TransformRows",
    "build_index",
    "column_getter",
    "decode_logs",
    "decode_series",
    "decode_transforms",
    "header_rate_hz",
    "read_series",
    "scan_minimum",
    "tf_connections",
]
