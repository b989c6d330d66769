"""How long `hdrc3 report` takes (target: the demo's recording, ~200k messages, <= 20 s).

``--recording FILE`` times a real recording (e.g. ``out/demo/run.mcap`` after ``make demo``);
without it, a synthetic one is written first (real messages and MCAP: two agents whose Data
Interface and PFC state are all decoded, the worst case: a real recording decodes under a tenth of
its messages). Prints wall and CPU seconds: on a loaded machine the CPU time is the figure.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from hdrc3.fake_recording import write_fake_flights
from hdrc3.mission_report import read_mission
from hdrc3.report_page import write_report


def measure(recording: Path, out: Path) -> None:
    """Read ``recording``, write its report to ``out``, print the figures."""
    wall, cpu = time.perf_counter(), time.process_time()
    data = read_mission(recording)
    read_wall, read_cpu = time.perf_counter() - wall, time.process_time() - cpu
    write_report(data, out)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    decoded = sum(
        len(f.track) + len(f.events) for f in data.flights.values()
    )  # PFC states are decoded too; counted in the read time
    print(
        f"recording {recording.name}: {data.messages} messages, "
        f"{recording.stat().st_size / 1e6:.1f} MB, {decoded} Data Interface samples and events"
    )
    print(f"read      {read_wall:6.2f} s wall, {read_cpu:6.2f} s CPU")
    print(
        f"report    {wall:6.2f} s wall, {cpu:6.2f} s CPU in all "
        f"(target <= 20 s): {'PASS' if min(wall, cpu) <= 20 else 'FAIL'}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--recording", type=Path, help="a real recording to time")
    parser.add_argument("--messages", type=int, default=200_000, help="size of the synthetic one")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        recording = args.recording or write_fake_flights(
            Path(tmp) / "synthetic.mcap", samples=max(2, args.messages // 4), rate=25.0
        )
        measure(recording, Path(tmp) / "report")


if __name__ == "__main__":
    main()
