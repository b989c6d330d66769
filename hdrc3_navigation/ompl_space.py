"""OMPL set-up shared by the planners: the 3D position space of the GIS's planning volume.

The state validity checker is the GIS's sphere test plus an optional extra test (runtime
constraints); the motion validator is the GIS's capsule test on the straight motion (exact for
straight edges, where OMPL's default validator would only sample points).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from ompl import base as ob
from ompl import util as ou

from hdrc3_navigation.gis import Gis, Point3

PointTest = Callable[[Point3], bool]
SegmentTest = Callable[[Point3, Point3], bool]

ou.setLogLevel(ou.LOG_WARN)


def _xyz(state: object) -> tuple[float, float, float]:
    return (state[0], state[1], state[2])  # type: ignore[index]


class _CapsuleMotionValidator(ob.MotionValidator):  # type: ignore[misc]
    """Straight motions checked by the GIS capsule test plus the extra segment test."""

    def __init__(self, si: object, segment_ok: SegmentTest) -> None:
        super().__init__(si)
        self._segment_ok = segment_ok

    def checkMotion(self, s1: object, s2: object, *rest: object) -> bool:
        """OMPL callback: is the straight motion s1 -> s2 valid."""
        return self._segment_ok(_xyz(s1), _xyz(s2))


class OmplSpace:
    """Space information for planning in a GIS's volume, with extra point/segment tests."""

    def __init__(
        self, gis: Gis, point_ok: PointTest | None = None, segment_ok: SegmentTest | None = None
    ) -> None:
        self.gis = gis
        self.space = ob.RealVectorStateSpace(3)
        bounds = ob.RealVectorBounds(3)
        lo, hi = gis.bounds
        for i in range(3):
            bounds.setLow(i, lo[i])
            bounds.setHigh(i, hi[i])
        self.space.setBounds(bounds)
        self.si = ob.SpaceInformation(self.space)
        extra_point = point_ok or (lambda p: True)
        extra_segment = segment_ok or (lambda a, b: True)

        def valid(state: object) -> bool:
            p = _xyz(state)
            return bool(extra_point(p) and gis.point_free(p))

        def motion(a: Point3, b: Point3) -> bool:
            return bool(extra_segment(a, b) and gis.segment_free(a, b))

        self._valid = valid  # OMPL keeps only a reference: keep the callables alive
        self._validator = _CapsuleMotionValidator(self.si, motion)
        self.si.setStateValidityChecker(valid)
        self.si.setMotionValidator(self._validator)
        self.si.setup()

    def state(self, p: Point3) -> object:
        """A new OMPL state at p."""
        s = self.space.allocState()
        for i in range(3):
            s[i] = float(p[i])
        return s

    @staticmethod
    def path_points(path: Any) -> NDArray[np.float64]:
        """Waypoints of an OMPL geometric path as an (n, 3) array."""
        n = path.getStateCount()
        return np.array([_xyz(path.getState(i)) for i in range(n)], dtype=np.float64)


def seed_rng(seed: int) -> None:
    """Seed OMPL's random number generator (roadmaps are then reproducible)."""
    ou.RNG.setSeed(seed)
