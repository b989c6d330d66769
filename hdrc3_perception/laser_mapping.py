"""Elevation map building from the rotating laser range finder (chapter section 11.2).

Each scan line of the LMS-291 is registered with the aircraft's own navigation solution (the
Data Interface's state, never the simulator's truth): the beam geometry is the one the sensor is
built to (:func:`sim.airframe.scan_rays` with the mount calibration of :mod:`sim.airframe`),
and the pose at the scan's time is interpolated between the two states around it. Scans come in
faster (13-53 ms) and earlier than states (25 Hz, after the filter), so they wait in a bounded
queue until a state at or after their time has arrived.

The point cloud is "sampled with 1 meter resolution" (§11.2) into a grid: the highest return per
cell, the top surface a path planner must clear, kept only for cells with ``min_returns``
returns so that a single stray return does not make a tower. Returns beyond ``max_range_used``
are left out: the attitude error grows a height error of range x angle (0.5 deg at 80 m is 0.7 m).
"""

from __future__ import annotations

import enum
import math
from collections import deque
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import ConfigError
from hdrc3_navigation.elevation_map import ElevationMap
from hdrc3_perception.camera import NavPose
from sim.airframe import scan_rays

Bounds = tuple[float, float, float, float]
"""(east min, north min, east max, north max), m."""


@dataclass(frozen=True, slots=True)
class MapperConfig:
    """How scans become a grid."""

    resolution: float = 1.0
    """Cell edge, m (the chapter's 1 m)."""
    max_range_used: float = 60.0
    """Returns farther than this are not used, m."""
    min_range: float = 2.0
    """Returns nearer than this (the own airframe, the skids) are not used, m."""
    min_returns: int = 2
    """A cell is mapped once it holds this many returns."""
    queue: int = 500
    """Scans waiting for a state (6.5 s at 13 ms per scan); the oldest are dropped beyond."""
    max_state_gap: float = 0.25
    """Two states further apart than this (s) do not bracket a scan: it is dropped."""

    def problem(self) -> str | None:
        """Why this configuration cannot work, or None."""
        if not (math.isfinite(self.resolution) and 0.1 <= self.resolution <= 10.0):
            return f"resolution must be within [0.1, 10] m, got {self.resolution}"
        if not (0.0 <= self.min_range < self.max_range_used <= 80.0):
            return "need 0 <= min_range < max_range_used <= 80 m"
        if self.min_returns < 1 or self.queue < 1 or not self.max_state_gap > 0.0:
            return "min_returns, queue and max_state_gap must be positive"
        return None


@dataclass(frozen=True, slots=True)
class ScanLine:
    """One scan line as the sensor reports it (``RotatingLaserScan``)."""

    time: float
    rotation_angle: float
    angle_min: float
    angle_increment: float
    ranges: NDArray[np.float64]
    """m per beam, inf where nothing returned."""

    def beam_angles(self) -> NDArray[np.float64]:
        """Beam angles in the scan plane, rad."""
        angles: NDArray[np.float64] = self.angle_min + self.angle_increment * np.arange(
            len(self.ranges), dtype=np.float64
        )
        return angles


class Drop(enum.Enum):
    """Why a scan line did not reach the map."""

    BEFORE_FIRST_STATE = "older than the first state"
    STATE_GAP = "the states around it are too far apart"
    QUEUE_FULL = "no state came while the queue filled"
    MALFORMED = "non-finite angles"


@dataclass(frozen=True, slots=True)
class TimedPose:
    """A navigation state at a time."""

    time: float
    pose: NavPose


def interpolate(a: TimedPose, b: TimedPose, time: float) -> NavPose:
    """The pose at ``time`` between two states (heading along the shorter way round)."""
    span = b.time - a.time
    f = 0.0 if span <= 0.0 else min(1.0, max(0.0, (time - a.time) / span))
    pa, pb = a.pose, b.pose
    position = tuple(x + f * (y - x) for x, y in zip(pa.position, pb.position, strict=True))
    turn = (pb.heading - pa.heading + math.pi) % math.tau - math.pi
    return NavPose(
        (position[0], position[1], position[2]),
        pa.roll + f * (pb.roll - pa.roll),
        pa.pitch + f * (pb.pitch - pa.pitch),
        (pa.heading + f * turn) % math.tau,
    )


