"""The declarations of the record and frame tools: analyze_logs, get_tf_tree, lookup_transform,
topic_statistics (their params models live beside their queries)."""

from __future__ import annotations

from bagmcp_analysis.queries.logs import LogParams, analyze_logs, logs_are_small
from bagmcp_analysis.queries.statistics import StatisticsParams, statistics_are_small, topic_statistics
from bagmcp_analysis.queries.tf import TfTreeParams, TransformParams, get_tf_tree, lookup_transform, tf_is_small
from bagmcp_analysis.reports.logs import LogReport
from bagmcp_analysis.reports.statistics import TopicStatisticsReport
from bagmcp_analysis.reports.tf import TfTreeReport, TransformReport
from bagmcp_kit.declared import Declared
from bagmcp_shared.wording import counted


def _log_summary(r: LogReport) -> str:
    levels = ", ".join(f"{n} {c}" for n, c in (r.summary.by_level.items() if r.summary else []) if c)
    return f"{counted(r.total, 'log record')} match ({levels or 'none'}); showing {r.returned}"


def _tree_summary(r: TfTreeReport) -> str:
    return f"{counted(len(r.frames), 'frame')}, roots {', '.join(r.roots)}, {counted(len(r.edges), 'edge')}"


def _transform_summary(r: TransformReport) -> str:
    return f"{r.source_frame} in {r.target_frame}: {[round(v, 4) for v in r.translation_m]} m, yaw {r.yaw_deg:.2f} deg"


def _statistics_summary(r: TopicStatisticsReport) -> str:
    return (
        f"{r.topic}: {r.count} messages at {r.rate_hz or 0:.3f} Hz, {r.gap_count} gaps, ~{r.dropped_estimate} dropped"
    )


LOGS = Declared(
    "analyze_logs",
    "ROS 1 and ROS 2 log records (/rosout) filtered by exact `level` or `min_level`, node, text and time, "
    'with counts by level and node, first and last errors, and bursts. Example: min_level="WARN".',
    LogParams,
    LogReport,
    analyze_logs,
    _log_summary,
    small=logs_are_small,
    job="logs",
)
TF_TREE = Declared(
    "get_tf_tree",
    "TF frames, their parent/child edges (static or dynamic, with rates), roots, and frames with more than "
    "one parent. Example: time=10.",
    TfTreeParams,
    TfTreeReport,
    get_tf_tree,
    _tree_summary,
    small=lambda access, p: tf_is_small(access, p.bag),
    job="tf_tree",
)
TRANSFORM = Declared(
    "lookup_transform",
    "The transform from source_frame to target_frame at a time, chained through the TF tree and "
    "interpolated: translation, quaternion, roll/pitch/yaw. Example: target_frame=map, source_frame=laser.",
    TransformParams,
    TransformReport,
    lookup_transform,
    _transform_summary,
    small=lambda access, p: tf_is_small(access, p.bag),
)
STATISTICS = Declared(
    "topic_statistics",
    "Timing of one topic: rate, jitter, gaps, estimated dropped messages, header-stamp delay. "
    'Example: topic="/imu", gap_periods=5.',
    StatisticsParams,
    TopicStatisticsReport,
    topic_statistics,
    _statistics_summary,
    small=statistics_are_small,
)
