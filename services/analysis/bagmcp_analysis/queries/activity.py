"""How each topic behaved in a window against the whole bag: counts, rates, silences and header delays."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.queries.statistics import stamps_of
from bagmcp_analysis.reports.window import TopicActivity, TopicStatus
from bagmcp_analysis.timing import HeaderTiming, header_timing
from bagmcp_shared.access import OpenBag
from bagmcp_shared.catalog import TopicStats

GAP_PERIODS = 3.0
MIN_GAP_S = 0.1
SLOW_SHARE = 0.5
LATE_MIN_EXCESS_S = 0.05
SAMPLE_STRETCHES = 8
SAMPLE_MESSAGES = 4
ORDER: dict[TopicStatus, int] = {"silent": 0, "gap": 1, "late": 2, "slow": 3, "absent": 4, "ok": 5}


def _delays(times: npt.NDArray[np.int64], headers: npt.NDArray[np.int64] | None) -> HeaderTiming | None:
    return header_timing(times, headers) if headers is not None and len(times) else None


def _bag_stamps(ob: OpenBag, stats: TopicStats) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64] | None]:
    """A topic's log times and header stamps over the bag: whole from the index, else sampled.

    A topic the index does not hold (images, point clouds) would be decoded whole: on a 2 GB bag that
    was the whole of summarize_window's cost (21-34 s cold from S3, 2 GB fetched for a 10 s window).
    Its baseline delay is instead the median over ``SAMPLE_STRETCHES`` stretches of about
    ``SAMPLE_MESSAGES`` messages spread evenly across the topic's span (32 messages, a chunk or so each).
    """
    if ob.indexed(stats.name) or stats.count <= SAMPLE_STRETCHES * SAMPLE_MESSAGES * 2 or not stats.rate_hz:
        times, headers, _ = stamps_of(ob, stats.name)
        return times, headers
    first, last = stats.first_ns or ob.start_ns, stats.last_ns or ob.end_ns
    length = int(SAMPLE_MESSAGES / stats.rate_hz * 1e9)
    step = max((last - first - length) // (SAMPLE_STRETCHES - 1), 1)
    parts = [stamps_of(ob, stats.name, first + k * step, first + k * step + length) for k in range(SAMPLE_STRETCHES)]
    times = np.concatenate([t for t, _, _ in parts])
    stamped = [h for _, h, _ in parts if h is not None]
    return times, np.concatenate(stamped) if len(stamped) == len(parts) else None


def _is_late(window: HeaderTiming | None, bag: HeaderTiming | None) -> bool:
    """Later than usual: the window's median delay is over twice the bag's, and at least 50 ms more."""
    if window is None or bag is None:
        return False
    return window.delay_median_s - bag.delay_median_s > max(LATE_MIN_EXCESS_S, abs(bag.delay_median_s))


def _status(stats: TopicStats, lo: int, hi: int, count: int, silence_s: float | None, late: bool) -> TopicStatus:
    recorded = stats.first_ns is not None and stats.last_ns is not None and stats.first_ns <= hi and stats.last_ns >= lo
    span_s = max((hi - lo) / 1e9, 1e-9)
    period = 1 / stats.rate_hz if stats.rate_hz else None
    if not recorded:
        return "absent"
    if not count and period is not None:
        return "silent"
    if period is not None and silence_s is not None and silence_s > max(GAP_PERIODS * period, MIN_GAP_S):
        return "gap"
    if late:
        return "late"
    if stats.rate_hz and span_s > 2 * (period or 0) and count / span_s < SLOW_SHARE * stats.rate_hz:
        return "slow"
    return "ok"


def topic_activity(ob: OpenBag, stats: TopicStats, lo: int, hi: int) -> TopicActivity:
    """One topic in [lo, hi]: messages, rate, longest silence and header delay against the whole bag."""
    times, headers, _ = stamps_of(ob, stats.name, lo, hi)
    window_delay = _delays(times, headers)
    bag_delay = _delays(*_bag_stamps(ob, stats)) if window_delay is not None else None
    edges = np.concatenate(([max(lo, stats.first_ns or lo)], np.sort(times), [min(hi, stats.last_ns or hi)]))
    silences = np.diff(edges)
    longest = int(silences.argmax()) if len(silences) else 0
    silence_s = float(silences[longest]) / 1e9 if len(silences) else None
    status = _status(stats, lo, hi, len(times), silence_s, _is_late(window_delay, bag_delay))
    span_s = max((hi - lo) / 1e9, 1e-9)
    return TopicActivity(
        topic=stats.name,
        count=len(times),
        rate_hz=round(len(times) / span_s, 4) if len(times) > 1 else None,
        bag_rate_hz=stats.rate_hz,
        longest_silence_s=round(silence_s, 6) if silence_s is not None else None,
        silent_from=ob.instant(int(edges[longest])) if status in ("silent", "gap") and len(silences) else None,
        delay_s=round(window_delay.delay_median_s, 6) if window_delay is not None else None,
        bag_delay_s=round(bag_delay.delay_median_s, 6) if bag_delay is not None else None,
        status=status,
    )


def activity_statement(activity: TopicActivity) -> str | None:
    """The sentence an agent can quote about a topic that was not ok, with its numbers."""
    usual = f"normally {activity.bag_rate_hz:.3g} Hz" if activity.bag_rate_hz else "usually present"
    if activity.status == "silent":
        return f"{activity.topic} was silent for the whole window ({usual})"
    if activity.status == "gap" and activity.silent_from is not None:
        return (
            f"{activity.topic} went silent for {activity.longest_silence_s:.3f} s from "
            f"{activity.silent_from.offset_s:.3f} s ({usual})"
        )
    if activity.status == "late":
        return (
            f"{activity.topic} arrived late: header stamps {activity.delay_s:.3f} s behind log time (median) "
            f"against {activity.bag_delay_s:.3f} s over the bag"
        )
    if activity.status == "slow":
        rates = f"{activity.rate_hz or 0:.3g} Hz against {activity.bag_rate_hz:.3g} Hz"
        return f"{activity.topic} ran at {rates} over the bag"
    return None
