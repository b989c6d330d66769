"""`hdrc3 report` as a user runs it, and the page it writes opened in headless Chromium.

Chromium comes from Debian's packages (`.ci/run` installs it). The page's own script counts the
figures the browser decoded; the DOM after the load event says how many of them loaded.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from hdrc3.fake_recording import write_fake_flights

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def test_report_command_writes_a_page_whose_figures_all_load(hdrc3_cli, tmp_path: Path) -> None:
    if CHROMIUM is None:
        pytest.skip("Debian's chromium is not installed (.ci/run installs it)")
    rec = write_fake_flights(tmp_path / "run.mcap", upper_layers=True)
    report = hdrc3_cli("report", str(rec), "--out", str(tmp_path / "report"))
    assert report.finish(timeout=120) == 0, report.lines
    assert "read 59 messages on 11 topics" in report.lines
    page = tmp_path / "report" / "index.html"
    assert f"report: {page}" in report.lines
    dom = subprocess.run(
        [
            CHROMIUM,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=10000",
            "--dump-dom",
            page.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    ).stdout
    figures = re.search(r"figures: (\d+) of (\d+) loaded", dom)
    assert figures is not None, dom[:2000]
    assert figures.groups() == ("4", "4")  # overview, two flights, timeline


def test_report_of_a_missing_file_is_a_one_line_error(hdrc3_cli, tmp_path: Path) -> None:
    report = hdrc3_cli("report", str(tmp_path / "none.mcap"))
    assert report.finish(timeout=60) == 2
    assert report.lines == [f"hdrc3 report: error: {tmp_path / 'none.mcap'}: no such recording"]
