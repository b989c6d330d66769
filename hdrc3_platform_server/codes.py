"""Answer codes, event kinds and command names of FCL and PPCL (chapter sections 6.2.2-6.2.3).

The numeric values equal the constants of hdrc3_interfaces FclReturn, PpclReturn and
PlatformEvent, so the node copies them into messages unchanged. ``FclCode.FINISHED`` is never an
immediate answer: the chapter's FCL_FINISHED return arrives as a PlatformEvent of kind FINISHED,
and ``hdrc3 fcl`` names that event with it. What each command is (service, arguments, events,
required state) is in ``commands.py``.
"""

from __future__ import annotations

import enum


class FclCode(enum.IntEnum):
    """Answer of an FCL command (FclReturn.code; FINISHED only names the completion event)."""

    OK = 0
    BUSY = 1
    NOT_ACCEPTED = 2
    FINISHED = 3


class PpclCode(enum.IntEnum):
    """Immediate answer of a PPCL command (PpclReturn.code)."""

    OK = 0
    CONTROL_DENIED = 1
    NOT_ACCEPTED = 2
    BUSY = 3


class EventKind(enum.IntEnum):
    """Kind of a completion/progress PlatformEvent."""

    FINISHED = 0
    FAILED = 1
    CANCELLED = 2
    SEGMENT_REQUEST = 3
    INFO = 4


class FclCommand(enum.Enum):
    """The FCL commands; the value is the service name and the CLI command word."""

    TAKEOFF = "takeoff"
    LAND = "land"
    YAW = "yaw"
    CLIMB = "climb"
    TRAJ3D_FLYTO = "traj3d_flyto"
    TRAJ3D = "traj3d"
    TRACK = "track"
    EMERGENCY_BRAKE = "emergency_brake"
    CANCEL = "cancel"

    @property
    def label(self) -> str:
        """Name used in PlatformEvent.command, e.g. ``fcl_takeoff``."""
        return f"fcl_{self.value}"


class Resource(enum.IntEnum):
    """Payload resources with exclusive ownership (PpclControl.RESOURCE_*)."""

    PTU = 0
    CAMERA = 1
    IMAGE_PROCESSING = 2
    LASER = 3


class PpclCommand(enum.Enum):
    """The PPCL commands that engage a mode or set a parameter (forwarded to the PPC)."""

    LOOK_AT = "look_at"
    TURN_TO = "turn_to"
    PTU_ABORT = "ptu_abort"
    IP_COLOR_TRACKER = "ip_color_tracker"
    IP_STATE_ESTIMATION = "ip_state_estimation"
    IP_ABORT = "ip_abort"
    IP_SALIENCY = "ip_saliency"
    ZOOM = "zoom"
    EXPOSURE = "exposure"
    IRIS = "iris"
    SHUTTER = "shutter"
    LASER_ANGULAR_RESOLUTION = "laser_angular_resolution"
    LASER_DISTANCE_RESOLUTION = "laser_distance_resolution"
    LASER_ROTATION_SPEED = "laser_rotation_speed"
    LASER_ROTATION_ANGLE = "laser_rotation_angle"
    LASER_START_DATA_COLLECTION = "laser_start_data_collection"
    LASER_STOP_DATA_COLLECTION = "laser_stop_data_collection"

    @property
    def label(self) -> str:
        """Name used in PlatformEvent.command, e.g. ``ppcl_turn_to``."""
        return f"ppcl_{self.value}"


class PtuActivity(enum.IntEnum):
    """Answer of ppcl_ptu_activity_info (PpclPtuActivityInfo.Response constants)."""

    LOOK_AT_POINT = 0
    TURNTO = 1
    IDLE = 2
