"""What the tools need to know about flight-log types (PX4 ULog ``px4/...``, ArduPilot DataFlash
``ardupilot/...``): where positions and GPS fixes are, which columns the index extracts, which types are
log records. The ROS counterparts live beside their users (``topics``, ``index.columns``); the tables
here extend them. Field names are the logs' own (PX4 msg definitions, ArduPilot's log message docs);
where PX4 renamed fields between versions (``lat`` in 1e-7 degrees became ``latitude_deg``) every
variant is listed and the one the log's own format has is used.
"""

from __future__ import annotations

from dataclasses import dataclass

from rosbags.typesys.store import Typestore

from bagmcp_shared.errors import MessagePathError
from bagmcp_shared.paths import check_steps, parse_field_path


@dataclass(frozen=True)
class FixSource:
    """Where a GPS-like type keeps latitude, longitude (degrees after ``scale_deg``), altitude (metres
    after ``scale_m``) and its fix status (a fix counts when ``status >= min_status``; no status: all); and,
    for a type several receivers log into (ArduPilot's GPS with ``I``), the field naming the receiver."""

    latitude: str
    longitude: str
    altitude: str
    status: str | None = None
    min_status: float = 0.0
    scale_deg: float = 1.0
    scale_m: float = 1.0
    instance: str | None = None

    @property
    def columns(self) -> list[str]:
        optional = [c for c in (self.status, self.instance) if c]
        return [self.latitude, self.longitude, self.altitude, *optional]


_PX4_GPS = (
    FixSource("latitude_deg", "longitude_deg", "altitude_msl_m", "fix_type", 3.0),  # PX4 1.14 and later
    FixSource("lat", "lon", "alt", "fix_type", 3.0, 1e-7, 1e-3),  # before: 1e-7 degrees, millimetres
)
FLIGHT_FIXES: dict[str, tuple[FixSource, ...]] = {
    "px4/vehicle_gps_position": _PX4_GPS,
    "px4/sensor_gps": _PX4_GPS,
    "px4/vehicle_global_position": (FixSource("lat", "lon", "alt"),),
    "ardupilot/POS": (FixSource("Lat", "Lng", "Alt"),),  # the EKF's position: no fix status
    "ardupilot/GPS": (  # Status 3: a 3D fix; I: the receiver (logs before ArduPilot 4.0 have GPS2 instead)
        FixSource("Lat", "Lng", "Alt", "Status", 3.0, instance="I"),
        FixSource("Lat", "Lng", "Alt", "Status", 3.0),
    ),
}
# Local positions (metres, x north, y east, z down) and their heading field (rad; PX4 before 1.13: ``yaw``)
FLIGHT_POSES: dict[str, tuple[str, ...]] = {"px4/vehicle_local_position": ("heading", "yaw")}
# Preferred first: an estimator's position, then raw GPS.
FLIGHT_POSE_ORDER = (
    "px4/vehicle_local_position",
    "ardupilot/POS",
    "px4/vehicle_global_position",
    "px4/vehicle_gps_position",
    "px4/sensor_gps",
    "ardupilot/GPS",
)

_XYZ = ("x", "y", "z")
FLIGHT_COLUMNS: dict[str, tuple[tuple[str, ...], ...]] = {
    "px4/vehicle_local_position": tuple(
        ("x", "y", "z", "vx", "vy", "vz", heading, "xy_valid", "z_valid") for heading in ("heading", "yaw")
    ),
    "px4/vehicle_local_position_setpoint": (("x", "y", "z", "vx", "vy", "vz", "yaw"),),
    "px4/trajectory_setpoint": (
        (*(f"position[{i}]" for i in range(3)), *(f"velocity[{i}]" for i in range(3)), "yaw"),
        ("x", "y", "z", "vx", "vy", "vz", "yaw"),
    ),
    "px4/vehicle_gps_position": tuple((*f.columns, "vel_m_s") for f in _PX4_GPS),
    "px4/sensor_gps": tuple((*f.columns, "vel_m_s") for f in _PX4_GPS),
    "px4/vehicle_global_position": (("lat", "lon", "alt"),),
    "px4/vehicle_status": (("nav_state", "arming_state"),),
    "px4/battery_status": (("voltage_v", "current_a", "remaining"),),
    "px4/vehicle_attitude": (tuple(f"q[{i}]" for i in range(4)),),
    "ardupilot/GPS": (("Lat", "Lng", "Alt", "Status", "Spd", "I"), ("Lat", "Lng", "Alt", "Status", "Spd")),
    "ardupilot/POS": (("Lat", "Lng", "Alt", "RelHomeAlt"),),
    "ardupilot/ATT": (("Roll", "Pitch", "Yaw", "DesRoll", "DesPitch", "DesYaw"),),
    "ardupilot/BAT": (("Volt", "Curr"),),
    "ardupilot/CURR": (("Volt", "Curr"),),
    "ardupilot/MODE": (("ModeNum",), ("Mode",)),
    "ardupilot/CTUN": (("Alt", "DAlt", "BAlt"),),
}
LOGGED_TYPE = "px4/logged_message"
MSG_TYPE = "ardupilot/MSG"
ERR_TYPE = "ardupilot/ERR"
FLIGHT_LOG_TYPES = frozenset({LOGGED_TYPE, MSG_TYPE, ERR_TYPE})


def _fits(store: Typestore, msgtype: str, columns: tuple[str, ...] | list[str]) -> bool:
    try:
        for column in columns:
            check_steps(store, msgtype, parse_field_path(column))
    except MessagePathError:
        return False
    return True


def flight_columns(store: Typestore, msgtype: str) -> tuple[str, ...] | None:
    """The index columns of a flight type, in the variant its definition has; None when none fits."""
    return next((c for c in FLIGHT_COLUMNS.get(msgtype, ()) if _fits(store, msgtype, c)), None)


def heading_field(store: Typestore, msgtype: str) -> str | None:
    """The heading field of a flight local-position type, in the variant its definition has."""
    return next((f for f in FLIGHT_POSES.get(msgtype, ()) if _fits(store, msgtype, [f])), None)


def fix_source(store: Typestore, msgtype: str) -> FixSource | None:
    """Where ``msgtype`` (a flight GPS-like type) keeps its fix, in the variant its definition has."""
    return next((f for f in FLIGHT_FIXES.get(msgtype, ()) if _fits(store, msgtype, f.columns)), None)
