"""Delivery executors: boxes and carriers on the winch hook (chapter section 11.1.2).

One executor per operator of TALplanner's UAV logistics domain
(``hdrc3_deliberative/domains/uav_logistics/domain.tal``), under the operator's name:
``pick-up-box``, ``drop-box``, ``put-on-carrier``, ``take-from-carrier``, ``attach-carrier``
and ``detach-carrier`` (``fly-to`` is the flight executor). The domain's helicopter is the
node's agent; its boxes, carriers and locations are points: an object's point is named by the
object's tag (what the magnet reads) and lies where the object is, a location's point where a
load goes down.

A pick-up is the chapter's sequence: switch the magnet off (one left energised after losing a
load grips nothing new) and wind the hook in (a recovery may have stopped a lift with the load
still gripped and cable out), look for the object from ``SEARCH_HEIGHT`` m above its point (the
hook camera sees a wide circle from there: a box that fell off the hook in flight lies metres
from where it was lost), hover ``HOVER_HEIGHT`` m above the object where the camera saw it,
align on the camera's view (a GPS fix is metres off), lower the hook to ``FIRST_CABLE`` m, align
again (the hover wanders a decimetre per second while the hook goes down: a single 5 m lowering
often ended beside the box), lower the hook as deep as the camera sees the object until it
rests on it (``ppcl_hook`` lower ends on a slack cable), attach (the magnet must hold that very
object), raise to ``CARRY_CABLE`` m, climb to ``DEPART_HEIGHT``. A
put-down hovers above the place, lowers until the load rests, releases, winds the hook in and
climbs likewise. Each step is one platform command
whose failure fails the node with the platform's reason (wrong box, nothing gripped, winch
stalled by an overweight load, load lost).
"""

from __future__ import annotations

import math
from collections.abc import Generator, Mapping
from types import MappingProxyType

from hdrc3_platform_server.hook_api import HookAction
from hdrc3_tst.executor import (
    SUCCEEDED,
    ActionContext,
    ActionExecutor,
    Progress,
    Status,
    failed,
)
from hdrc3_tst.executor_steps import airborne, finish, fly_to
from hdrc3_tst.platform_port import LET_GO, Sighting

Steps = Generator[None, None, Status]
HOVER_HEIGHT = 4.0
"""m above the ground where a load is picked up or put down."""
REACH = 1.5
"""m of cable paid out beyond the hover height: the hook reaches the ground with margin (the
lowering stops on a slack cable before that)."""
FIRST_CABLE = 3.0
"""m of cable of a pick-up's first lowering: the hook hangs a metre or two above the object, so
the last lowering after the second alignment takes a second or two."""
MAX_CABLE = 15.0
"""m of cable a pick-up pays out at most (the winch holds 20 m)."""
CARRY_CABLE = 1.0
"""m of cable a load hangs on in flight."""
DEPART_HEIGHT = 12.0
"""m above the ground an executor climbs back to when done: clear of the path planner's
6 m margin with a load hanging on ``CARRY_CABLE`` m of cable."""
APPROACH_SPEED = 2.0
"""m/s of the final approach over a load or place."""
ALIGNED = 0.25
"""m: the hook camera sees the object this close below the winch: lower (the magnet's 0.1 m
sphere lands on a 0.4 m box; the RMAX hovers to about +-0.2 m)."""
PICK_ATTEMPTS = 5
"""Lowerings onto an object before a pick-up gives up."""
MISSED = "gripped nothing"
"""Part of ppcl_hook's reason when the magnet landed beside the object."""
WRONG_OBJECT = "wrong object"
"""Part of ppcl_hook's reason when the magnet holds another object than the one asked for."""
CORRECTION_SPEED = 0.5
"""m/s of a correction flight over an object."""
SETTLE_S = 4.0
"""Mission seconds the aircraft hovers after a correction before the camera is asked again."""
SIGHT_TIMEOUT_S = 5.0
"""Mission seconds to wait for a new sighting of the object."""
CORRECT_ABOVE = 0.6
"""m: a larger offset is flown; a smaller one is waited out."""
ALIGN_S = 60.0
"""Mission seconds an alignment may take."""
SEARCH_HEIGHT = 24.0
"""m above the ground a pick-up looks for its object from: the hook camera (35 deg half angle,
30 m range) sees objects up to about 16 m to the side there."""


def over(ctx: ActionContext, place: str) -> Steps:
    """Take off if needed and hover ``HOVER_HEIGHT`` m above the place's point."""
    outcome = yield from airborne(ctx)
    if outcome.progress is not Progress.SUCCEEDED:
        return outcome
    (point,) = ctx.place(place)
    east, north = float(point[0]), float(point[1])
    up = ctx.frame.ground_up(east, north) + HOVER_HEIGHT
    return (yield from fly_to(ctx, (east, north, up), APPROACH_SPEED))


