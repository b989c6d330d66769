"""The ``monitor-radiation`` executor (chapter section 9.4, the Fukushima examples).

``monitor-radiation(target, duration)`` reads the aircraft's dose-rate meter
(``/<agent>/sensors/radiation``, one integration per second) for ``duration`` seconds, wherever
the aircraft is (the chapter's ``monitor-single`` hovers it meanwhile). It reports the mean
dose rate at the aircraft with its counting uncertainty (``1 / sqrt(counts)``), the mean
distance to the target from the aircraft's own position estimate, and what that makes the
target's dose rate at 1 m if the target is the only source: inverse square and the air's
attenuation of Cs-137's 662 keV gamma rays (``sim.world.AIR_ATTENUATION``, the physical
constant world files default to), background not subtracted. Four aircraft around one target
(``monitor-pattern``) so give four estimates of it. No sample in the whole interval fails the
node.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from hdrc3_tst.executor import SUCCEEDED, ActionContext, ActionExecutor, failed
from hdrc3_tst.executor_steps import Steps
from hdrc3_tst.platform_port import DoseSample
from sim.world import AIR_ATTENUATION


@dataclass(frozen=True)
class DoseEstimate:
    """What one monitoring interval measured."""

    samples: int
    counts: int
    mean_dose_rate: float
    """microsievert per hour at the aircraft."""
    distance: float
    """m, mean distance from the aircraft to the target."""

    @property
    def relative_error(self) -> float:
        """The counting uncertainty of the mean (1 sigma, relative)."""
        return 1.0 / math.sqrt(self.counts) if self.counts else math.inf

    @property
    def at_one_metre(self) -> float:
        """The target's dose rate at 1 m if it is the only source (microsievert per hour)."""
        d = self.distance
        return self.mean_dose_rate * d * d * math.exp(AIR_ATTENUATION * d)

    def text(self, target: str) -> str:
        """One line for the node's notes."""
        return (
            f"monitor-radiation: {self.mean_dose_rate:.3g} uSv/h +-{100 * self.relative_error:.1f}%"
            f" at the aircraft ({self.samples} s, {self.counts} counts), {self.distance:.1f} m from"
            f" {target}: about {self.at_one_metre:,.0f} uSv/h at 1 m from it"
        )


def estimate(samples: list[tuple[DoseSample, float]]) -> DoseEstimate:
    """The estimate of (sample, distance to the target) pairs (at least one)."""
    counts = sum(s.counts for s, _ in samples)
    mean = sum(s.dose_rate for s, _ in samples) / len(samples)
    distance = sum(d for _, d in samples) / len(samples)
    return DoseEstimate(len(samples), counts, mean, distance)


class MonitorRadiation(ActionExecutor):
    """``monitor-radiation(target, duration)``: the detector's samples over the interval."""

    def run(self, ctx: ActionContext) -> Steps:
        """Collect every new sample until the duration has passed, then report the estimate."""
        (point,) = ctx.place("target")
        target = (float(point[0]), float(point[1]), float(point[2]))
        duration = ctx.number("duration")
        samples: list[tuple[DoseSample, float]] = []
        after: float | None = None
        while True:
            sample = ctx.platform.dose()
            state = ctx.state()
            fresh = sample is not None and (after is None or sample.time > after)
            if fresh and sample is not None and state is not None:
                after = sample.time
                here = (state.east, state.north, state.up)
                samples.append((sample, math.dist(here, target)))
            if ctx.elapsed >= duration:
                break
            yield
        if not samples:
            return failed(f"the radiation detector gave no sample in {duration:g} s")
        ctx.notes.append(estimate(samples).text(ctx.name("target")))
        return SUCCEEDED


RADIATION_EXECUTORS: Mapping[str, type[ActionExecutor]] = MappingProxyType(
    {"monitor-radiation": MonitorRadiation}
)
"""The sensing executors of the radiation detector, by action name."""
