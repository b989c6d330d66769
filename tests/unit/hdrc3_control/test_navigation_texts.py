"""The PFC's navigation announcements for each state of the filter."""

from __future__ import annotations

from hdrc3_control.measurements import GpsMeasurement
from hdrc3_control.navigation_texts import baro_text, failsafe_texts, fault_text
from hdrc3_control.pfc_state import FAILSAFE_PREFIX
from hdrc3_control.state_estimator import StateEstimator


def test_an_uninitialised_filter() -> None:
    est = StateEstimator()
    assert fault_text(est, 0.0) == "navigation not initialised"
    assert baro_text(est) is None
    texts = failsafe_texts(est, 0.0, on_ground=True)
    assert set(texts) == {"Fs-Hold-DO", "Fs-Land-DO", "Fs-End-DO"}
    assert all(t.startswith(FAILSAFE_PREFIX) for t in texts.values())
    assert texts["Fs-End-DO"] == f"{FAILSAFE_PREFIX} ended: on the ground"
    assert texts["Fs-Land-DO"].endswith("navigation not initialised")


def test_gps_age_and_the_barometer_exclusion_are_named() -> None:
    est = StateEstimator()
    est.update_gps(GpsMeasurement(0.0, (0.0, 0.0, 10.0), (0.0, 0.0, 0.0)))
    assert fault_text(est, 0.0) == "navigation lost: no attitude data"
    texts = failsafe_texts(est, 4.0, on_ground=False)
    assert "GPS lost for 4.0 s" in texts["Fs-Hold-DO"] and "within 6.0 s" in texts["Fs-Hold-DO"]
    assert texts["Fs-End-DO"].endswith("GPS back, hovering on GPS")
    est.baro_fault = "barometer drifting: x"
    assert baro_text(est) == (
        "navigation degraded: barometer drifting: x: barometer excluded, height from GPS"
    )