def search(ctx: ActionContext, place: str, tag: str) -> Steps:
    """Take off if needed, look for ``tag`` from above the place's point, hover low above it.

    From ``SEARCH_HEIGHT`` m above the point, the first new sighting of the object gives where
    it is (the aircraft's own estimate plus the camera's offset); the aircraft descends to
    ``HOVER_HEIGHT`` m above that, or above the point when the camera does not see it (the
    alignment then fails with that reason).
    """
    outcome = yield from airborne(ctx)
    if outcome.progress is not Progress.SUCCEEDED:
        return outcome
    (point,) = ctx.place(place)
    east, north = float(point[0]), float(point[1])
    high = ctx.frame.ground_up(east, north) + SEARCH_HEIGHT
    outcome = yield from fly_to(ctx, (east, north, high), APPROACH_SPEED)
    if outcome.progress is not Progress.SUCCEEDED:
        return outcome
    before = ctx.platform.seen(tag)
    seen = yield from _sighting(ctx, tag, before.time if before is not None else None)
    state = ctx.state()
    if seen is not None and state is not None:
        east, north = state.east + seen.offset[0], state.north + seen.offset[1]
    up = ctx.frame.ground_up(east, north) + HOVER_HEIGHT
    return (yield from fly_to(ctx, (east, north, up), APPROACH_SPEED))


def _sighting(
    ctx: ActionContext, tag: str, after: float | None
) -> Generator[None, None, Sighting | None]:
    """The first sighting of ``tag`` newer than ``after`` (None: not seen within the timeout)."""
    deadline = ctx.now + SIGHT_TIMEOUT_S
    while True:
        seen = ctx.platform.seen(tag)
        if seen is not None and (after is None or seen.time > after):
            return seen
        if ctx.now > deadline:
            return None
        yield


def align(ctx: ActionContext, tag: str, fresh: bool = False) -> Steps:
    """Hover the winch over the object ``tag`` on the hook camera's offsets.

    ``fresh``: start from a sighting newer than the latest one (not one seen before a lowering).

    The flight to the object's point ends metres off (GPS): an offset over ``CORRECT_ABOVE`` is
    flown (then the aircraft hovers ``SETTLE_S`` s); a smaller one is waited out, since the
    hover wanders a few decimetres around its set-point and passes over the object. Done when
    a sighting is within ``ALIGNED``; failed after ``ALIGN_S`` s.
    """
    deadline = ctx.now + ALIGN_S
    latest = ctx.platform.seen(tag) if fresh else None
    after: float | None = latest.time if latest is not None else None
    miss = math.inf
    while ctx.now <= deadline:
        seen = yield from _sighting(ctx, tag, after)
        if seen is None:
            return failed(f"the hook camera does not see {tag}")
        after = seen.time
        de, dn, _ = seen.offset
        miss = math.hypot(de, dn)
        if miss <= ALIGNED:
            return SUCCEEDED
        state = ctx.state()
        if miss > CORRECT_ABOVE and state is not None:
            target = (state.east + de, state.north + dn, state.up)
            outcome = yield from fly_to(ctx, target, CORRECTION_SPEED)
            if outcome.progress is not Progress.SUCCEEDED:
                return outcome
            settled = ctx.now + SETTLE_S
            while ctx.now < settled:
                yield
            latest = ctx.platform.seen(tag)
            after = latest.time if latest is not None else after
    return failed(f"could not hover over {tag}: still {miss:.2f} m off after {ALIGN_S:g} s")


def depart(ctx: ActionContext, place: str) -> Steps:
    """Climb straight up to ``DEPART_HEIGHT`` m above the place's ground."""
    (point,) = ctx.place(place)
    east, north = float(point[0]), float(point[1])
    state = ctx.state()
    if state is not None:
        east, north = state.east, state.north
    up = ctx.frame.ground_up(east, north) + DEPART_HEIGHT
    return (yield from fly_to(ctx, (east, north, up), APPROACH_SPEED))


def lower_onto(ctx: ActionContext, tag: str) -> Steps:
    """Lower the hook onto the object: ``REACH`` m beyond its depth below the winch.

    The depth is the hook camera's latest view of the object (at least ``HOVER_HEIGHT``): the
    hover holds the estimated altitude, which drifts by metres, so a fixed cable length can
    end above the object.
    """
    seen = ctx.platform.seen(tag)
    depth = max(-seen.offset[2], HOVER_HEIGHT) if seen is not None else HOVER_HEIGHT
    return (yield from hook(ctx, HookAction.LOWER, min(depth + REACH, MAX_CABLE)))


def hook(ctx: ActionContext, action: HookAction, length: float = 0.0, tag: str = "") -> Steps:
    """One ppcl_hook command to its end."""
    return (yield from finish(ctx, ctx.hook(action, length, tag)))


