"""The process's memory budget for stored input (:class:`~bagmcp_shared.settings.InputBudget`), and the
checks every reader makes with it before it decompresses a record or decodes an image.

One budget per process, set where the process reads its settings (``use_input_budget``), because the
checks sit deep in the bag readers and image decoders that many callers reach; the defaults hold until then.
Each check raises :class:`~bagmcp_shared.errors.UnsupportedFormatError` naming the bag and the record,
so a hostile file is refused in a sentence instead of costing gigabytes: a 16.6 KB MCAP whose one chunk
declares 512 MiB grew the bag-store and a worker 1.3 GB each before these checks.
"""

from __future__ import annotations

from bagmcp_shared.errors import UnsupportedFormatError
from bagmcp_shared.settings import InputBudget

_current = InputBudget()


def use_input_budget(budget: InputBudget) -> None:
    global _current  # one budget per process, set once at its start
    _current = budget


def input_budget() -> InputBudget:
    return _current


def check_record(where: str, *, declared_bytes: int, compressed_bytes: int) -> int:
    """The limit for one compressed record (``where`` names the bag and the record, e.g. "x.mcap: the chunk
    at byte 123"); refuses it when what it declares is already past that limit."""
    limit = _current.record_limit(compressed_bytes)
    if declared_bytes > limit:
        raise record_refused(
            where, f"declares {declared_bytes:,} bytes uncompressed from {compressed_bytes:,} compressed"
        )
    return limit


def record_refused(where: str, detail: str) -> UnsupportedFormatError:
    """The error for a record that declares (``detail``), or turns out to hold, more than the budget allows."""
    budget = _current
    return UnsupportedFormatError(
        f"{where} {detail}: more than this server decompresses (a record may expand {budget.max_expansion:.0f} "
        f"times once past {budget.expansion_floor_bytes >> 20} MiB, to at most {budget.max_record_bytes >> 20} MiB: "
        "BAGMCP_MAX_EXPANSION, BAGMCP_MAX_RECORD_BYTES), so it is refused as a decompression bomb; "
        "rewrite the recording with smaller chunks"
    )


def check_image(what: str, *, width: int, height: int, bytes_per_pixel: int) -> None:
    """Refuses an image whose pixels would take more than the budget, before they are decoded; a ValueError,
    as the image decoders raise for every image they cannot show."""
    needed = width * height * bytes_per_pixel
    if needed > _current.max_image_bytes:
        raise ValueError(
            f"{what} is {width:,} x {height:,} pixels ({needed:,} bytes decoded), more than the "
            f"{_current.max_image_bytes:,} bytes this server decodes (BAGMCP_MAX_IMAGE_BYTES); "
            "pick a smaller image or raise the limit"
        )
