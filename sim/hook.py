"""The winch and electromagnet hook under one aircraft (chapter section 11.1.2, Figure 38).

Pure state machine, no physics: the winch pays cable out or winds it in towards a commanded
length at a fixed speed and stalls while the cable tension exceeds its rating; the electromagnet
is energised or not. Whether the magnet actually grips an object is decided by the rigid-body
world (:mod:`sim.payload`), which asks :meth:`Hook.may_grip` and reports with :meth:`Hook.gripped`.

Faults (``SimInjectFault`` on sensor ``hook``): *release* lets go of the held object at once;
*hook failure* makes the magnet lose its grip and grip nothing until cleared; *wrong box* makes
the next grip take another object than the one touched (:mod:`sim.payload` swaps them).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass


class WinchState(enum.IntEnum):
    """What the winch drum does (values equal HookState.WINCH_*)."""

    STOPPED = 0
    LOWERING = 1
    RAISING = 2
    STALLED = 3


class HookFault(enum.IntEnum):
    """Injectable hook faults (values equal SimInjectFault.MODE_*)."""

    NONE = 0
    RELEASE = 5
    HOOK_FAIL = 6
    WRONG_BOX = 7


@dataclass(frozen=True, slots=True)
class HookParams:
    """Winch and magnet ratings."""

    winch_speed: float = 1.0
    """m/s, paying out and winding in."""
    max_cable: float = 20.0
    """m, cable on the drum."""
    stowed_cable: float = 0.12
    """m, cable out when the hook is wound in (the hook hangs just below the fuselage)."""
    stall_tension: float = 240.0
    """N: the drum does not wind in above this tension (about 24 kg hanging with the hook).
    Below the RMAX's nominal 30 kg payload, the planner's first lift-capacity assumption
    (``hdrc3_tst.goal_planning.HELICOPTER_LIFT``): a heavier load is found out by a failed lift
    (section 9.3)."""
    hook_mass: float = 1.5
    """kg, electromagnet and cable end."""
    hook_radius: float = 0.08
    """m, the magnet's (spherical) collision shape."""
    load_cell_time: float = 0.2
    """s, time constant of the load cell's filter (a hook paid out at the winch's speed falls
    in short free falls and jerks, so the raw constraint force is zero most of the time)."""


@dataclass(frozen=True, slots=True)
class HookReading:
    """What the ``carrying`` sensor reports (HookState)."""

    carrying: bool
    object_id: str
    magnet: bool
    winch: WinchState
    cable_length: float
    tension: float


class Hook:
    """Winch length, magnet switch, held object and faults of one aircraft's hook."""

    def __init__(self, params: HookParams | None = None) -> None:
        """Hook wound in, magnet off, nothing held, no fault."""
        self.params = params or HookParams()
        self.target = self.params.stowed_cable
        self.length = self.params.stowed_cable
        self.magnet = False
        self.held: str | None = None
        self.winch = WinchState.STOPPED
        self.tension = 0.0
        self.failed = False
        """HOOK_FAIL injected and not cleared."""
        self.wrong_box = False
        """WRONG_BOX injected: the next grip takes another object."""
        self.release_now = False
        """RELEASE injected: the world lets go of the held object at its next step."""
        self.armed = True
        """False after the magnet lost a held object while energised: it grips again only after
        being switched off and on (else it would re-grip the object it just dropped)."""

    # ---------------------------------------------------------------- inputs
    def command(self, cable_length: float, magnet: bool) -> None:
        """New set-point; the length is clamped to [stowed, max] (unchecked otherwise)."""
        p = self.params
        self.target = min(max(cable_length, p.stowed_cable), p.max_cable)
        self.magnet = magnet
        if not magnet:
            self.armed = True

    def inject(self, fault: HookFault) -> None:
        """Switch a fault on (NONE clears hook failure and a pending wrong box)."""
        if fault is HookFault.NONE:
            self.failed = False
            self.wrong_box = False
        elif fault is HookFault.RELEASE:
            self.release_now = self.held is not None
        elif fault is HookFault.HOOK_FAIL:
            self.failed = True
        else:
            self.wrong_box = True

    # ------------------------------------------------------------------ step
    def step(self, dt: float, tension: float) -> float:
        """Move the drum for ``dt`` s under ``tension`` N; return the cable length now."""
        self.tension += (tension - self.tension) * min(1.0, dt / self.params.load_cell_time)
        error = self.target - self.length
        if abs(error) < 1e-9:
            self.winch = WinchState.STOPPED
        elif error > 0.0:
            self.winch = WinchState.LOWERING
            self.length = min(self.target, self.length + self.params.winch_speed * dt)
        elif tension > self.params.stall_tension:
            self.winch = WinchState.STALLED
        else:
            self.winch = WinchState.RAISING
            self.length = max(self.target, self.length - self.params.winch_speed * dt)
        return self.length

    # ------------------------------------------------------------- gripping
    def may_grip(self) -> bool:
        """True when the magnet is on, works and holds nothing yet."""
        return self.magnet and self.armed and not self.failed and self.held is None

    def must_let_go(self) -> bool:
        """True when a held object has to fall: magnet off, hook failure or an injected release."""
        return self.held is not None and (not self.magnet or self.failed or self.release_now)

    def gripped(self, object_id: str) -> None:
        """The world attached ``object_id`` to the magnet."""
        self.held = object_id
        self.wrong_box = False

    def let_go(self) -> None:
        """The world detached the held object."""
        self.held = None
        self.release_now = False
        self.armed = not self.magnet

    def reading(self) -> HookReading:
        """The ``carrying`` sensor's sample now."""
        tension = self.tension if math.isfinite(self.tension) else 0.0
        return HookReading(
            carrying=self.held is not None,
            object_id=self.held or "",
            magnet=self.magnet,
            winch=self.winch,
            cable_length=self.length,
            tension=tension,
        )