def pick_up(ctx: ActionContext, place: str, crowded: bool = False) -> Steps:
    """Find the object of point ``place``, hover over it, lower, attach it (by its tag), raise.

    A lowering that lands the magnet beside the object (attach: nothing gripped) is tried again
    from the alignment, up to ``PICK_ATTEMPTS`` times. ``crowded``: other objects stand next to
    it (a carrier's boxes around its lifting plate, a box among the others on a carrier), so a
    magnet that gripped another object landed beside it: it lets go and tries again too.
    """
    tag = ctx.name(place)
    for step in (
        *(hook(ctx, action, length) for action, length in LET_GO),
        search(ctx, place, tag),
    ):
        # magnet off and hook wound in first: an electromagnet left energised after losing a
        # load grips nothing new, and one still holding a load that did not lift (a recovery
        # stopped the raise with cable out) must not fly it, nor trail the cable
        outcome = yield from step
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
    for _ in range(PICK_ATTEMPTS):
        # generators: each step sends its command only when it runs
        for step in (
            align(ctx, tag),
            hook(ctx, HookAction.LOWER, FIRST_CABLE),
            align(ctx, tag, fresh=True),
            lower_onto(ctx, tag),
            hook(ctx, HookAction.ATTACH, 0.0, tag),
        ):
            outcome = yield from step
            if outcome.progress is not Progress.SUCCEEDED:
                break
        if outcome.progress is Progress.SUCCEEDED:
            outcome = yield from hook(ctx, HookAction.RAISE, CARRY_CABLE)
            if outcome.progress is not Progress.SUCCEEDED:
                return outcome
            return (yield from depart(ctx, place))
        beside = crowded and WRONG_OBJECT in outcome.reason
        if MISSED not in outcome.reason and not beside:
            return outcome
        if beside:
            released = yield from hook(ctx, HookAction.RELEASE)
            if released.progress is not Progress.SUCCEEDED:
                return released
        wound = yield from hook(ctx, HookAction.RAISE, 0.0)
        if wound.progress is not Progress.SUCCEEDED:
            return wound
    return outcome


def put_down(ctx: ActionContext, place: str) -> Steps:
    """Hover over point ``place``, lower the load until it rests, release, wind in."""
    for step in (
        over(ctx, place),
        hook(ctx, HookAction.LOWER, HOVER_HEIGHT + REACH),
        hook(ctx, HookAction.RELEASE),
        hook(ctx, HookAction.RAISE, 0.0),
        depart(ctx, place),
    ):
        outcome = yield from step
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
    return SUCCEEDED


class PickUpBox(ActionExecutor):
    """``pick-up-box(box)``: the box at its point (a depot) onto the hook."""

    def run(self, ctx: ActionContext) -> Steps:
        """Pick up the box."""
        return (yield from pick_up(ctx, "box"))


class TakeFromCarrier(ActionExecutor):
    """``take-from-carrier(box)``: a box off a carrier (its point: its place on the carrier)."""

    def run(self, ctx: ActionContext) -> Steps:
        """Pick up the box from the carrier (among its other boxes, on the carrier)."""
        return (yield from pick_up(ctx, "box", crowded=True))


class AttachCarrier(ActionExecutor):
    """``attach-carrier(carrier)``: the carrier by its central lifting plate."""

    def run(self, ctx: ActionContext) -> Steps:
        """Pick up the carrier (its boxes may stand around the lifting plate)."""
        return (yield from pick_up(ctx, "carrier", crowded=True))


class DropBox(ActionExecutor):
    """``drop-box(box, place)``: the held box put down on the ground at the place."""

    def run(self, ctx: ActionContext) -> Steps:
        """Put the box down."""
        return (yield from put_down(ctx, "place"))


class PutOnCarrier(ActionExecutor):
    """``put-on-carrier(box, place)``: the held box put down at its place on a carrier."""

    def run(self, ctx: ActionContext) -> Steps:
        """Put the box on the carrier."""
        return (yield from put_down(ctx, "place"))


class DetachCarrier(ActionExecutor):
    """``detach-carrier(carrier, place)``: the held carrier put down at the place."""

    def run(self, ctx: ActionContext) -> Steps:
        """Put the carrier down."""
        return (yield from put_down(ctx, "place"))


PAYLOAD_EXECUTORS: Mapping[str, type[ActionExecutor]] = MappingProxyType(
    {
        "pick-up-box": PickUpBox,
        "drop-box": DropBox,
        "put-on-carrier": PutOnCarrier,
        "take-from-carrier": TakeFromCarrier,
        "attach-carrier": AttachCarrier,
        "detach-carrier": DetachCarrier,
    }
)
"""The delivery executors by action name (= the UAV logistics operators; a test checks)."""
