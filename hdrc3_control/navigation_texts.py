"""The PFC's announcements about its navigation: the texts of the fault and failsafe slots.

The kernel writes them every tick into the slots its automata send with ``PFC-Fault-EV``
(``Fault-DO``, ``Baro-DO``, ``Fs-Hold-DO``, ``Fs-Land-DO``, ``Fs-End-DO``); the platform server
shows them as reasons (``hdrc3_platform_server/README.md``, failsafe policy).
"""

from __future__ import annotations

from hdrc3_control.commands import EstimatorHealth
from hdrc3_control.pfc_state import FAILSAFE_PREFIX
from hdrc3_control.state_estimator import StateEstimator


def fault_text(est: StateEstimator, now: float) -> str:
    """Navigation health at ``now`` (``Fault-DO``)."""
    if not est.initialised:
        return "navigation not initialised"
    health = est.health(now)
    if health is EstimatorHealth.OK:
        return "navigation recovered: GPS aiding current"
    if health is EstimatorHealth.DEGRADED:
        age = est.aiding_age(now)
        return f"navigation degraded: no GPS fix for {age:.1f} s, dead reckoning on the IMU"
    return f"navigation lost: {est.lost_cause(now)}"


def baro_text(est: StateEstimator) -> str | None:
    """The barometer's exclusion (``Baro-DO``), or None while it is used."""
    if est.baro_fault is None:
        return None
    return f"navigation degraded: {est.baro_fault}: barometer excluded, height from GPS"


def failsafe_texts(est: StateEstimator, now: float, on_ground: bool) -> dict[str, str]:
    """The failsafe announcements at ``now`` (slots of ``automata/failsafe.hcsm``)."""
    age = est.aiding_age(now)
    left = max(0.0, est.config.max_dead_reckoning - age)
    ended = "on the ground" if on_ground else "GPS back, hovering on GPS"
    return {
        "Fs-Hold-DO": (
            f"{FAILSAFE_PREFIX}: GPS lost for {age:.1f} s: braking and hovering on dead "
            "reckoning; flight commands other than land refused; emergency landing unless "
            f"GPS is back within {left:.1f} s"
        ),
        "Fs-Land-DO": (
            f"{FAILSAFE_PREFIX}: emergency landing: navigation lost: "
            f"{est.lost_cause(now) or 'solution unusable'}"
        ),
        "Fs-End-DO": f"{FAILSAFE_PREFIX} ended: {ended}",
    }
