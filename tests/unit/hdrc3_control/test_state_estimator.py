"""Navigation filter: consistency, dead reckoning through GPS dropouts, health, gating, vision."""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import numpy as np
import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_control.aiding import AidingSource, Verdict
from hdrc3_control.commands import EstimatorHealth, G
from hdrc3_control.measurements import (
    AttitudeMeasurement,
    BaroMeasurement,
    GpsMeasurement,
    ImuMeasurement,
    VisionPoseMeasurement,
)
from hdrc3_control.state_estimator import StateEstimator, body_to_enu

VEL = np.array([3.0, -2.0, 0.5])
P0 = np.array([10.0, 20.0, 30.0])


@dataclass
class Scenario:
    """Straight, unaccelerated flight with white sensor noise and a constant accelerometer bias."""

    seed: int = 0
    accel_bias: tuple[float, float, float] = (0.03, -0.03, 0.02)
    gps_off: tuple[float, float] = (math.inf, math.inf)
    vision: bool = False
    vision_delay: float = 0.0
    """s between an image's time (the fix's stamp) and the fix reaching the filter."""
    vision_off: tuple[tuple[float, float], ...] = ()
    """The pad out of sight (occlusions) in these intervals of image times."""
    gps_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)
    verdicts: list[Verdict] = field(default_factory=list)
    baro_drift: float = 0.0
    """m/s of barometer drift from t = 40 s on (the filter has converged by then)."""
    baro_fault_at: float | None = None
    """When the filter excluded the barometer."""
    climbs: tuple[tuple[float, float, float], ...] = ()
    """(start s, duration s, rate m/s): vertical speed added over the interval, reached and
    left on 1 s ramps (the accelerometer feels them)."""
    est: StateEstimator = field(default_factory=StateEstimator)
    health: dict[float, EstimatorHealth] = field(default_factory=dict)

    def vertical(self, t: float) -> tuple[float, float]:
        """(added vertical speed, vertical acceleration) of the ``climbs`` at ``t``."""
        speed = accel = 0.0
        for start, duration, rate in self.climbs:
            up = min(max(t - start, 0.0), 1.0)
            down = min(max(t - start - duration, 0.0), 1.0)
            speed += rate * (up - down)
            accel += rate * ((0.0 < t - start < 1.0) - (0.0 < t - start - duration < 1.0))
        return speed, accel

    def run(self, seconds: float, record: list[tuple[float, np.ndarray, np.ndarray]]) -> None:
        rng = np.random.default_rng(self.seed)
        queued: list[VisionPoseMeasurement] = []
        climbed = 0.0
        for k in range(round(seconds * 200)):
            t = k / 200.0
            climb_speed, climb_accel = self.vertical(t)
            truth = np.concatenate([P0 + VEL * t, VEL])
            truth[2] += climbed
            truth[5] += climb_speed
            climbed += climb_speed / 200.0
            if k % 4 == 0:
                self.est.update_attitude(AttitudeMeasurement(t, 0.0, 0.0, 0.3))
            f = np.array([0.0, 0.0, -G - climb_accel]) + np.array(self.accel_bias)
            f += 0.05 * rng.standard_normal(3)
            w = 0.003 * rng.standard_normal(3)
            self.est.update_imu(ImuMeasurement(t, tuple(f), tuple(w)))  # type: ignore[arg-type]
            if k % 20 == 0 and not self.gps_off[0] <= t < self.gps_off[1]:
                pos = truth[:3] + self.gps_bias + rng.normal(0.0, [0.5, 0.5, 2.0])
                vel = truth[3:] + 0.1 * rng.standard_normal(3)
                self.est.update_gps(GpsMeasurement(t, tuple(pos), tuple(vel)))  # type: ignore[arg-type]
            if k % 8 == 0:
                drift = self.baro_drift * max(0.0, t - 40.0)
                noise = 0.3 * rng.standard_normal()
                self.est.update_baro(BaroMeasurement(t, truth[2] + drift + noise))
            if self.vision and k % 8 == 0 and not any(a <= t < b for a, b in self.vision_off):
                pos = truth[:3] + 0.05 * rng.standard_normal(3)
                queued.append(VisionPoseMeasurement(t, tuple(pos)))  # type: ignore[arg-type]
            while queued and queued[0].time + self.vision_delay <= t + 1e-9:
                self.verdicts.append(self.est.update_vision(queued.pop(0)))
            self.health[round(t, 3)] = self.est.health(t)
            if self.est.baro_fault is not None and self.baro_fault_at is None:
                self.baro_fault_at = t
            if self.est.initialised:
                record.append(
                    (t, truth, self.est.state_vector()[:6], self.est.covariance()[:6, :6])
                )  # type: ignore[arg-type]


