"""State synthesis: grid, policies for missing values, fusion, staleness, execution flags."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.monitor_states import StateSynthesizer, Step, SynthesizedState
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.policy import MissingHandling, Policy
from hdrc3_dyknow.sample import Sample

PERIOD, MAX_DELAY, STALE = 100, 200, 500


def rig(
    missing: MissingHandling = MissingHandling.LAST_VALUE,
) -> tuple[KnowledgeProcessHost, StateSynthesizer]:
    host = KnowledgeProcessHost()
    host.declare("alt", Policy(missing=missing))
    host.declare("alt2", Policy(missing=missing))
    synth = StateSynthesizer(host, PERIOD, MAX_DELAY, STALE)
    synth.start(0)
    synth.need({"altitude(uav0)": ("alt",)}, 0)
    return host, synth


def run(
    host: KnowledgeProcessHost, synth: StateSynthesizer, until: int, samples: dict[int, float]
) -> list[SynthesizedState]:
    states = []
    for now in range(0, until + 1, 20):
        if now in samples:
            host.publish("alt", Sample(now, now, samples[now]))
        host.advance(now)
        states.extend(synth.advance(now)[0])
    return states


def test_one_state_per_period_as_soon_as_the_stream_reaches_it() -> None:
    host, synth = rig()
    emitted: dict[int, int] = {}
    for now in range(0, 1001, 20):
        host.publish("alt", Sample(now, now, float(now)))
        host.advance(now)
        for state in synth.advance(now)[0]:
            emitted[state.time_ms] = now
    assert sorted(emitted) == list(range(0, 1001, PERIOD))
    # complete states go out at once, not after the maximum delay
    assert all(now == time for time, now in emitted.items())


def test_a_lagging_stream_holds_states_back_for_at_most_max_delay() -> None:
    host, synth = rig()
    host.publish("alt", Sample(0, 0, 1.0))
    host.advance(0)
    assert [s.time_ms for s in synth.advance(0)[0]] == [0]
    assert synth.advance(PERIOD + MAX_DELAY - 1)[0] == []
    (state,) = synth.advance(PERIOD + MAX_DELAY)[0]
    assert (state.time_ms, state.values["altitude(uav0)"]) == (PERIOD, 1.0)


@pytest.mark.parametrize(
    ("missing", "expected"),
    [
        # samples 0..200 climbing 1 m per 100 ms, then a 300 ms dropout: state 400 estimates
        (MissingHandling.LAST_VALUE, 2.0),
        (MissingHandling.EXTRAPOLATE, 4.0),
        (MissingHandling.DROP, None),
    ],
)
def test_the_policy_decides_missing_values(
    missing: MissingHandling, expected: float | None
) -> None:
    host, synth = rig(missing)
    samples = {0: 0.0, 100: 1.0, 200: 2.0, 500: 5.0}
    by_time = {s.time_ms: s for s in run(host, synth, 700, samples)}
    state = by_time[400]
    if expected is None:
        assert "altitude(uav0)" in state.missing and "altitude(uav0)" not in state.values
    else:
        assert state.values["altitude(uav0)"] == pytest.approx(expected)
    assert by_time[500].values["altitude(uav0)"] == 5.0


def test_a_stopped_stream_is_stale_missing_and_alarmed_once_then_resumes() -> None:
    host, synth = rig(MissingHandling.EXTRAPOLATE)
    changes = []
    states = []
    for now in range(0, 3001, 20):
        if now <= 1000 or now >= 2500:
            host.publish("alt", Sample(now, now, 10.0))
        host.advance(now)
        new_states, new_changes = synth.advance(now)
        states.extend(new_states)
        changes.extend(new_changes)
    stale, resumed = changes
    assert (stale.label, stale.stale, stale.last_sample_ms) == ("alt", True, 1000)
    assert stale.time_ms == 1000 + STALE + PERIOD  # first state more than STALE ms after
    assert (resumed.stale, resumed.time_ms) == (False, 2500)
    by_time = {s.time_ms: s for s in states}
    assert "altitude(uav0)" in by_time[2000].missing
    assert by_time[1500].values["altitude(uav0)"] == 10.0  # within STALE: extrapolated
    assert synth.stale_labels() == []


def test_a_stream_that_never_delivers_goes_stale_after_it_was_needed() -> None:
    host, synth = rig()
    changes = []
    for now in range(0, 1001, 50):
        host.advance(now)
        changes.extend(synth.advance(now)[1])
    assert [(c.label, c.stale, c.last_sample_ms) for c in changes] == [("alt", True, None)]


def test_matched_streams_are_fused_by_freshness() -> None:
    host, synth = rig()
    synth.need({"altitude(uav0)": ("alt", "alt2")}, 0)
    host.publish("alt", Sample(0, 0, 1.0))
    host.publish("alt2", Sample(50, 50, 2.0))
    host.publish("alt", Sample(100, 100, 3.0))
    host.publish("alt2", Sample(180, 180, 4.0))
    host.advance(180)
    states = {s.time_ms: s.values["altitude(uav0)"] for s in synth.advance(400)[0]}
    assert states == {0: 1.0, 100: 3.0, 200: 4.0}


@pytest.mark.parametrize(
    ("args", "holds"),
    [
        (("uav0",), True),
        (("uav0", "box1"), True),
        (("uav1", "box1"), False),  # another agent
        (("uav0", "box2"), False),  # another argument
        ((), False),
    ],
)
def test_execution_flags_take_a_subset_of_the_arguments(args: tuple[str, ...], holds: bool) -> None:
    step = Step("n1", "pickup-box", "uav0", (("box", "box1"), ("depot", "d1")), 0)
    assert step.flags("pickup-box", args) is holds
    assert not step.flags("putdown-box", args)


def test_flags_hold_exactly_while_the_step_runs() -> None:
    _, synth = rig()
    synth.release(["altitude(uav0)"])
    synth.need_flags({"executing-climb(uav0)": ("climb", ("uav0",))})
    synth.step_started(Step("n1", "climb", "uav0", (), 250))
    assert synth.step_stopped("n1", 520) is not None
    assert synth.step_stopped("unknown", 600) is None
    flags = {s.time_ms: s.values["executing-climb(uav0)"] for s in synth.advance(1000)[0]}
    assert [t for t, v in flags.items() if v] == [300, 400, 500]
    assert len(flags) == 11 - MAX_DELAY // PERIOD
