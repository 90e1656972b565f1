"""A bag summary as JSON-ready data and as the text ``bagmcp info`` prints."""

from __future__ import annotations

from bagmcp_shared.bags.models import BagSummary, TopicSummary
from bagmcp_shared.timebase import iso_from_ns

JsonDict = dict[str, object]


def _instant(stamp_ns: int | None) -> JsonDict | None:
    if stamp_ns is None:
        return None
    return {"iso": iso_from_ns(stamp_ns), "epoch_s": stamp_ns / 1e9, "epoch_ns": stamp_ns}


def topic_dict(topic: TopicSummary) -> JsonDict:
    rate = topic.rate_hz
    return {
        "name": topic.name,
        "type": topic.msgtype,
        "count": topic.count,
        "rate_hz": round(rate, 4) if rate is not None else None,
        "first": _instant(topic.first_ns),
        "last": _instant(topic.last_ns),
    }


def summary_dict(summary: BagSummary) -> JsonDict:
    """Everything ``bagmcp info --json`` prints; also what the catalog stores."""
    return {
        "path": summary.path,
        "format": str(summary.format),
        "profile": summary.profile,
        "files": list(summary.files),
        "size_bytes": summary.size_bytes,
        "message_count": summary.message_count,
        "duration_s": round(summary.duration_s, 9),
        "start": _instant(summary.start_ns),
        "end": _instant(summary.end_ns),
        "topics": [topic_dict(t) for t in summary.topics],
        "notes": list(summary.notes),
    }


def _size_text(size: int) -> str:
    value = float(size)
    for unit in ("B", "KiB", "MiB", "GiB"):
        if value < 1024 or unit == "GiB":
            return f"{value:.1f} {unit}" if unit != "B" else f"{size} B"
        value /= 1024
    return f"{size} B"


def _instant_text(stamp_ns: int | None) -> str:
    if stamp_ns is None:
        return "-"
    seconds, nanos = divmod(stamp_ns, 1_000_000_000)
    return f"{iso_from_ns(stamp_ns)} ({seconds}.{nanos:09d})"


def summary_text(summary: BagSummary) -> str:
    """A ``ros2 bag info``-like block of text."""
    lines = [
        f"Path:      {summary.path}",
        f"Files:     {', '.join(summary.files)}",
        f"Format:    {summary.format}" + (f" (profile {summary.profile})" if summary.profile else ""),
        f"Size:      {_size_text(summary.size_bytes)}",
        f"Duration:  {summary.duration_s:.3f} s",
        f"Start:     {_instant_text(summary.start_ns)}",
        f"End:       {_instant_text(summary.end_ns)}",
        f"Messages:  {summary.message_count}",
        f"Topics:    {len(summary.topics)}",
    ]
    width = max((len(t.name) for t in summary.topics), default=0)
    for t in summary.topics:
        rate = f"{t.rate_hz:.2f} Hz" if t.rate_hz is not None else "-"
        lines.append(f"  {t.name:<{width}}  {t.msgtype}  count={t.count}  rate={rate}")
    lines += [f"Note:      {note}" for note in summary.notes]
    return "\n".join(lines)
