"""Executor steps: a flight the PFC refuses while it settles into a hover is sent again."""

from __future__ import annotations

import pytest

from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.executor import ActionContext, ActionExecutor, Progress, Status, Stepper
from hdrc3_tst.executor_steps import SETTLE_RETRY_S, SETTLE_WAIT_S, Steps, fly_to
from hdrc3_tst.fake_platform import FakePlatform
from hdrc3_tst.platform_port import PlatformState

FLYING = PlatformState(0.0, 0.0, 30.0, on_ground=False, autonomous=True)
SETTLING = "FAILED rejected by the PFC: Traj3D-Flyto-EV not accepted in Mode-Switch:Stabilizing-ST"


class FlyNorth(ActionExecutor):
    def run(self, ctx: ActionContext) -> Steps:
        return (yield from fly_to(ctx, (0.0, 50.0, 30.0), 5.0))


def _stepper() -> tuple[FakePlatform, Stepper]:
    platform = FakePlatform(sample=FLYING)
    ctx = ActionContext(
        "n", "uav0", ACTIONS["hover"], {}, {}, platform, frame_from_world("revinge"), 0.0
    )
    return platform, Stepper(FlyNorth(), ctx)


@pytest.mark.parametrize(
    ("reason", "sent", "progress"),
    [
        (SETTLING, 2, Progress.RUNNING),  # sent again a second later
        (SETTLING.replace("Stabilizing-ST", "Braking-ST"), 2, Progress.RUNNING),
        ("FAILED rejected by the PFC: Traj3D-Flyto-EV not accepted in Mode-Switch:Landing-ST",
         1, Progress.FAILED),
        ("FAILED no path", 1, Progress.FAILED),
    ],
)  # fmt: skip
def test_a_flight_refused_while_the_pfc_settles_is_sent_again(
    reason: str, sent: int, progress: Progress
) -> None:
    platform, stepper = _stepper()
    stepper.step(0.0)
    platform.complete(platform.sent[-1], ok=False, reason=reason)
    outcome = stepper.step(0.1)
    if outcome.progress is Progress.RUNNING:
        outcome = stepper.step(0.2 + SETTLE_RETRY_S)
    assert outcome.progress is progress
    assert len(platform.sent) == sent
    assert all(c.command is FclCommand.TRAJ3D_FLYTO for c in platform.sent)


def test_a_pfc_that_never_settles_fails_the_flight_after_the_wait() -> None:
    platform, stepper = _stepper()
    now = 0.0
    outcome = stepper.step(now)
    while outcome.progress is Progress.RUNNING and now < 2 * SETTLE_WAIT_S:
        if not platform.sent[-1].state.ended:
            platform.complete(platform.sent[-1], ok=False, reason=SETTLING)
        now += 0.5
        outcome = stepper.step(now)
    assert outcome == Status(Progress.FAILED, f"fcl_traj3d_flyto: {SETTLING}")
    assert SETTLE_WAIT_S <= now <= SETTLE_WAIT_S + 2 * SETTLE_RETRY_S
