"""The report page: figures written beside it, text escaped, problems shown."""

from __future__ import annotations

from pathlib import Path

from hdrc3.fake_recording import write_fake_flights
from hdrc3.mission_report import read_mission
from hdrc3.report_page import write_report

PNG = b"\x89PNG\r\n\x1a\n"


def test_page_links_every_figure_it_wrote_and_escapes_text(tmp_path: Path) -> None:
    rec = tmp_path / "run.mcap"
    write_fake_flights(rec)
    page = write_report(read_mission(rec), tmp_path / "report")
    text = page.read_text(encoding="utf-8")
    for name in ("overview.png", "flight_uav0.png", "flight_uav1.png"):
        assert (page.parent / name).read_bytes()[:8] == PNG
        assert f"src='{name}'" in text
    assert "PFC fault: &lt;b&gt;GPS&lt;/b&gt; &amp; IMU" in text and "<b>GPS" not in text
    assert "plus 1 segment requests" in text and "/uav1/pfc/state" in text


def test_page_without_flights_names_the_problem(tmp_path: Path) -> None:
    rec = tmp_path / "other.mcap"
    write_fake_flights(rec, agents={})
    page = write_report(read_mission(rec), tmp_path / "report")
    text = page.read_text(encoding="utf-8")
    assert "no flights to show" in text and "<img" not in text
    assert "/clock" not in text  # a topic without messages is not listed