class LaserMapper:
    """Accumulates registered laser returns into a height grid over an area.

    Args:
        bounds: The area mapped; returns outside it are counted but not kept.
        config: Grid and filtering settings.

    Raises:
        ConfigError: Empty or non-finite bounds, or an impossible configuration.

    """

    def __init__(self, bounds: Bounds, config: MapperConfig | None = None) -> None:
        self.config = config or MapperConfig()
        problem = self.config.problem()
        e0, n0, e1, n1 = bounds
        if problem is None and not (all(math.isfinite(v) for v in bounds) and e0 < e1 and n0 < n1):
            problem = f"map bounds must be finite with min < max, got {bounds}"
        if problem is not None:
            raise ConfigError(problem)
        r = self.config.resolution
        self.east0, self.north0 = e0, n0
        self.columns, self.rows = math.ceil((e1 - e0) / r), math.ceil((n1 - n0) / r)
        self._top = np.full(self.rows * self.columns, -np.inf)
        self._count = np.zeros(self.rows * self.columns, dtype=np.int64)
        self._scans: deque[ScanLine] = deque()
        self._last: TimedPose | None = None
        self.points = 0
        """Returns kept in the grid."""
        self.dropped: dict[Drop, int] = dict.fromkeys(Drop, 0)

    def reset(self) -> None:
        """Forget every return (a new map); the last state is kept."""
        self._top[:] = -np.inf
        self._count[:] = 0
        self._scans.clear()
        self.points = 0
        self.dropped = dict.fromkeys(Drop, 0)

    def add_scan(self, scan: ScanLine) -> None:
        """Queue a scan line until a state at or after its time arrives."""
        if not all(math.isfinite(v) for v in (scan.time, scan.rotation_angle, scan.angle_min)):
            self.dropped[Drop.MALFORMED] += 1
            return
        if self._last is not None and scan.time < self._last.time - self.config.max_state_gap:
            self.dropped[Drop.STATE_GAP] += 1
            return
        if len(self._scans) >= self.config.queue:
            self._scans.popleft()
            self.dropped[Drop.QUEUE_FULL] += 1
        self._scans.append(scan)

    def add_state(self, time: float, pose: NavPose) -> list[NDArray[np.float64]]:
        """A navigation state: register every queued scan up to its time.

        Returns:
            The registered points (N x 3, ENU) of each scan mapped now, for display.

        """
        state = TimedPose(time, pose)
        previous, self._last = self._last, state
        clouds = []
        while self._scans and self._scans[0].time <= time:
            scan = self._scans.popleft()
            if previous is None:
                self.dropped[Drop.BEFORE_FIRST_STATE] += 1
            elif scan.time < previous.time or time - previous.time > self.config.max_state_gap:
                self.dropped[Drop.STATE_GAP] += 1
            else:
                clouds.append(self._register(scan, interpolate(previous, state, scan.time)))
        return clouds

    def _register(self, scan: ScanLine, pose: NavPose) -> NDArray[np.float64]:
        ranges = np.asarray(scan.ranges, dtype=np.float64)
        origin, directions = scan_rays(
            pose.position,
            (pose.roll, pose.pitch, pose.heading),
            scan.rotation_angle,
            scan.beam_angles(),
        )
        cfg = self.config
        keep = np.isfinite(ranges) & (ranges >= cfg.min_range) & (ranges <= cfg.max_range_used)
        points: NDArray[np.float64] = origin + directions[keep] * ranges[keep, None]
        col = np.floor((points[:, 0] - self.east0) / cfg.resolution).astype(np.int64)
        row = np.floor((points[:, 1] - self.north0) / cfg.resolution).astype(np.int64)
        inside = (col >= 0) & (col < self.columns) & (row >= 0) & (row < self.rows)
        cells = row[inside] * self.columns + col[inside]
        np.maximum.at(self._top, cells, points[inside, 2])
        np.add.at(self._count, cells, 1)
        self.points += int(inside.sum())
        return points

    @property
    def mapped_cells(self) -> int:
        """Cells holding at least ``min_returns`` returns."""
        return int((self._count >= self.config.min_returns).sum())

    def snapshot(self, name: str) -> ElevationMap:
        """The map so far (cells with too few returns unmapped)."""
        heights = np.where(self._count >= self.config.min_returns, self._top, np.nan)
        shape = (self.rows, self.columns)
        return ElevationMap(
            name,
            self.east0,
            self.north0,
            self.config.resolution,
            heights.reshape(shape),
            self._count.reshape(shape).copy(),
        )
