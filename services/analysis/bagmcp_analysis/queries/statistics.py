"""topic_statistics: rate, jitter, gaps, dropped messages and header delay of one topic."""

from __future__ import annotations

from typing import Annotated

import numpy as np
import numpy.typing as npt
from pydantic import BaseModel, Field

from bagmcp_analysis.reports.statistics import GapOut, TopicStatisticsReport
from bagmcp_analysis.timing import topic_timing
from bagmcp_kit.arguments import BagRef, TopicName
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.bags.stamps import topic_stamps
from bagmcp_shared.jobs import Progress


class StatisticsParams(BaseModel):
    """The arguments of topic_statistics."""

    bag: BagRef
    topic: TopicName
    gap_periods: Annotated[float, Field(gt=1, description="a gap: longer than this many periods")] = 3.0


def stamps_of(
    ob: OpenBag, topic: str, lo: int | None = None, hi: int | None = None, progress: Progress | None = None
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64] | None, str]:
    """Log times and header stamps of a topic: from the index when it holds the topic, else the bag."""
    stop = None if hi is None else hi + 1
    if ob.index is not None and ob.indexed(topic):
        series = ob.index.read(topic, [], start_ns=lo, stop_ns=stop)
        headers = series.header_ns if bool((series.header_ns > 0).any()) else None
        return series.t_ns, headers, "index"
    times, headers = topic_stamps(ob.reader, topic, start_ns=lo, stop_ns=stop, progress=progress)
    return times, headers, "bag"


def topic_statistics(access: BagAccess, params: StatisticsParams, progress: Progress) -> TopicStatisticsReport:
    with access.open(params.bag) as ob:
        topic = ob.topic_name(params.topic)
        times, headers, source = stamps_of(ob, topic, progress=progress)
        timing = topic_timing(times, headers, gap_periods=params.gap_periods)
        return TopicStatisticsReport(
            bag=ob.name,
            topic=topic,
            type=ob.msgtype(topic),
            count=timing.count,
            start=ob.instant(int(times.min())) if len(times) else None,
            end=ob.instant(int(times.max())) if len(times) else None,
            clock="log_time",
            rate_hz=timing.rate_hz,
            nominal_rate_hz=timing.nominal_rate_hz,
            median_period_s=timing.median_period_s,
            jitter_s=timing.jitter_s,
            jitter_p95_s=timing.jitter_p95_s,
            min_period_s=timing.min_period_s,
            max_period_s=timing.max_period_s,
            gaps=[
                GapOut(start=ob.instant(g.start_ns), end=ob.instant(g.end_ns), length_s=g.length_s, periods=g.periods)
                for g in timing.gaps
            ],
            gap_count=timing.gap_count,
            dropped_estimate=timing.dropped_estimate,
            duplicates=timing.duplicates,
            out_of_order=timing.out_of_order,
            header=timing.header,
            source=source,
        )


def statistics_are_small(access: BagAccess, params: StatisticsParams) -> bool:
    with access.open(params.bag) as ob:
        topic = ob.topic_name(params.topic)
        return ob.indexed(topic) or ob.topic(topic).count <= 50_000  # stamps are read without decoding