def test_body_to_enu_rotations() -> None:
    np.testing.assert_allclose(body_to_enu(0.0, 0.0, 0.0, (1.0, 0.0, 0.0)), [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(
        body_to_enu(0.0, 0.0, math.pi / 2, (1.0, 0.0, 0.0)), [1, 0, 0], atol=1e-12
    )
    np.testing.assert_allclose(
        body_to_enu(0.3, -0.2, 1.0, (0.0, 0.0, -1.0))[2], math.cos(0.3) * math.cos(0.2)
    )


def test_uninitialised_filter_is_lost_and_refuses_an_estimate() -> None:
    est = StateEstimator()
    assert est.health(0.0) is EstimatorHealth.LOST
    with pytest.raises(ConfigError):
        est.estimate(0.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_filter_is_consistent(seed: int) -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    Scenario(seed=seed).run(30.0, rec)
    nees = [float((x - t) @ np.linalg.solve(p, x - t)) for _, t, x, p in rec[2000:]]  # type: ignore[misc]
    # 6 states: a consistent filter has mean NEES ~6, a conservative one less; never far above
    assert 0.5 < float(np.mean(nees)) < 9.0
    err = np.array([x - t for _, t, x, _ in rec[2000:]])  # type: ignore[misc]
    assert np.sqrt(np.mean(err[:, 0] ** 2 + err[:, 1] ** 2)) < 0.5
    assert np.sqrt(np.mean(err[:, 3:] ** 2)) < 0.1


@pytest.mark.parametrize(("dropout", "max_error"), [(3.0, 1.0), (5.0, 2.0)])
def test_dead_reckoning_through_a_gps_dropout(dropout: float, max_error: float) -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario(gps_off=(20.0, 20.0 + dropout))
    sc.run(20.0 + dropout - 0.01, rec)
    assert sc.est.health(sc.est._time or 0.0) is EstimatorHealth.DEGRADED
    _, truth, x, _ = rec[-1]  # type: ignore[misc]
    assert float(np.linalg.norm(x[:2] - truth[:2])) < max_error


def test_health_goes_lost_after_max_dead_reckoning_and_recovers() -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario(gps_off=(5.0, 17.0))
    sc.run(19.0, rec)
    assert [sc.health[t] for t in (4.0, 5.4, 14.9, 15.2, 16.9)] == [
        EstimatorHealth.OK,
        EstimatorHealth.OK,
        EstimatorHealth.DEGRADED,
        EstimatorHealth.LOST,
        EstimatorHealth.LOST,
    ]
    # GPS is back at 17 s (re-acquired through the gate reset if the drift is large)
    assert sc.health[18.5] is EstimatorHealth.OK


def test_frozen_imu_is_lost() -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario()
    sc.run(2.0, rec)
    for k in range(25):
        sc.est.update_imu(ImuMeasurement(2.0 + k / 200, (0.1, 0.2, -9.7), (0.0, 0.0, 0.0)))
    assert sc.est.health(2.12) is EstimatorHealth.LOST


def test_gps_outlier_is_rejected() -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario()
    sc.run(10.0, rec)
    before = sc.est.state_vector()
    jump = tuple(before[:3] + np.array([60.0, 0.0, 0.0]))
    assert not sc.est.update_gps(GpsMeasurement(10.0, jump, tuple(before[3:6])))  # type: ignore[arg-type]
    np.testing.assert_allclose(sc.est.state_vector(), before)
    assert sc.est.rejections == 1


def test_vision_hook_keeps_the_solution_aided_without_gps() -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario(gps_off=(5.0, 100.0), vision=True)
    sc.run(15.0, rec)
    assert sc.est.health(14.99) is EstimatorHealth.OK
    _, truth, x, _ = rec[-1]  # type: ignore[misc]
    assert float(np.linalg.norm(x[:3] - truth[:3])) < 0.2


@pytest.mark.parametrize(
    ("drift", "excluded_after"),
    [
        (0.0, None),  # climbing at 0.5 m/s: the barometer agrees with the GPS climb
        (0.01, None),  # 0.3 m in 30 s: weather, the bias state's job
        (0.2, (45.0, 60.0)),  # 3 m in 15 s, plus the low-pass and the filter noise
        (-0.5, (40.0, 47.0)),
    ],
)
def test_a_drifting_barometer_is_excluded_and_the_height_stays(
    drift: float, excluded_after: tuple[float, float] | None
) -> None:
    sc = Scenario(seed=4, baro_drift=drift)
    record: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc.run(90.0, record)
    if excluded_after is None:
        assert sc.est.baro_fault is None and sc.baro_fault_at is None
        return
    assert sc.baro_fault_at is not None
    assert excluded_after[0] <= sc.baro_fault_at <= excluded_after[1]
    assert sc.est.baro_fault is not None and "barometer drifting" in sc.est.baro_fault
    _, truth, x, _ = record[-1]  # type: ignore[misc]
    assert abs(x[2] - truth[2]) < 1.5  # the height did not follow the barometer


@pytest.mark.parametrize(
    "climbs",
    [
        ((45.0, 7.0, 3.0),),  # 21 m up at 3 m/s from a steady climb
        ((45.0, 7.0, -3.0),),  # 21 m down
        ((45.0, 10.0, 2.0), (60.0, 10.0, -2.0)),  # up 20 m, a 5 s pause, down again
    ],
)
def test_a_good_barometer_is_kept_through_climbs_and_descents(
    climbs: tuple[tuple[float, float, float], ...],
) -> None:
    # the barometer's low-pass lags a climb by the climb rate times its time constant: the GPS
    # climb it is compared with must lag alike, or every brisk climb looks like a drift
    sc = Scenario(seed=4, climbs=climbs)
    record: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc.run(90.0, record)
    assert sc.est.baro_fault is None
    # the filter follows the climbs on its inertial data (a wrong-signed one is metres off)
    assert max(abs(x[2] - truth[2]) for t, truth, x, _ in record if t > 40.0) < 0.5  # type: ignore[misc]


def _error(record: list[tuple[float, np.ndarray, np.ndarray]], at: float) -> float:
    """Position error of the filter at time ``at``."""
    _, truth, x, _ = min(record, key=lambda r: abs(r[0] - at))  # type: ignore[misc]
    return float(np.linalg.norm(x[:3] - truth[:3]))


@pytest.mark.parametrize(("delay", "max_error"), [(0.0, 0.1), (0.15, 0.1), (0.4, 0.12)])
def test_late_vision_fixes_are_moved_to_the_filter_s_time(delay: float, max_error: float) -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario(gps_off=(2.0, 100.0), vision=True, vision_delay=delay)
    sc.run(10.0, rec)
    # flying at 3.6 m/s: uncompensated, a 0.4 s old fix would be 1.4 m behind
    assert max(_error(rec, t) for t in np.arange(4.0, 10.0, 0.5)) < max_error
    assert Verdict.REJECTED not in sc.verdicts
    assert sc.est.used(9.99) == (AidingSource.VISION, AidingSource.BARO)


@pytest.mark.parametrize(("occlusion", "max_error"), [(1.0, 0.15), (3.0, 0.6)])
def test_occlusions_are_dead_reckoned_through(occlusion: float, max_error: float) -> None:
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    end = 8.0 + occlusion - 0.005
    sc = Scenario(gps_off=(2.0, 100.0), vision=True, vision_off=((8.0, end),))
    sc.run(end + 1.0, rec)
    assert sc.health[7.9] is EstimatorHealth.OK
    assert sc.health[round(end, 3)] is EstimatorHealth.DEGRADED  # blind: dead reckoning
    assert _error(rec, end) < max_error
    assert sc.health[round(end + 0.9, 3)] is EstimatorHealth.OK  # the pad is seen again
    assert sc.verdicts[-1] is Verdict.ACCEPTED and _error(rec, end + 0.9) < 0.1


@pytest.fixture(scope="module")
def on_vision() -> StateEstimator:
    """A filter flown 8 s on vision fixes (no GPS after 2 s)."""
    sc = Scenario(gps_off=(2.0, 100.0), vision=True)
    sc.run(8.0, [])
    return sc.est


@pytest.mark.parametrize(
    ("offset", "sigma", "verdict"),
    [
        ((1.5, 0.0, 0.0), 0.05, Verdict.REJECTED),  # an outlier: 1.5 m off a cm solution
        ((0.0, 0.0, -0.8), 0.05, Verdict.REJECTED),
        ((0.05, 0.02, 0.0), 0.05, Verdict.ACCEPTED),
        ((math.nan, 0.0, 0.0), 0.05, Verdict.INVALID),
        ((0.0, 0.0, 0.0), 0.0, Verdict.INVALID),
        ((0.0, 0.0, 0.0), 0.05, Verdict.STALE),  # 2 s old: beyond the filter's memory
    ],
)
def test_vision_outliers_are_gated(
    on_vision: StateEstimator,
    offset: tuple[float, float, float],
    sigma: float,
    verdict: Verdict,
) -> None:
    est = copy.deepcopy(on_vision)
    before = est.state_vector()
    t = 8.0 - 1.0 / 200.0 - (2.0 if verdict is Verdict.STALE else 0.0)
    truth = P0 + VEL * t
    fix = VisionPoseMeasurement(t, tuple(truth + np.array(offset)), sigma)  # type: ignore[arg-type]
    assert est.update_vision(fix) is verdict
    if verdict is not Verdict.ACCEPTED:
        np.testing.assert_allclose(est.state_vector(), before)
    assert est.aiding.count(AidingSource.VISION, verdict) == 1 + on_vision.aiding.count(
        AidingSource.VISION, verdict
    )


def test_vision_takes_over_from_a_biased_gps() -> None:
    """GPS 3 m off (its correlated error): the pad comes into view, the fixes win."""
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    sc = Scenario(gps_bias=(3.0, -2.0, 0.0), vision=True, vision_off=((0.0, 10.0),))
    sc.run(15.0, rec)
    assert 3.0 < _error(rec, 9.9) < 4.5  # on the GPS before the pad was seen
    assert _error(rec, 14.9) < 0.15
    assert sc.est.used(14.99) == (AidingSource.GPS_VELOCITY, AidingSource.VISION, AidingSource.BARO)
    assert sc.est.aiding.count(AidingSource.GPS, Verdict.ACCEPTED) > 40
    # one run of consistent rejections, then the filter is on the fixes
    assert sc.est.aiding.count(AidingSource.VISION, Verdict.REJECTED) == 10
    assert sc.est.aiding.report(14.99, 0.5)["used"] == ["gps_velocity", "vision", "baro"]


@pytest.mark.parametrize(("gap", "back_on_gps"), [(2.0, False), (5.0, True)])
def test_a_gap_in_the_fixes_is_bridged_on_gps_velocity(gap: float, back_on_gps: bool) -> None:
    """On the fixes over a GPS 3.6 m off, the pad is lost for ``gap`` s (frames dropped).

    Shorter than ``vision_priority`` the filter keeps to GPS velocity and stays on the fixes; a
    longer gap hands the position back to GPS (pulled towards its bias by the end of the gap).
    """
    end = 15.0 + gap
    runs = [
        Scenario(gps_bias=(3.0, -2.0, 0.0), vision=True, vision_off=((0.0, 10.0), (15.0, end)))
        for _ in range(2)
    ]
    rec: list[tuple[float, np.ndarray, np.ndarray]] = []
    runs[0].run(15.0, [])
    runs[1].run(end, rec)  # the same seed: the first 15 s are the same
    before, after = (sc.est.aiding.count(AidingSource.GPS, Verdict.ACCEPTED) for sc in runs)
    error = _error(rec, end - 0.01)
    if back_on_gps:
        assert after > before and error > 1.0, (after - before, error)
    else:
        assert after == before and error < 0.2, (after - before, error)
