"""Algorithm 2 semantics, table-driven: each case is a model, a script of macro steps, and the
expected (event, transition) sequence and final configuration."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hdrc3_hcsm.conditions import ConditionTable
from hdrc3_hcsm.event import PostStatus
from hdrc3_hcsm.interpreter import FaultKind, Interpreter, InterpreterConfig, StepStatus
from hdrc3_hcsm.loader import load_file, load_text
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.trace import TraceRecorder, fired_ids

HEAD = "model T on PFC; computers PFC, DRC;\n"


@dataclass(frozen=True)
class Step:
    post: tuple[tuple[str, bytes | None], ...] = ()
    conds: dict[str, bool] = field(default_factory=dict)


@dataclass(frozen=True)
class Case:
    name: str
    model: str
    steps: tuple[Step, ...]
    fired: list[tuple[str, str]]
    config: tuple[str, ...]


def make(text: str, **kwargs: object) -> tuple[Interpreter, ConditionTable, TraceRecorder]:
    model = compile_model(load_text(HEAD + text, "case.hcsm"))
    conds = ConditionTable(model.conditions)
    trace = TraceRecorder()
    interp = Interpreter(model, conds.callables(), trace=trace, **kwargs)  # type: ignore[arg-type]
    return interp, conds, trace


NESTED = """
event E-EV = 1; event F-EV = 2;
condition Outer-CO;
automaton A Outer {
    init Idle-ST; super Busy-ST = Inner; state Done-ST;
    A.1: Idle-ST -> Busy-ST on pulse;
    A.2: Busy-ST -> Done-ST on E-EV [Outer-CO];
    A.3: Busy-ST -> Idle-ST on exit;
}
automaton B Inner {
    init I0-ST; state I1-ST; exit I2-ST;
    B.1: I0-ST -> I1-ST on E-EV;
    B.2: I1-ST -> I2-ST on F-EV;
}
root Outer;
"""

TWO_REGIONS = """
event E-EV = 1; event G-EV = 2; event H-EV = 3;
automaton A Left { init L0-ST; state L1-ST;
    A.1: L0-ST -> L1-ST on E-EV / SEND G-EV; }
automaton B Right { init R0-ST; state R1-ST; state R2-ST;
    B.1: R0-ST -> R1-ST on E-EV / SEND H-EV;
    B.2: R1-ST -> R2-ST on G-EV; }
automaton C Watch { init W0-ST; state W1-ST;
    C.1: W0-ST -> W1-ST on H-EV; }
root Left | Right | Watch;
"""

EXIT_BOTH = """
event E-EV = 1; event F-EV = 2;
automaton A Parent { init P0-ST; super Work-ST = Pair; state P2-ST;
    A.1: P0-ST -> Work-ST on pulse;
    A.2: Work-ST -> P2-ST on exit; }
automaton B One { init O0-ST; exit O1-ST; B.1: O0-ST -> O1-ST on E-EV; }
automaton C Two { init T0-ST; exit T1-ST; C.1: T0-ST -> T1-ST on F-EV; }
container Pair = One | Two;
root Parent;
"""

GUARDS = """
event E-EV = 1;
condition X-CO, Y-CO;
automaton A G { init S-ST; state T1-ST; state T2-ST; state T3-ST;
    A.1: S-ST -> T1-ST on E-EV [X-CO AND NOT Y-CO];
    A.2: S-ST -> T2-ST on E-EV [X-CO OR Y-CO];
    A.3: S-ST -> T3-ST on E-EV [NOT (X-CO OR Y-CO)]; }
root G;
"""

ORDER = """
event E-EV = 1; event P-EV = 2;
automaton A M { init S-ST;
    A.1: S-ST -> S-ST on pulse / SEND P-EV;
    A.2: S-ST -> S-ST on P-EV;
    A.3: S-ST -> S-ST on E-EV; }
