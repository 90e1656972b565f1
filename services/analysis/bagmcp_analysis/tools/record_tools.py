"""MCP adapters for records and frames: analyze_logs, get_tf_tree, lookup_transform, topic_statistics."""

from __future__ import annotations

from typing import Annotated

from mcp.server.mcpserver import Context
from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_analysis.job_kinds import (
    LOGS,
    STATISTICS,
    TF_TREE,
    TRANSFORM,
    LogParams,
    StatisticsParams,
    TfTreeParams,
    TransformParams,
)
from bagmcp_analysis.queries.logs import logs_are_small
from bagmcp_analysis.queries.statistics import statistics_are_small
from bagmcp_analysis.queries.tf import tf_is_small
from bagmcp_analysis.reports.logs import LogReport
from bagmcp_analysis.reports.statistics import TopicStatisticsReport
from bagmcp_analysis.reports.tf import TfTreeReport, TransformReport
from bagmcp_kit.answers import tool_errors
from bagmcp_kit.arguments import READ_ONLY, BagRef, Offset, TimeArg, TopicName, params_of
from bagmcp_kit.jobs import LongAnswer
from bagmcp_kit.toolsets import BagTools, tool
from bagmcp_shared.wording import counted

Level = Annotated[str | None, Field(description="DEBUG, INFO, WARN, ERROR, FATAL (or number)")]
Frame = Annotated[str, Field(description="TF frame id")]


def _log_summary(r: LogReport) -> str:
    levels = ", ".join(f"{n} {c}" for n, c in (r.summary.by_level.items() if r.summary else []) if c)
    return f"{counted(r.total, 'log record')} match ({levels or 'none'}); showing {r.returned}"


def _transform_summary(r: TransformReport) -> str:
    return f"{r.source_frame} in {r.target_frame}: {[round(v, 4) for v in r.translation_m]} m, yaw {r.yaw_deg:.2f} deg"


def _statistics_summary(r: TopicStatisticsReport) -> str:
    return (
        f"{r.topic}: {r.count} messages at {r.rate_hz or 0:.3f} Hz, {r.gap_count} gaps, ~{r.dropped_estimate} dropped"
    )


class RecordTools(BagTools):
    @tool(READ_ONLY)
    async def analyze_logs(
        self,
        ctx: Context,
        bag: BagRef,
        level: Level = None,
        min_level: Annotated[str | None, Field(description="this level or worse")] = None,
        node: Annotated[str | None, Field(description="node name (or part of it)")] = None,
        contains: Annotated[str | None, Field(description="text in the message, any case")] = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        summary: bool = True,
        topic: Annotated[str | None, Field(description="default: every log topic")] = None,
        offset: Offset = 0,
        limit: Annotated[int, Field(ge=1, le=500, description="records to show")] = 50,
    ) -> Annotated[CallToolResult, LongAnswer[LogReport]]:
        """ROS 1 and ROS 2 log records (/rosout) filtered by exact `level` or `min_level`, node, text and time,
        with counts by level and node, first and last errors, and bursts. Example: min_level="WARN"."""
        with tool_errors():
            params = params_of(
                LogParams,
                bag=bag,
                topic=topic,
                level=level,
                min_level=min_level,
                node=node,
                contains=contains,
                start=start,
                end=end,
                summary=summary,
                limit=limit,
                offset=offset,
            )
        return await self._work.run(ctx, LOGS, params, _log_summary, small=lambda p: logs_are_small(self._access, p))

    @tool(READ_ONLY)
    async def get_tf_tree(
        self, ctx: Context, bag: BagRef, time: Annotated[TimeArg | None, Field(description="default: whole bag")] = None
    ) -> Annotated[CallToolResult, LongAnswer[TfTreeReport]]:
        """TF frames, their parent/child edges (static or dynamic, with rates), roots, and frames with more than
        one parent. Example: time=10."""
        with tool_errors():
            params = params_of(TfTreeParams, bag=bag, time=time)
        return await self._work.run(
            ctx,
            TF_TREE,
            params,
            lambda r: f"{counted(len(r.frames), 'frame')}, roots {', '.join(r.roots)}, {counted(len(r.edges), 'edge')}",
            small=lambda p: tf_is_small(self._access, p.bag),
        )

    @tool(READ_ONLY)
    async def lookup_transform(
        self,
        ctx: Context,
        bag: BagRef,
        target_frame: Frame,
        source_frame: Frame,
        time: Annotated[TimeArg | None, Field(description="default: end of the bag")] = None,
    ) -> Annotated[CallToolResult, LongAnswer[TransformReport]]:
        """The transform from source_frame to target_frame at a time, chained through the TF tree and
        interpolated: translation, quaternion, roll/pitch/yaw. Example: target_frame=map, source_frame=laser."""
        with tool_errors():
            params = params_of(
                TransformParams, bag=bag, target_frame=target_frame, source_frame=source_frame, time=time
            )
        return await self._work.run(
            ctx,
            TRANSFORM,
            params,
            _transform_summary,
            small=lambda p: tf_is_small(self._access, p.bag),
        )

    @tool(READ_ONLY)
    async def topic_statistics(
        self,
        ctx: Context,
        bag: BagRef,
        topic: TopicName,
        gap_periods: Annotated[float, Field(gt=1, description="a gap: longer than this many periods")] = 3.0,
    ) -> Annotated[CallToolResult, LongAnswer[TopicStatisticsReport]]:
        """Timing of one topic: rate, jitter, gaps, estimated dropped messages, header-stamp delay.
        Example: topic="/imu", gap_periods=5."""
        with tool_errors():
            params = params_of(StatisticsParams, bag=bag, topic=topic, gap_periods=gap_periods)
        return await self._work.run(
            ctx,
            STATISTICS,
            params,
            _statistics_summary,
            small=lambda p: statistics_are_small(self._access, p),
        )
