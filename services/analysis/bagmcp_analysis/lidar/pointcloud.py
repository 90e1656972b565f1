"""sensor_msgs/PointCloud2 summary: x/y/z decoded with a strided numpy view (offsets, padding, endianness)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

# ROS sensor_msgs/PointField datatypes -> numpy type codes (without byte order).
DATATYPES: dict[int, str] = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}


@dataclass(frozen=True)
class CloudField:
    """One sensor_msgs/PointField: name, byte offset in the point, ROS datatype code and element count."""

    name: str
    offset: int
    datatype: int
    count: int


@dataclass(frozen=True)
class CloudExtents:
    """Axis-aligned bounding box of the valid points, in metres."""

    min_x_m: float
    max_x_m: float
    min_y_m: float
    max_y_m: float
    min_z_m: float
    max_z_m: float


@dataclass(frozen=True)
class CloudHit:
    """The point nearest the sensor origin; range_m is 3-D, bearing_deg = atan2(y, x) in degrees."""

    x: float
    y: float
    z: float
    range_m: float
    bearing_deg: float


@dataclass(frozen=True)
class CloudStats:
    """Point count, finite-xyz count, extents, closest point and the cloud's field names."""

    points: int
    valid: int
    extents: CloudExtents | None
    closest: CloudHit | None
    fields: list[str]


def _xyz_dtype(fields: Sequence[CloudField], *, point_step: int, is_bigendian: bool) -> np.dtype[np.void]:
    """Structured dtype with x, y, z at their offsets and itemsize point_step."""
    by_name: dict[str, CloudField] = {}
    for field in fields:
        by_name.setdefault(field.name, field)
    missing = [axis for axis in ("x", "y", "z") if axis not in by_name]
    if missing:
        names = ", ".join(f.name for f in fields) or "none"
        raise ValueError(f"The point cloud has no {'/'.join(missing)} field (fields: {names}); it needs x, y and z.")
    order = ">" if is_bigendian else "<"
    formats: list[str] = []
    for axis in ("x", "y", "z"):
        field = by_name[axis]
        code = DATATYPES.get(field.datatype)
        if code is None:
            raise ValueError(f"Field {axis!r} has unknown PointField datatype {field.datatype}; expected 1 to 8.")
        if field.offset < 0 or field.offset + np.dtype(code).itemsize > point_step:
            raise ValueError(f"Field {axis!r} at offset {field.offset} does not fit in point_step {point_step}.")
        formats.append(order + code)
    offsets = [by_name[axis].offset for axis in ("x", "y", "z")]
    return np.dtype({"names": ["x", "y", "z"], "formats": formats, "offsets": offsets, "itemsize": point_step})


def _xyz(
    data: bytes, dtype: np.dtype[np.void], *, point_step: int, row_step: int, width: int, height: int
) -> npt.NDArray[np.float64]:
    """(width * height, 3) float64 array of x, y, z read through a strided view of data."""
    if width * point_step > row_step and height > 1:
        raise ValueError(f"row_step {row_step} is smaller than width * point_step ({width * point_step}).")
    needed = (height - 1) * row_step + width * point_step
    if len(data) < needed:
        raise ValueError(f"The point cloud data has {len(data)} bytes but its layout needs at least {needed}.")
    view = np.ndarray(shape=(height, width), dtype=dtype, buffer=data, strides=(row_step, point_step))
    xyz = np.empty((width * height, 3), dtype=np.float64)
    for column, axis in enumerate(("x", "y", "z")):
        xyz[:, column] = view[axis].reshape(-1)
    return xyz


def cloud_stats(
    *,
    fields: Sequence[CloudField],
    data: bytes,
    point_step: int,
    row_step: int,
    width: int,
    height: int,
    is_bigendian: bool,
) -> CloudStats:
    """Summary of a PointCloud2: valid = finite x, y and z; ValueError if x, y or z is missing."""
    if point_step <= 0 or width < 0 or height < 0 or row_step < 0:
        raise ValueError("point_step must be positive and width, height and row_step non-negative.")
    dtype = _xyz_dtype(fields, point_step=point_step, is_bigendian=is_bigendian)
    names = [f.name for f in fields]
    if width == 0 or height == 0:
        return CloudStats(points=0, valid=0, extents=None, closest=None, fields=names)
    xyz = _xyz(data, dtype, point_step=point_step, row_step=row_step, width=width, height=height)
    good = xyz[np.isfinite(xyz).all(axis=1)]
    if good.shape[0] == 0:
        return CloudStats(points=xyz.shape[0], valid=0, extents=None, closest=None, fields=names)
    low, high = good.min(axis=0), good.max(axis=0)
    extents = CloudExtents(float(low[0]), float(high[0]), float(low[1]), float(high[1]), float(low[2]), float(high[2]))
    distances = np.sqrt((good * good).sum(axis=1))
    best = good[int(np.argmin(distances))]
    x, y, z = float(best[0]), float(best[1]), float(best[2])
    closest = CloudHit(
        x=x, y=y, z=z, range_m=math.sqrt(x * x + y * y + z * z), bearing_deg=math.degrees(math.atan2(y, x))
    )
    return CloudStats(
        points=int(xyz.shape[0]), valid=int(good.shape[0]), extents=extents, closest=closest, fields=names
    )