root M;
"""

REUSE = """
event E-EV = 1;
automaton A Top { init T0-ST; super X-ST = Cell | Cell; super Y-ST = Cell;
    A.1: T0-ST -> X-ST on pulse;
    A.2: X-ST -> Y-ST on exit; }
automaton B Cell { init C0-ST; exit C1-ST; B.1: C0-ST -> C1-ST on E-EV; }
root Top;
"""

STALE_EXIT = """
event E-EV = 1; event X-EV = 2; event Y-EV = 3;
automaton A Trigger { init T0-ST; state T1-ST; A.1: T0-ST -> T1-ST on E-EV / SEND X-EV; }
automaton B Grand { init G0-ST; super S-ST = Parent; state G2-ST;
    B.1: G0-ST -> S-ST on pulse;
    B.2: S-ST -> G2-ST on X-EV; }
automaton C Parent { init P0-ST; super Q-ST = Child; state P2-ST;
    C.1: P0-ST -> Q-ST on pulse;
    C.2: Q-ST -> P2-ST on exit / SEND Y-EV; }
automaton D Child { init C0-ST; exit C1-ST; D.1: C0-ST -> C1-ST on E-EV; }
automaton E Watch { init W0-ST; state W1-ST; E.1: W0-ST -> W1-ST on Y-EV; }
root Trigger | Grand | Watch;
"""

CASES = [
    Case(
        "child reacts when the parent has no enabled transition",
        NESTED,
        (Step(), Step(post=(("E-EV", None),))),
        [("pulse", "A.1"), ("E-EV", "B.1")],
        ("Outer:Busy-ST", "Outer/Busy-ST/Inner:I1-ST"),
    ),
    Case(
        "parent has priority over its children and aborts them",
        NESTED,
        (Step(), Step(post=(("E-EV", None),), conds={"Outer-CO": True})),
        [("pulse", "A.1"), ("E-EV", "A.2")],
        ("Outer:Done-ST",),
    ),
    Case(
        "exit event goes to the parent superstate; re-entry restarts the child",
        NESTED,
        (Step(), Step(post=(("E-EV", None), ("F-EV", None))), Step()),
        [("pulse", "A.1"), ("E-EV", "B.1"), ("F-EV", "B.2"), ("exit", "A.3"), ("pulse", "A.1")],
        ("Outer:Busy-ST", "Outer/Busy-ST/Inner:I0-ST"),
    ),
    Case(
        "concurrent regions see the same event in region order; sends queue behind it",
        TWO_REGIONS,
        (Step(post=(("E-EV", None),)),),
        [("E-EV", "A.1"), ("E-EV", "B.1"), ("G-EV", "B.2"), ("H-EV", "C.1")],
        ("Left:L1-ST", "Right:R2-ST", "Watch:W1-ST"),
    ),
    Case(
        "exit event only when every region of the container has exited",
        EXIT_BOTH,
        (Step(), Step(post=(("E-EV", None),)), Step(post=(("F-EV", None),))),
        [("pulse", "A.1"), ("E-EV", "B.1"), ("F-EV", "C.1"), ("exit", "A.2")],
        ("Parent:P2-ST",),
    ),
    Case(
        "exit event of an aborted parent is dropped",
        STALE_EXIT,
        (Step(), Step(), Step(post=(("E-EV", None),))),
        [("pulse", "B.1"), ("pulse", "C.1"), ("E-EV", "A.1"), ("E-EV", "D.1"), ("X-EV", "B.2")],
        ("Trigger:T1-ST", "Grand:G2-ST", "Watch:W0-ST"),
    ),
    Case(
        "guard AND NOT",
        GUARDS,
        (Step(post=(("E-EV", None),), conds={"X-CO": True}),),
        [("E-EV", "A.1")],
        ("G:T1-ST",),
    ),
    Case(
        "guard OR (first enabled transition in file order wins)",
        GUARDS,
        (Step(post=(("E-EV", None),), conds={"X-CO": True, "Y-CO": True}),),
        [("E-EV", "A.2")],
        ("G:T2-ST",),
    ),
    Case(
        "guard NOT (...)",
        GUARDS,
        (Step(post=(("E-EV", None),)),),
        [("E-EV", "A.3")],
        ("G:T3-ST",),
    ),
    Case(
        "pulse first, external event appended before the pulse's internal events",
        ORDER,
        (Step(post=(("E-EV", None), ("E-EV", None))),),
        [("pulse", "A.1"), ("E-EV", "A.3"), ("P-EV", "A.2"), ("E-EV", "A.3")],
        ("M:S-ST",),
    ),
    Case(
        "reusable automaton instantiated in two regions and in two superstates",
        REUSE,
        (Step(), Step(post=(("E-EV", None),)), Step()),
        [("pulse", "A.1"), ("E-EV", "B.1"), ("E-EV", "B.1"), ("exit", "A.2")],
        ("Top:Y-ST", "Top/Y-ST/Cell:C0-ST"),
    ),
]


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_semantics(case: Case) -> None:
    interp, conds, trace = make(case.model)
    for i, step in enumerate(case.steps):
        for name, value in step.conds.items():
            conds.set(name, value)
        for name, data in step.post:
            assert interp.post_external(name, data) is PostStatus.ACCEPTED
        result = interp.execute(float(i))
        assert result.status is StepStatus.OK
        assert result.faults == ()
    assert fired_ids(trace) == case.fired
    assert interp.configuration() == case.config


MEMORY = """
event In-EV = 1; event Echo-EV = 2; event Out-EV = 3 to DRC;
flag Got-AC;
slot Keep-DO[8]; slot Small-DO[2];
automaton A Mem { init S0-ST; state S1-ST; state S2-ST; state S3-ST;
    A.1: S0-ST -> S1-ST on In-EV / PUT Keep-DO, SET Got-AC, SEND Echo-EV data Keep-DO;
    A.2: S1-ST -> S2-ST on Echo-EV / GET Keep-DO, SEND Out-EV data cache to DRC;
    A.3: S2-ST -> S3-ST on In-EV / SET Got-AC, PUT Small-DO; }
