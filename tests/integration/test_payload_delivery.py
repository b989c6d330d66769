"""A box delivered on the real node chain (issue 15): pick up at the supply depot, put down afar.

``hdrc3 tst run examples/tst/delivery_box.tst --launch`` flies uav0 (world_sim with the MuJoCo
payload, control_kernel, platform_server with ppcl_hook, tst_manager with the delivery
executors): to the depot, pick-up-box box1 (hook camera alignment, lower, attach, raise), carry
it to the west field, drop-box there. Checked from the recording: the mission succeeded, the
carrying sensor reported box1 held on the way, every ppcl_hook command ended exactly once, the
execution flags of both delivery nodes went up and down, and the last /world_sim/objects message
has box1 resting on the ground at the west field, no longer held.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.integration.flight_runs import SEED, recorded

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"
PUT_DOWN_WITHIN = 4.0
"""m of the west field's point: the drop hovers there on GPS (metres of error)."""


@pytest.mark.timeout(1200)
def test_a_box_is_picked_up_at_the_depot_and_put_down_at_the_field(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> None:
    from sim.world_loader import load_world

    out = tmp_path / "run"
    run = hdrc3_cli(
        "tst", "run", str(EXAMPLES / "delivery_box.tst"), "--launch", "--world", "revinge",
        "--out", str(out), "--domain-id", str(ros_domain), "--mission", "deliver", "--seed", SEED,
    )  # fmt: skip
    code = run.finish(timeout=1100.0)
    text = "\n".join(run.lines)
    assert code == 0, text
    assert "mission deliver succeeded" in text

    messages = recorded(
        out / "run.mcap",
        "/world_sim/objects",
        "/uav0/sensors/carrying",
        "/uav0/platform_events",
        "/uav0/execution_flags",
    )
    held = [m.object_id for m in messages["/uav0/sensors/carrying"] if m.carrying]
    assert held and set(held) == {"box1"}
    hooks = [e for e in messages["/uav0/platform_events"] if e.command == "ppcl_hook"]
    ends = Counter(e.command_id for e in hooks if e.kind in (0, 1, 2))
    # 4 hook commands per node, 3 more per lowering that landed beside the box; each ends once
    assert len(ends) >= 8 and set(ends.values()) == {1}
    assert any(e.kind == 0 and e.reason == "box1" for e in hooks)  # attach: the magnet holds box1
    flags = {(f.node_id, f.executing) for f in messages["/uav0/execution_flags"]}
    assert {("pick", True), ("pick", False), ("put", True), ("put", False)} <= flags

    world = load_world("revinge")
    field = world.place("west_field")
    (box,) = [o for o in messages["/world_sim/objects"][-1].objects if o.id == "box1"]
    assert box.held_by == ""
    assert math.hypot(box.east - field.east, box.north - field.north) < PUT_DOWN_WITHIN
    assert box.up == pytest.approx(world.terrain.height(box.east, box.north), abs=0.05)
