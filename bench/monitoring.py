"""Execution monitoring cost, false alarms and detection latency (HDRC3 chapter 9.3, issue 15).

The whole monitoring pipeline of :mod:`hdrc3_deliberative.execution_monitor` runs on a 25 Hz
Data Interface trace: ``HelicopterState`` messages into DyKnow streams (policy filters), state
synthesis with the packaged ``default.monitors`` settings (40 ms periods on the Data Interface's
grid, 200 ms maximum delay) and progression of every active formula, advanced after every
message as the node does. No ROS and no DDS: the figures are the core's own cost.

1. **CPU and false alarms**: ``--formulas`` (default 100) active global formulas, a mix of the
   chapter's robust speed limit (§9.3.2), Example 9.1's overshoot rule over the vertical speed,
   and altitude envelopes, with distinct thresholds so that no two formulas share a
   sub-formula. The trace (``--trace``) is ``--minutes`` (default 30) of

   * ``sim`` (default): a nominal closed-loop flight. The JSBSim RMAX of ``sim.world_sim``,
     flown in process by the PFC kernel (:class:`~hdrc3_control.kernel_harness.KernelFlight`)
     in 3 m/s wind with gusts, takes off and flies a 150 m square at 8 m/s, climbing and
     descending 15 m on alternate legs. The messages are made from the kernel's own estimate
     (GPS, IMU and barometer with their noise), as the Platform Server makes them. Ground truth
     only feeds the printed envelope, which shows that every formula holds on the true flight.
     At about 2.5 times real time, 30 minutes of flight take about 12 minutes of wall time.
   * ``synthetic``: level flight at 8 m/s with Gaussian noise, no simulator (seconds).

   Printed: the CPU time of the monitor's calls per second of trace, as a share of one core at
   real time; and the violations (each one a false alarm).
2. **Latency**: the robust speed limit ``always (speed > T implies eventually[0,1000]
   always[0,500] speed <= T)`` over noisy traces that exceed T from an onset time drawn at
   random (``--trials``). Measured from the ground-truth onset to the (simulated) time the
   violation event is returned, against the formula's bound (1000 ms) plus one state period.
   The excess is first seen in the next 25 Hz sample, which lies on the state grid, so it is
   seen at most one period late.

Run: ``.venv/bin/python bench/monitoring.py [--formulas 100] [--minutes 30] [--trials 20]
[--trace sim|synthetic]``
"""

from __future__ import annotations

import argparse
import itertools
import math
import random
import statistics
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, fields
from typing import Any

from hdrc3_control.kernel_harness import KernelFlight
from hdrc3_control.pfc_state import FlightMode
from hdrc3_deliberative.execution_monitor import EventKind
from hdrc3_deliberative.monitor_fakes import MonitorRig
from hdrc3_deliberative.monitor_spec import DEFAULT_SPEC, MonitorSpecParser
from hdrc3_dyknow.fakes import FakeHelicopterState
from hdrc3_platform_server.data_interface import DI_RATE_HZ, RateGate, helicopter_state
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.platform_status import PfcSample
from sim.truth_state import TruthState
from sim.wind import WindSettings

SETTINGS = MonitorSpecParser().parse_file(DEFAULT_SPEC).settings
"""The packaged default.monitors' state settings."""
STATES = (
    f"states period {SETTINGS.period_ms} ms, max_delay {SETTINGS.max_delay_ms} ms,"
    f" stale {SETTINGS.stale_ms} ms;\n"
)
PERIOD_MS = SETTINGS.period_ms
MESSAGE_MS = round(1000 / DI_RATE_HZ)  # the Data Interface
NOMINAL_SPEED = 8.0
NOISE = 0.3  # m/s, 1 sigma
SPEED_BOUND_MS = 1000
WAYPOINTS = ((150.0, 0.0, 30.0), (150.0, 150.0, 45.0), (0.0, 150.0, 30.0), (0.0, 0.0, 45.0))
"""The sim trace's square (local ENU m, height over the origin)."""
CRUISE = 8.0
"""m/s along the square."""
WIND, GUST = 3.0, 1.0
"""Mean wind from the west and gust intensity of the sim trace, m/s."""
PROGRESS_MS = 300_000
"""A progress line every 5 min of the sim trace."""
SPIN_UP_S = 12.0
"""Rotor spin-up on the skids before the take-off."""


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


Fields = dict[str, Any]
"""A Data Interface message's fields (``HelicopterState`` names)."""
MESSAGE_FIELDS = tuple(f.name for f in fields(FakeHelicopterState) if f.name != "header")
"""The fields the monitor's streams may read."""


def synthetic_trace(minutes: float, seed: int) -> Iterator[tuple[int, Fields]]:
    """Straight level flight at 8 m/s with Gaussian noise on speed and altitude (no sim)."""
    rng = random.Random(seed)
    for now in range(0, int(minutes * 60_000) + 1, MESSAGE_MS):
        yield (
            now,
            {
                "velocity_north": NOMINAL_SPEED + rng.gauss(0.0, NOISE),
                "velocity_up": rng.gauss(0.0, NOISE),
                "altitude": 50.0 + rng.gauss(0.0, 0.5),
            },
        )


