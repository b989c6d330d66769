"""Random requests never crash the core, every answer is defined, no completion is lost."""

from __future__ import annotations

import math

from hypothesis import example, given
from hypothesis import strategies as st

from hdrc3_platform_server.codes import FclCode, FclCommand, PpclCode, PpclCommand, Resource
from hdrc3_platform_server.commands import FCL, PPCL
from hdrc3_platform_server.completion import TERMINAL
from hdrc3_platform_server.fakes import FakeRig
from hdrc3_platform_server.geo_frame import WorldFrame

FRAME = WorldFrame(55.70, 13.47, 95.0)
numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-200.0, 200.0),
    st.sampled_from([0.0, 0.5, 1.0, 13.47, 55.70, 95.0, 125.0, 8.0]),
)
fcl_step = st.tuples(
    st.just("fcl"), st.sampled_from(list(FclCommand)), st.lists(numbers, max_size=15), st.booleans()
)
ppcl_step = st.tuples(
    st.just("ppcl"), st.sampled_from(list(PpclCommand)), st.lists(numbers, max_size=5)
)
control_step = st.tuples(st.just("control"), st.integers(-1, 5), st.booleans())
run_step = st.tuples(st.just("run"), st.floats(0.0, 1.5))
steps = st.lists(st.one_of(fcl_step, ppcl_step, control_step, run_step), max_size=40)


@given(steps, st.booleans())
# Found by this test on random seeds: an infinite camera id reached int() (OverflowError).
@example([("ppcl", PpclCommand.IRIS, [math.inf])], False)
@example([("ppcl", PpclCommand.EXPOSURE, [math.inf])], False)
@example([("ppcl", PpclCommand.ZOOM, [math.inf])], True)
# A land accepted during an emergency brake replaced the brake, whose outcome was lost.
@example(
    [("fcl", FclCommand.EMERGENCY_BRAKE, [], False), ("fcl", FclCommand.LAND, [], True)], False
)
def test_random_requests(sequence: list[tuple[object, ...]], on_ground: bool) -> None:
    rig = FakeRig(FRAME, on_ground=on_ground)
    accepted: list[int] = []
    for step in sequence:
        kind = step[0]
        if kind == "run":
            rig.run(float(step[1]))  # type: ignore[arg-type]
        elif kind == "control":
            answer = rig.core.ppcl.control(int(step[1]), bool(step[2]), "fuzz")  # type: ignore[call-overload]
            assert answer.code in PpclCode
        elif kind == "fcl":
            command: FclCommand = step[1]  # type: ignore[assignment]
            raw: list[float] = list(step[2])  # type: ignore[call-overload]
            n = len(FCL[command].names)
            exact = (raw + [1.0] * n)[:n]
            a = rig.core.fcl.submit(command, exact if step[3] else raw, rig.t)
            assert a.code in FclCode and (a.command_id > 0) is (a.code is FclCode.OK)
            assert a.code is FclCode.OK or a.reason
            if a.code is FclCode.OK:
                accepted.append(a.command_id)
        else:
            pcommand: PpclCommand = step[1]  # type: ignore[assignment]
            n = len(PPCL[pcommand].names)
            pargs = (list(step[2]) + [0.0] * n)[:n]  # type: ignore[call-overload]
            p = rig.core.ppcl.submit(pcommand, pargs, rig.t)
            assert p.code in PpclCode and (p.code is PpclCode.OK or p.reason)
            if p.code is PpclCode.OK:
                accepted.append(p.command_id)
    rig.core.fcl.submit(FclCommand.CANCEL, (), rig.t)
    rig.run(3.0)
    for cid in accepted:
        terminal = [e for e in rig.log.of(cid) if e.kind in TERMINAL]
        assert len(terminal) == 1, (cid, rig.log.of(cid))
    for res in Resource:
        rig.core.ppcl.control(res, False, "fuzz")