root Mem;
"""


def test_cache_get_put_and_remote_send() -> None:
    interp, _, trace = make(MEMORY)
    interp.post_external("In-EV", b"abc")
    result = interp.execute(0.0)
    assert fired_ids(trace) == [("In-EV", "A.1"), ("Echo-EV", "A.2")]
    assert interp.memory.read("Keep-DO") == b"abc"
    assert interp.memory.cache == b"abc"
    assert interp.flags.active() == {"Got-AC"}
    [out] = interp.take_outbox()
    assert (out.name, out.event_id, out.data, out.source, out.target) == (
        "Out-EV",
        3,
        b"abc",
        "PFC",
        "DRC",
    )
    assert result.transitions == 2 and result.micro_steps == 3


def test_failed_action_leaves_state_and_effects_untouched() -> None:
    interp, _, trace = make(MEMORY)
    interp.post_external("In-EV", b"abc")
    interp.execute(0.0)
    interp.flags.clear()
    interp.post_external("In-EV", b"too-long")  # cache no longer fits Small-DO[2]
    result = interp.execute(1.0)
    assert [f.kind for f in result.faults] == [FaultKind.ACTION_FAILED]
    assert result.faults[0].tid == "A.3"
    assert interp.configuration() == ("Mem:S2-ST",)
    assert interp.flags.active() == frozenset()  # SET before the failing PUT was not committed
    assert interp.memory.read("Small-DO") == b""
    assert trace.records()[-1].faults and interp.stats.faults == 1


def test_guard_exception_is_a_fault_not_a_crash() -> None:
    model = compile_model(load_text(HEAD + GUARDS, "g.hcsm"))

    def broken() -> bool:
        raise RuntimeError("sensor gone")

    interp = Interpreter(model, {"X-CO": broken, "Y-CO": lambda: True})
    interp.post_external("E-EV")
    result = interp.execute(0.0)
    assert [f.kind for f in result.faults] == [FaultKind.GUARD_FAILED] * 3
    assert interp.configuration() == ("G:S-ST",)


PING_PONG = """
event Ping-EV = 1; event Pong-EV = 2;
automaton A P { init S-ST; A.1: S-ST -> S-ST on Ping-EV / SEND Pong-EV; }
automaton B Q { init S-ST; B.1: S-ST -> S-ST on Pong-EV / SEND Ping-EV; }
root P | Q;
"""


def test_livelock_is_bounded_and_reported() -> None:
    interp, _, _ = make(PING_PONG, config=InterpreterConfig(max_micro_steps=50))
    interp.post_external("Ping-EV")
    result = interp.execute(0.0)
    assert result.status is StepStatus.LIVELOCK
    assert result.micro_steps == 50
    assert interp.stats.livelocks == 1
    assert interp.execute(1.0).status is StepStatus.OK  # the internal queue was dropped


@pytest.mark.parametrize(
    ("name", "status"),
    [("Nope-EV", PostStatus.UNKNOWN_EVENT), ("pulse", PostStatus.UNKNOWN_EVENT)],
)
def test_unknown_external_event_is_counted(name: str, status: PostStatus) -> None:
    interp, _, _ = make(PING_PONG)
    assert interp.post_external(name) is status
    assert interp.stats.unknown_events == 1
    assert interp.execute(0.0).status is StepStatus.OK


def test_event_data_larger_than_the_cache_is_rejected() -> None:
    from hdrc3_hcsm.memory import MemoryBank

    model = compile_model(load_text(HEAD + PING_PONG, "p.hcsm"))
    interp = Interpreter(model, {}, memory=MemoryBank(model.slots, cache_size=4))
    assert interp.post_external("Ping-EV", b"12345") is PostStatus.TOO_LARGE
    assert interp.post_external("Ping-EV", b"1234") is PostStatus.ACCEPTED


def test_external_queue_is_bounded() -> None:
    interp, _, _ = make(PING_PONG, config=InterpreterConfig(external_queue_size=2))
    statuses = [interp.post_external("Ping-EV") for _ in range(3)]
    assert statuses[-1] is PostStatus.QUEUE_FULL
    assert interp.pending_external() == 2


def test_synchrony_events_posted_during_a_step_wait() -> None:
    model = compile_model(load_text(HEAD + GUARDS, "g.hcsm"))
    interp: Interpreter

    def posting() -> bool:
        interp.post_external("E-EV")
        return False

    interp = Interpreter(model, {"X-CO": posting, "Y-CO": lambda: False})
    interp.post_external("E-EV")
    result = interp.execute(0.0)
    assert result.external_events == 1
    assert interp.pending_external() >= 1


FINISH = """
event E-EV = 1;
automaton A M { init S-ST; exit X-ST; A.1: S-ST -> X-ST on E-EV; }
root M;
"""


def test_root_reaching_exit_finishes() -> None:
    interp, _, _ = make(FINISH)
    interp.post_external("E-EV")
    assert interp.execute(0.0).status is StepStatus.FINISHED


def test_reload_keeps_states_that_still_exist() -> None:
    interp, _, _ = make(NESTED)
    interp.execute(0.0)
    interp.post_external("E-EV")
    interp.execute(1.0)
    changed = NESTED.replace("state Done-ST;", "state Done-ST; state Extra-ST;").replace(
        "A.3: Busy-ST -> Idle-ST on exit;",
        "A.3: Busy-ST -> Idle-ST on exit; A.4: Done-ST -> Extra-ST on F-EV;",
    )
    # New events come first, so every index changes; the queued F-EV must survive by name.
    changed = changed.replace("event E-EV = 1;", "event N-EV = 9; event E-EV = 1;")
    interp.post_external("F-EV")
    interp.reload(compile_model(load_text(HEAD + changed, "v2.hcsm")))
    assert interp.configuration() == ("Outer:Busy-ST", "Outer/Busy-ST/Inner:I1-ST")
    assert interp.model.source.file == "v2.hcsm"
    interp.execute(2.0)
    assert interp.configuration() == ("Outer:Idle-ST",)  # F-EV -> B.2 -> exit -> A.3


def test_reload_that_needs_more_slots_is_refused_without_a_new_bank() -> None:
    from hdrc3_hcsm.errors import BindingError
    from hdrc3_hcsm.memory import MemoryBank

    interp, _, _ = make(NESTED)
    bigger = compile_model(load_text(HEAD + "slot New-DO[4];" + NESTED, "v2.hcsm"))
    with pytest.raises(BindingError, match="New-DO"):
        interp.reload(bigger)
    assert interp.model.source.file == "case.hcsm"
    interp.reload(bigger, memory=MemoryBank(bigger.slots))
    assert interp.memory.read("New-DO") == b""


CONDS = {
    "Braking-Done-CO",
    "Hover-Stable-CO",
    "Single-Segment-CO",
    "Traj-Arrived-CO",
    "Ctrl-Ready-CO",
    "Ctrl-Failed-CO",
    "Ctrl-Halted-CO",
}
PFC_EVENTS = ["Traj3D-EV", "Ctrl-Ok-EV", "Ctrl-Stop-EV", "Ctrl-Stopped-EV", "Nope-EV", "exit"]


@given(
    st.lists(
        st.tuples(
            st.lists(st.sampled_from(PFC_EVENTS), max_size=4),
            st.dictionaries(st.sampled_from(sorted(CONDS)), st.booleans()),
        ),
        max_size=25,
    )
)
def test_random_event_storms_keep_the_pfc_model_consistent(
    script: list[tuple[list[str], dict[str, bool]]],
) -> None:
    from hdrc3_hcsm.models import model_path

    model = compile_model(load_file(model_path("pfc_modes.hcsm")))
    conds = ConditionTable(model.conditions)
    interp = Interpreter(model, conds.callables())
    for k, (events, values) in enumerate(script):
        for name, value in values.items():
            conds.set(name, value)
        for name in events:
            interp.post_external(name, b"x")
        result = interp.execute(k * 0.02)
        assert result.status is StepStatus.OK
        assert result.micro_steps <= interp.config.max_micro_steps
        config = interp.configuration()
        in_traj3d = "Mode-Switch:Traj3D-ST" in config
        assert in_traj3d == any(c.startswith("Mode-Switch/Traj3D-ST/Traj3D:") for c in config)
        assert len(config) == 2 + in_traj3d
        interp.flags.clear()


UNCONSUMED = """
event Go-EV = 1; event Stop-EV = 2;
condition Ready-CO;
automaton A Run { init Idle-ST; state Busy-ST;
    A.1: Idle-ST -> Busy-ST on Go-EV [Ready-CO];
    A.2: Busy-ST -> Idle-ST on Stop-EV; }
root Run;
"""


@pytest.mark.parametrize(
    ("ready", "posts", "unconsumed"),
    [
        (True, ("Go-EV",), ()),  # taken
        (False, ("Go-EV",), ("Go-EV",)),  # a transition on it, guard false
        (True, ("Stop-EV",), ("Stop-EV",)),  # no transition on it from Idle-ST
        (True, ("Go-EV", "Go-EV", "Stop-EV"), ("Go-EV",)),  # in order, per occurrence
    ],
)
def test_step_reports_external_events_that_made_no_transition(
    ready: bool, posts: tuple[str, ...], unconsumed: tuple[str, ...]
) -> None:
    interp, conds, _ = make(UNCONSUMED)
    conds.set("Ready-CO", ready)
    for name in posts:
        assert interp.post_external(name) is PostStatus.ACCEPTED
    assert interp.execute(0.0).unconsumed == unconsumed
