"""Execution monitoring cost and detection latency (HDRC3 chapter 9.3, issue 15 targets).

The whole monitoring pipeline of :mod:`hdrc3_deliberative.execution_monitor` runs on a synthetic
Data Interface trace: ``HelicopterState``-shaped messages at 25 Hz into DyKnow streams (policy
filters), state synthesis at 10 Hz (100 ms periods, 200 ms maximum delay) and progression of
every active formula. No ROS: the figures are the core's own cost.

1. **CPU**: ``--formulas`` (default 100) active global formulas, a mix of the chapter's robust
   speed limit (§9.3.2), Example 9.1's power-style overshoot rule over altitude rate, and
   altitude envelopes, with distinct thresholds so that no two formulas share a sub-formula.
   The trace is ``--minutes`` (default 30) of nominal flight with Gaussian sensor noise: the
   CPU time of this process per simulated second, as a share of one core at real time, and the
   number of violations (false alarms: the trace never breaks any formula).
2. **Latency**: the robust speed limit ``always (speed > T implies eventually[0,1000]
   always[0,500] speed <= T)`` over noisy traces that exceed T from an onset time drawn at
   random (``--trials``): ground-truth onset to the (simulated) time the violation event is
   returned, against the formula's bound (1000 ms) plus one state period.

Run: ``.venv/bin/python bench/monitoring.py [--formulas 100] [--minutes 30] [--trials 20]``
"""

from __future__ import annotations

import argparse
import random
import statistics
import time

from hdrc3_deliberative.execution_monitor import EventKind
from hdrc3_deliberative.monitor_fakes import MonitorRig

STATES = "states period 100 ms, max_delay 200 ms, stale 1000 ms;\n"
PERIOD_MS = 100
MESSAGE_MS = 40  # 25 Hz Data Interface
TICK_MS = 20  # the node's timer
NOMINAL_SPEED = 8.0
NOISE = 0.3  # m/s, 1 sigma
SPEED_BOUND_MS = 1000


def formulas(count: int) -> str:
    """``count`` distinct global formulas that nominal flight satisfies."""
    lines = []
    for i in range(count):
        kind = i % 3
        if kind == 0:  # robust speed limit, 9.3.2
            limit = 12.0 + i * 0.01
            body = (
                f"always (speed(uav0) > {limit:.2f} implies eventually[0,1000] always[0,500]"
                f" speed(uav0) <= {limit:.2f})"
            )
        elif kind == 1:  # Example 9.1 shape over the vertical speed
            m = 2.0 + i * 0.01
            body = (
                f"always (vertical_speed(uav0) > {m:.2f} implies vertical_speed(uav0) < 1.5 *"
                f" {m:.2f} until[0,2000] always[0,1000] vertical_speed(uav0) <= {m:.2f})"
            )
        else:  # altitude envelope with a weak robustness window
            low = 20.0 + i * 0.01
            body = (
                f"always eventually[0,1500] (altitude(uav0) > {low:.2f} and altitude(uav0) < 200)"
            )
        lines.append(f"monitor f{i}: {body};")
    return STATES + "\n".join(lines) + "\n"


def cpu_share(count: int, minutes: float, seed: int) -> tuple[float, int, int, int]:
    """(CPU share of one core, violations, states, active formulas at the end)."""
    rng = random.Random(seed)
    rig = MonitorRig(formulas(count), extra_streams="")
    result = rig.start(0)
    assert result.monitors, result.reason
    end = int(minutes * 60_000)
    started = time.process_time()
    for now in range(0, end + 1, TICK_MS):
        if now % MESSAGE_MS == 0:
            rig.state(
                now,
                velocity_north=NOMINAL_SPEED + rng.gauss(0.0, NOISE),
                velocity_up=rng.gauss(0.0, NOISE),
                altitude=50.0 + rng.gauss(0.0, 0.5),
            )
        rig.advance(now)
    cpu = time.process_time() - started
    states = rig.monitor.synthesizer.states
    return cpu / (end / 1000.0), len(rig.of(EventKind.VIOLATED)), states, len(rig.monitor.active)


def latency(trials: int, seed: int) -> list[int]:
    """Onset-to-detection times (ms) of the robust speed limit over noisy traces."""
    rng = random.Random(seed)
    spec = STATES + (
        "monitor speed: always (speed(uav0) > 10 implies eventually[0,1000] always[0,500]"
        " speed(uav0) <= 10);"
    )
    out = []
    for _ in range(trials):
        rig = MonitorRig(spec, extra_streams="")
        rig.start(0)
        onset = rng.randrange(2000, 4000)
        detected = None
        for now in range(0, 8000, TICK_MS):
            if now % MESSAGE_MS == 0:
                base = 13.0 if now >= onset else NOMINAL_SPEED
                rig.state(now, velocity_north=base + rng.gauss(0.0, NOISE))
            if any(e.kind is EventKind.VIOLATED for e in rig.advance(now)):
                detected = now
                break
        assert detected is not None, "the violation was not detected"
        out.append(detected - onset)
    return out


def main() -> None:
    """Print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--formulas", type=int, default=100)
    parser.add_argument("--minutes", type=float, default=30.0)
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    share, false_alarms, states, active = cpu_share(args.formulas, args.minutes, args.seed)
    print(
        f"cpu: {args.formulas} formulas, {args.minutes:g} min simulated at 25 Hz input,"
        f" {states} states at 10 Hz: {share * 100:.2f} % of one core (target <= 5 %)",
        flush=True,
    )
    print(
        f"false alarms: {false_alarms} violations over {args.minutes:g} min of nominal noisy"
        f" flight ({active} formulas still active; target 0)",
        flush=True,
    )
    times = latency(args.trials, args.seed)
    target = SPEED_BOUND_MS + PERIOD_MS
    print(
        f"latency: robust speed limit (bound {SPEED_BOUND_MS} ms), {args.trials} trials:"
        f" median {statistics.median(times):.0f} ms, max {max(times)} ms"
        f" (target <= bound + one period = {target} ms)",
        flush=True,
    )


if __name__ == "__main__":
    main()
