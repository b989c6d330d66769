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


def test_page_shows_the_upper_layers(tmp_path: Path) -> None:
    rec = write_fake_flights(tmp_path / "run.mcap", upper_layers=True)
    page = write_report(read_mission(rec), tmp_path / "report")
    text = page.read_text(encoding="utf-8")
    assert (page.parent / "timeline.png").read_bytes()[:8] == PNG
    assert "src='timeline.png'" in text and "x confirmed" in text
    for heading in ("TST nodes", "Execution monitor", "Recoveries", "Saliency map points"):
        assert f"<h2>{heading}</h2>" in text
    assert "<td>scan-area</td><td>102.0</td><td>108.0</td><td>failed</td>" in text
    assert "<td>look-at</td><td>109.5</td><td>-</td><td>running</td>" in text
    assert "<td>stale data</td>" in text and "<td>hovering</td>" in text
    assert "1 violation(s) not followed by a new plan" in text
    assert "<td>50.0</td><td>5.0</td><td>0.83</td><td>6</td><td>yes</td>" in text


def test_page_without_upper_layers_has_no_empty_sections(tmp_path: Path) -> None:
    rec = write_fake_flights(tmp_path / "run.mcap")
    text = write_report(read_mission(rec), tmp_path / "report").read_text(encoding="utf-8")
    for heading in ("TST nodes", "Execution monitor", "Recoveries", "Saliency map points"):
        assert f"<h2>{heading}</h2>" not in text
