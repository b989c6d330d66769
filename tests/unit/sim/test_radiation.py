"""The radiation field of the world's sources and the dose-rate meter that counts it."""

from __future__ import annotations

import math

import pytest

from sim.sensors.fake_truth import make_truth
from sim.sensors.radiation import NEAR_M, RadiationField, RadiationParams, RadiationSensor
from sim.world_loader import load_world, parse_world
from tests.unit.sim.test_world_loader import BASE

WORLD = (
    BASE.replace('name = "test"', 'name = "test"\nradiation_background = 0.2')
    + '[[radiation_source]]\nname = "s"\nposition = [0.0, 0.0]\nheight = 0.0\n'
    + "dose_rate = 1000.0\nattenuation = 0.01\n"
)
"""A 1000 uSv/h source on the ground at the origin, where BASE's terrain is 1 m up."""
FIELD = RadiationField(parse_world(WORLD, "rad.toml"))


@pytest.mark.parametrize(
    ("point", "expected"),
    [
        ((10.0, 0.0, 1.0), 0.2 + 1000.0 * math.exp(-0.1) / 100.0),
        ((0.0, 30.0, 41.0), 0.2 + 1000.0 * math.exp(-0.5) / 2500.0),
        ((0.0, 0.0, 1.5), 0.2 + 1000.0 * math.exp(-0.01 * NEAR_M)),  # inside: as at 1 m
        ((5000.0, 0.0, 1.0), 0.2 + 1000.0 * math.exp(-50.0) / 5000.0**2),  # background only
    ],
)
def test_the_field_falls_with_the_square_of_the_distance_and_the_air(
    point: tuple[float, float, float], expected: float
) -> None:
    assert FIELD.dose_rate(point) == pytest.approx(expected)


def test_revinge_has_the_damaged_reactor_in_the_town_hall() -> None:
    world = load_world("revinge")
    (source,) = world.radiation_sources
    assert (source.name, source.east, source.north) == ("damaged_reactor", 190.0, 50.0)
    field = RadiationField(world)
    # the monitoring points of examples/talf/fukushima_monitor.talf: 50 m off, 30 m up
    ground = world.terrain.height(190.0, 100.0)
    assert 3.0 < field.dose_rate((190.0, 100.0, ground + 30.0)) < 20.0


@pytest.mark.parametrize("where", [(10.0, 0.0, 1.0), (0.0, 30.0, 41.0)])
def test_the_counts_are_poisson_around_the_field(where: tuple[float, float, float]) -> None:
    params = RadiationParams()
    sensor = RadiationSensor(FIELD, params, seed=3)
    samples = [sensor.update(make_truth(float(k), position_enu=where)) for k in range(400)]
    assert all(s is not None for s in samples)
    counts = [s.counts for s in samples if s is not None]
    mean = params.sensitivity * FIELD.dose_rate(where)
    # the mean of 400 Poisson counts is within 4 sigma of the expected mean
    assert abs(sum(counts) / len(counts) - mean) < 4.0 * math.sqrt(mean / len(counts))
    # and they vary as Poisson counts do
    variance = sum((c - mean) ** 2 for c in counts) / len(counts)
    assert 0.7 * mean < variance < 1.3 * mean
    first = samples[0]
    assert first is not None
    assert first.dose_rate == pytest.approx(first.counts / params.sensitivity)
    assert first.integration_time == 1.0


def test_the_same_seed_counts_the_same() -> None:
    def run(seed: int) -> list[int]:
        sensor = RadiationSensor(FIELD, seed=seed)
        samples = [sensor.update(make_truth(float(k))) for k in range(20)]
        return [s.counts for s in samples if s is not None]

    assert run(7) == run(7)
    assert run(7) != run(8)
