"""The GPS outages of a seed are a property of the seed: the mission tests rely on two of them.

Seed 0 (the default) puts a 4.2 s outage on uav1's receiver at 151.1 s of sim time, which holds
a scan still flying then (issue 12's example 6.1 fails there, as it should); seed 2 has no
outage over 2.5 s on either aircraft in its first 900 s, so the TST integration tests use it.
"""

from __future__ import annotations

import pytest

from sim.sensors.fake_truth import make_truth
from sim.wind import WindSettings
from sim.world_loader import load_world
from sim.world_sim import SimConfig, WorldSim

GPS_TRUTH_RATE_HZ = 50.0


def long_outages(seed: int, seconds: float, longer_than: float) -> dict[str, list[float]]:
    """Start times (s, rounded to 0.1) of outages over ``longer_than`` s, per agent."""
    sim = WorldSim(
        SimConfig(load_world("revinge"), ("uav0", "uav1"), seed, WindSettings((0, 0, 0), 0.0))
    )
    out: dict[str, list[float]] = {}
    for name in ("uav0", "uav1"):
        gps = sim.agents[name].sensors.gps
        last, starts = 0.0, []
        for i in range(1, int(seconds * GPS_TRUTH_RATE_HZ) + 1):
            t = i / GPS_TRUTH_RATE_HZ
            if gps.update(make_truth(t)) is not None:
                if t - last > longer_than:
                    starts.append(round(last, 1))
                last = t
        out[name] = starts
    return out


@pytest.mark.parametrize(
    ("seed", "outages"), [(0, {"uav0": [], "uav1": [151.1]}), (2, {"uav0": [], "uav1": []})]
)
def test_long_gps_outages_of_the_mission_seeds(seed: int, outages: dict[str, list[float]]) -> None:
    assert long_outages(seed, 900.0, 2.5) == outages
