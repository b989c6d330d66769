import pytest

from hdrc3_base.errors import ConfigError
from sim.lockstep import LockstepBarrier, Offer, Verdict

AGENTS = ("uav0", "uav1")


def test_explicit_mode_waits_for_every_required_agent() -> None:
    barrier: LockstepBarrier[str] = LockstepBarrier(AGENTS, ["uav0", "uav1"])
    assert barrier.begin_tick(0, connected=()) == {"uav0", "uav1"}
    assert not barrier.ready()
    assert barrier.offer(Offer("uav0", 0, "a")) is Verdict.ACCEPTED
    assert barrier.missing() == ["uav1"]
    assert barrier.offer(Offer("uav1", 0, "b")) is Verdict.ACCEPTED
    assert barrier.ready()
    assert barrier.commands() == {"uav0": "a", "uav1": "b"}


@pytest.mark.parametrize(
    ("stamp", "verdict"),
    [(19_999_999, Verdict.STALE), (40_000_000, Verdict.EARLY), (20_000_000, Verdict.ACCEPTED)],
)
def test_answers_must_carry_the_current_tick(stamp: int, verdict: Verdict) -> None:
    barrier: LockstepBarrier[str] = LockstepBarrier(AGENTS, ["uav0"])
    barrier.begin_tick(20_000_000)
    assert barrier.offer(Offer("uav0", stamp, "x")) is verdict
    assert barrier.ready() is (verdict is Verdict.ACCEPTED)


def test_duplicate_and_unknown_answers_are_ignored() -> None:
    barrier: LockstepBarrier[str] = LockstepBarrier(AGENTS, ["uav0"])
    barrier.begin_tick(0)
    assert barrier.offer(Offer("uav0", 0, "first")) is Verdict.ACCEPTED
    assert barrier.offer(Offer("uav0", 0, "second")) is Verdict.DUPLICATE
    assert barrier.offer(Offer("uav9", 0, "x")) is Verdict.UNKNOWN_AGENT
    assert barrier.commands() == {"uav0": "first"}


def test_automatic_mode_follows_connected_agents_and_holds_free_ones() -> None:
    barrier: LockstepBarrier[str] = LockstepBarrier(AGENTS)
    assert not barrier.explicit
    assert barrier.begin_tick(0, connected=["uav1", "ghost"]) == {"uav1"}
    # a free agent's latest command is taken whatever its stamp
    assert barrier.offer(Offer("uav0", 123, "free")) is Verdict.ACCEPTED
    assert not barrier.ready()
    barrier.release("uav1")
    assert barrier.ready()
    assert barrier.begin_tick(20_000_000, connected=[]) == frozenset()
    assert barrier.ready()
    assert barrier.commands() == {"uav0": "free"}


def test_forget_drops_latest_commands() -> None:
    barrier: LockstepBarrier[str] = LockstepBarrier(AGENTS, ["uav0"])
    barrier.begin_tick(0)
    barrier.offer(Offer("uav0", 0, "a"))
    barrier.forget()
    assert not barrier.ready()
    assert barrier.commands() == {}


def test_unknown_required_agent_is_misuse() -> None:
    with pytest.raises(ConfigError, match="uav7"):
        LockstepBarrier(AGENTS, ["uav7"])
