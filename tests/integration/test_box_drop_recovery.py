"""A box lost in flight is detected, recovered from and delivered (issue 15, chapter 9.3).

``hdrc3 tst run examples/tst/delivery_box_drop.tst --launch --fault uav0:hook:release@fly-to#2+10``
flies the whole chain (world_sim with the MuJoCo payload, control_kernel, platform_server,
tst_manager, task_planner, path_planner, execution_monitor): the goal node is planned by
TALplanner (fly-to, pick-up-box, fly-to, drop-box); ten seconds into the carrying flight the
hook lets go of box1. Checked from the recording:

* the execution monitor's ``box_held`` formula (default.monitors, Example 9.4 over the hook's
  carrying sensor) is violated within one state period and one sensor period of the first
  sensor reading without the box, and the violation names the recovery operator ``box-lost``;
* the tst_manager suspends the flight, the aircraft hovers (PFC in HOVER after the violation),
  the operator puts box1 where the aircraft is, TALplanner replans (recorded ``RecoveryEvent``s
  with the new plan), and the new plan picks box1 up again and delivers it: the mission
  succeeds and box1 rests at the west field.

Decisions come from sensors only: the violation from ``sensors/carrying``, the box's new place
from the aircraft's own state estimate and the hook camera.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from hdrc3_deliberative.monitor_spec import DEFAULT_SPEC, MonitorSpecParser
from sim.node import PAYLOAD_EVERY
from sim.world_sim import TICK_RATE_HZ
from tests.integration.flight_runs import SEED

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"
FAULT = "uav0:hook:release@fly-to#2+10"
STATE_PERIOD_MS = MonitorSpecParser().parse_file(DEFAULT_SPEC).settings.period_ms
"""default.monitors' state period."""
SENSOR_PERIOD_MS = PAYLOAD_EVERY * 1000 // TICK_RATE_HZ
"""The carrying sensor's period."""
PUT_DOWN_WITHIN = 4.0
"""m of the west field's point: the drop hovers there on GPS (metres of error)."""


@pytest.mark.timeout(1500)
def test_a_box_lost_in_flight_is_picked_up_again_and_delivered(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> None:
    from hdrc3.recovery_record import read_lost_load, stamp_ms
    from hdrc3_interfaces.msg import PfcState, RecoveryEvent
    from sim.world_loader import load_world

    out = tmp_path / "run"
    run = hdrc3_cli(
        "tst", "run", str(EXAMPLES / "delivery_box_drop.tst"), "--launch", "--out", str(out),
        "--domain-id", str(ros_domain), "--mission", "drop", "--seed", SEED, "--fault", FAULT,
    )  # fmt: skip
    code = run.finish(timeout=1400.0)
    text = "\n".join(run.lines)
    assert code == 0, text
    assert "mission drop succeeded" in text
    assert f"fault: injecting {FAULT}" in text

    record = read_lost_load(out / "run.mcap", "uav0", "box1")
    lost = record.violation
    assert lost is not None, "no violation naming box1 recorded"
    assert lost.monitor_id.startswith("box_held@")
    assert (lost.action, lost.recovery, lost.emergency_brake) == ("pick-up-box", "box-lost", True)
    assert dict(zip(lost.argument_names, lost.argument_values, strict=True)) == {"box": "box1"}
    # detected within the formula's bound (an unbounded until: 0) plus one state period and the
    # carrying sensor's period, after the ground truth shows the box off the hook
    assert record.detection_ms is not None and record.sensor_ms is not None
    print(f"box_held violated {record.detection_ms} ms after the release (ground truth)")
    assert 0 <= record.detection_ms <= STATE_PERIOD_MS + SENSOR_PERIOD_MS
    assert stamp_ms(lost.header.stamp) >= record.sensor_ms  # from the sensor, not before it

    e = RecoveryEvent
    assert [ev.step for ev in record.recovery] == [
        e.STEP_SUSPENDED,
        e.STEP_BRAKED,
        e.STEP_HOVERING,
        e.STEP_OPERATOR_APPLIED,
        e.STEP_REPLANNED,
    ]
    assert list(record.recovery[3].changes) == ["at(box1, recover_uav0_1)"]
    assert [a.split()[0] for a in record.recovery[4].plan] == ["pick-up-box", "fly-to", "drop-box"]
    # braked, then hovered until the new plan
    assert PfcState.MODE_BRAKING in record.modes and record.modes[-1] == PfcState.MODE_HOVER

    # the remaining delivery completed: box1 rests at the west field
    world = load_world("revinge")
    field = world.place("west_field")
    box = record.final
    assert box is not None and box.held_by == ""
    assert math.hypot(box.east - field.east, box.north - field.north) < PUT_DOWN_WITHIN