@dataclass
class Envelope:
    """What the aircraft truly did (ground truth, only to show the formulas held)."""

    speed: float = 0.0
    climb: float = 0.0
    altitude: tuple[float, float] = (math.inf, -math.inf)

    def add(self, truth: TruthState, origin_altitude: float) -> None:
        """Widen by one true state."""
        self.speed = max(self.speed, math.hypot(*truth.velocity_enu[:2]))
        self.climb = max(self.climb, truth.velocity_enu[2])
        up = truth.position_enu[2] + origin_altitude
        self.altitude = (min(self.altitude[0], up), max(self.altitude[1], up))


def sim_trace(minutes: float, seed: int, envelope: Envelope) -> Iterator[tuple[int, Fields]]:
    """The Data Interface of a nominal closed-loop flight (JSBSim RMAX flown by the PFC kernel).

    Take-off from revinge's home, then the square ``WAYPOINTS`` over and over at ``CRUISE`` m/s,
    each leg a ``Traj3D-Flyto-EV`` sent once the previous one arrived and the aircraft hovers;
    ``WIND`` m/s of mean wind with gusts. The kernel's own state estimate (GPS, IMU, barometer
    with their noise) becomes ``HelicopterState`` as the Platform Server makes it, 25 Hz.
    """
    flight = KernelFlight(seed=seed, wind=WindSettings((WIND, 0.0, 0.0), GUST))
    world = flight.world
    frame = WorldFrame(world.origin.latitude, world.origin.longitude, world.origin.altitude)
    gate = RateGate()
    end = minutes * 60.0
    legs = itertools.cycle(WAYPOINTS)
    command: int | None = None
    flight.engine_on(autonomous=True)
    spun_up: float | None = None
    while flight.sim.time < end:
        snap = flight.tick().snapshot
        mode = flight.kernel.mode
        if spun_up is None and mode is FlightMode.GROUND_IDLE:
            spun_up = snap.time + SPIN_UP_S
        elif command is None and spun_up is not None and snap.time >= spun_up:
            command = flight.send("FCL-Takeoff-EV")
        elif command is not None and flight.finished(command) and mode is FlightMode.HOVER:
            command = flight.send("Traj3D-Flyto-EV", (*next(legs), CRUISE))
        if not gate.due(snap.time):
            continue
        if round(snap.time * 1000.0) % PROGRESS_MS == 0:
            print(f"  {snap.time / 60:.0f} of {minutes:g} min flown", flush=True)
        envelope.add(flight.sim.truth(flight.agent), world.origin.altitude)
        sample = PfcSample(
            pfc_time=snap.time,
            received=snap.time,
            position_enu=snap.position,
            velocity_enu=snap.velocity,
            latitude=0.0,  # the Platform Server's frame places the ENU position
            longitude=0.0,
            altitude=0.0,
            roll=snap.roll,
            pitch=snap.pitch,
            heading=snap.heading,
            rpm=snap.rotor_rpm,
            on_ground=snap.on_ground,
            auto_flag=snap.auto,
        )
        data = helicopter_state(sample, frame, snap.time, None, 0)
        yield round(snap.time * 1000.0), {name: getattr(data, name) for name in MESSAGE_FIELDS}


def cpu_share(
    count: int, trace: Iterable[tuple[int, Fields]]
) -> tuple[float, float, int, int, int]:
    """(CPU share of one core, s of trace, violations, states, active formulas at the end).

    Only the monitor's calls are timed: a simulator producing the trace costs nothing here.
    """
    rig = MonitorRig(formulas(count), extra_streams="")
    result = rig.start(0)
    assert result.monitors, result.reason
    cpu = 0.0
    last = 0
    for now, message in trace:
        started = time.process_time()
        rig.state(now, **message)
        rig.advance(now)
        cpu += time.process_time() - started
        last = now
    states = rig.monitor.synthesizer.states
    span = last / 1000.0
    return cpu / span, span, len(rig.of(EventKind.VIOLATED)), states, len(rig.monitor.active)


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
        for now in range(0, 8000, MESSAGE_MS):  # advanced on every message, as the node is
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
    parser.add_argument(
        "--trace",
        choices=("sim", "synthetic"),
        default="sim",
        help="where the 25 Hz input comes from",
    )
    args = parser.parse_args()

    envelope = Envelope()
    if args.trace == "sim":
        trace = sim_trace(args.minutes, args.seed, envelope)
        what = "closed-loop simulated flight (JSBSim, PFC kernel, sensor noise, wind)"
    else:
        trace = synthetic_trace(args.minutes, args.seed)
        what = "synthetic noisy level flight"
    share, span, false_alarms, states, active = cpu_share(args.formulas, trace)
    print(
        f"cpu: {args.formulas} formulas, {span / 60:.1f} min of {what} at {DI_RATE_HZ:g} Hz"
        f" input, {states} states at {1000 / PERIOD_MS:g} Hz: {share * 100:.2f} % of one core"
        " (target <= 5 %)",
        flush=True,
    )
    if args.trace == "sim":
        low, high = envelope.altitude
        print(
            f"truth: horizontal speed <= {envelope.speed:.2f} m/s, climb <= {envelope.climb:.2f}"
            f" m/s, altitude {low:.1f}-{high:.1f} m (every formula holds on it)",
            flush=True,
        )
    print(
        f"false alarms: {false_alarms} violations over {span / 60:.1f} min"
        f" ({active} formulas still active; target 0)",
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
