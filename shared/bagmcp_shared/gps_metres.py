"""GPS fixes (``sensor_msgs/NavSatFix``, and the GPS-like types of flight logs) as local metres: east (x),
north (y) and up (z) of the first valid fix. Trajectories and plots use the same conversion, so their
numbers agree."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_shared.access import OpenBag
from bagmcp_shared.bags.counted import ReportProgress
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import Series, read_series
from bagmcp_shared.topics import fix_columns

EARTH_RADIUS_M = 6_371_008.8
Floats = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LocalMetres:
    """The valid fixes (``kept`` marks them among all given) in metres; ``up_m`` is NaN without altitude."""

    kept: npt.NDArray[np.bool_]
    east_m: Floats
    north_m: Floats
    up_m: Floats


@dataclass(frozen=True)
class LocalFixes:
    """A topic's valid fixes in a window: log times, header stamps (0 when unset) and local metres."""

    log_ns: npt.NDArray[np.int64]
    header_ns: npt.NDArray[np.int64]
    metres: LocalMetres


def local_metres(latitude_deg: Floats, longitude_deg: Floats, altitude_m: Floats, status: Floats) -> LocalMetres:
    """Fixes with status >= 0 and a finite position, as metres from the first of them (equirectangular
    projection on a sphere, accurate over a few kilometres); ValueError when none is valid."""
    lat, lon, alt = (np.asarray(a, dtype=np.float64) for a in (latitude_deg, longitude_deg, altitude_m))
    fix_status = np.asarray(status, dtype=np.float64)
    if not lat.shape == lon.shape == alt.shape == fix_status.shape:
        raise ValueError("Latitude, longitude, altitude and status must have one value per fix.")
    kept = (fix_status >= 0) & np.isfinite(lat) & np.isfinite(lon) & (np.abs(lat) <= 90.0)
    if not kept.any():
        raise ValueError("No valid GPS fix (status >= 0 with finite latitude and longitude); pick another topic.")
    lat, lon, alt = lat[kept], lon[kept], alt[kept]
    lat0, lon0 = math.radians(float(lat[0])), float(lon[0])
    east_rad = np.radians((lon - lon0 + 180.0) % 360.0 - 180.0)
    known_alt = alt[np.isfinite(alt)]
    alt0 = float(known_alt[0]) if known_alt.size else 0.0
    return LocalMetres(
        kept=kept,
        east_m=EARTH_RADIUS_M * east_rad * math.cos(lat0),
        north_m=EARTH_RADIUS_M * (np.radians(lat) - lat0),
        up_m=np.where(np.isfinite(alt), alt - alt0, np.nan),
    )


def _one_receiver(series: Series, instance: str | None) -> npt.NDArray[np.bool_]:
    """The fixes of the lowest-numbered receiver when several log into one topic (all fixes otherwise)."""
    if instance is None or not len(series.t_ns):
        return np.ones(len(series.t_ns), dtype=bool)
    receivers = series.columns[instance]
    mask: npt.NDArray[np.bool_] = receivers == receivers.min()
    return mask


def read_local_fixes(ob: OpenBag, topic: str, lo: int, hi: int, progress: ReportProgress | None = None) -> LocalFixes:
    """The valid fixes of ``topic`` in [lo, hi] (the index first); an ArgumentError when there is none. A topic
    that several receivers log into (ArduPilot's GPS, by ``I``) gives the first receiver's fixes."""
    source = fix_columns(ob, ob.msgtype(topic))
    series = read_series(
        ob.reader, topic, source.columns, index=ob.index, start_ns=lo, stop_ns=hi + 1, progress=progress
    )
    one = _one_receiver(series, source.instance)
    lat, lon, alt = (series.columns[c][one].astype(np.float64) for c in source.columns[:3])
    fixed = (
        series.columns[source.status][one].astype(np.float64) >= source.min_status
        if source.status
        else np.ones(len(lat), bool)
    )
    try:
        metres = local_metres(
            lat * source.scale_deg, lon * source.scale_deg, alt * source.scale_m, np.where(fixed, 0.0, -1.0)
        )
    except ValueError as err:
        raise ArgumentError(f"{topic} has no valid GPS fix in this window (a fix with a position)") from err
    return LocalFixes(log_ns=series.t_ns[one][metres.kept], header_ns=series.header_ns[one][metres.kept], metres=metres)
