"""Benchmarks of the hdrc3_control flight modes flown in the simulated RMAX (in-process, sim time).

Subcommands: hover, path, latency, braking, landing, all. Each prints its figures against the
targets of the control-kernel issue and writes PNG plots (track, speed profile, errors) under
``--out`` (default out/control/). Errors are given twice: against the navigation solution (what
the controller can control) and against the ground truth (adds the navigation error: the
simulated GPS has a ~1.5 m horizontal error correlated over minutes).

Run: .venv/bin/python bench/control_kernel.py all [--out out/control] [--runs 5]
"""

from __future__ import annotations

import argparse
import math
import random
import sys
from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from control_sim import (
    FIGURE7_START,
    SimFlight,
    figure7_path,
    fly_path,
    hover,
    land,
    takeoff,
    touchdown_velocity,
)

from hdrc3_control.commands import AttitudeCommand, EstimatedState
from hdrc3_control.hover import HoverController, HoverSetpoint, HoverStatus
from hdrc3_control.landing import LandingTarget
from hdrc3_control.path_following import PathEvent, PathFollower
from hdrc3_control.path_segment import PathSegment

WIND = (0.0, 10.0, 0.0)
"""10 m/s wind blowing to the north (from the south), plus 2 m/s (1 sigma) gusts."""
GUST = 2.0


def _verdict(ok: bool) -> str:
    return "PASS" if ok else "FAIL"


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(x**2))) if len(x) else math.nan


# ---------------------------------------------------------------------- hover
def bench_hover(out: Path, seed: int) -> bool:
    ok_all = True
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    for col, (label, wind, gust) in enumerate(
        (("calm", (0.0, 0.0, 0.0), 0.0), ("wind", WIND, GUST))
    ):
        f = SimFlight(seed=seed, wind=wind, gust_sigma=gust)
        f.start_engine()
        up = takeoff(f, 15.0)
        sp = up.outputs[-1].hover_point
        settle = hover(f, sp, 40.0, up.integral, until_stable=True)
        settle = hover(f, sp, 10.0, settle.integral)  # stabilising
        run = hover(f, sp, 60.0, settle.integral)
        i0 = run.first_tick
        est = np.array([s.position for s in f.log.estimate[i0:]])
        tru = np.array([s.position_enu for s in f.log.truth[i0:]])
        t = np.array(f.log.time[i0:])
        e_est, e_tru = est - np.array(sp.position), tru - np.array(sp.position)
        hor_est, alt_est = _rms(np.hypot(e_est[:, 0], e_est[:, 1])), _rms(e_est[:, 2])
        hor_tru, alt_tru = _rms(np.hypot(e_tru[:, 0], e_tru[:, 1])), _rms(e_tru[:, 2])
        stable = [o.status is HoverStatus.STABLE for o in run.outputs]
        frac = float(np.mean(stable))
        if label == "calm":
            ok = hor_est <= 0.5 and alt_est <= 0.3
            target = "target RMS <= 0.5 m hor, <= 0.3 m alt"
        else:
            ok = frac == 1.0
            target = "target: Hover-Stable-CO at all times after stabilising"
        ok_all &= ok
        print(
            f"hover {label:5s}: RMS error (nav) hor {hor_est:.3f} m alt {alt_est:.3f} m | "
            f"(truth) hor {hor_tru:.3f} m alt {alt_tru:.3f} m | Hover-Stable {100 * frac:.1f} % "
            f"of {len(stable)} ticks | max |e| (nav) "
            f"{np.max(np.hypot(e_est[:, 0], e_est[:, 1])):.2f} m "
            f"-> {target}: {_verdict(ok)}"
        )
        ax = axes[0, col]
        ax.plot(e_est[:, 0], e_est[:, 1], label="navigation solution")
        ax.plot(e_tru[:, 0], e_tru[:, 1], alpha=0.6, label="truth")
        ax.set_title(f"hover {label}: horizontal offset from setpoint")
        ax.set_xlabel("east m")
        ax.set_ylabel("north m")
        ax.axis("equal")
        ax.legend()
        ax = axes[1, col]
        ax.plot(t, np.hypot(e_est[:, 0], e_est[:, 1]), label="hor error (nav)")
        ax.plot(t, e_est[:, 2], label="alt error (nav)")
        ax.plot(t, np.hypot(e_tru[:, 0], e_tru[:, 1]), alpha=0.5, label="hor error (truth)")
        ax.set_xlabel("sim time s")
        ax.set_ylabel("m")
        ax.legend()
    fig.tight_layout()
    fig.savefig(out / "hover.png", dpi=90)
    plt.close(fig)
    print(f"  plot: {out / 'hover.png'}")
    return ok_all


# ---------------------------------------------------------------------- path
def _truth_cross_track(segments: list[PathSegment], points: np.ndarray) -> np.ndarray:
    dense = np.concatenate([[s.position(x) for x in np.linspace(0, 1, 400)] for s in segments])
    return np.array([np.min(np.linalg.norm(dense - p, axis=1)) for p in points])


def bench_path(out: Path, seed: int) -> bool:
    ok_all = True
    fig, axes = plt.subplots(3, 2, figsize=(13, 12))
    for col, (label, wind, gust, limit) in enumerate(
        (("calm", (0.0, 0.0, 0.0), 0.0, 0.5), ("wind", WIND, GUST, 1.5))
    ):
        f = SimFlight(seed=seed, placement=FIGURE7_START, wind=wind, gust_sigma=gust)
        f.start_engine()
        up = takeoff(f, 15.0)
        st = hover(f, up.outputs[-1].hover_point, 40.0, up.integral, until_stable=True)
        segs = figure7_path(f.state().position)
        run = fly_path(f, segs, st.integral)
        i0 = run.first_tick
        outs = run.outputs
        tru = np.array([s.position_enu for s in f.log.truth[i0:]])
        vel = np.array([s.velocity_enu for s in f.log.truth[i0:]])
        t = np.array(f.log.time[i0:])
        ct_nav = np.array([o.cross_track for o in outs])
        ct_tru = _truth_cross_track(segs, tru)
        speed = np.hypot(vel[:, 0], vel[:, 1])
        ref = np.array([o.speed_ref for o in outs])
        lim = np.array([o.speed_limit for o in outs])
        arrival_nav = float(np.linalg.norm(np.array(f.state().position) - np.array(segs[-1].end)))
        arrival_tru = float(np.linalg.norm(tru[-1] - np.array(segs[-1].end)))
        slowed = [
            o.segment_id for o in outs if o.speed_limit < segs[o.segment_id].target_velocity - 0.1
        ]
        ok = (
            run.ok
            and _rms(ct_nav) <= limit
            and float(np.max(ref - lim)) <= 1e-9
            and arrival_nav <= 3.0
        )
        ok_all &= ok
        print(
            f"path  {label:5s}: arrived {run.ok} in {t[-1] - t[0]:.1f} s | cross-track RMS (nav) "
            f"{_rms(ct_nav):.3f} m max {np.max(ct_nav):.2f} m | (truth vs path) RMS "
            f"{_rms(ct_tru):.3f} m | max(speed_ref - V_compat) {np.max(ref - lim):+.3f} m/s | "
            f"max(truth speed - V_compat) {np.max(speed - lim):+.2f} m/s | max speed "
            f"{np.max(speed):.2f} m/s | curvature-limited ticks {len(slowed)} (segments "
            f"{sorted(set(slowed))}, min V_compat {np.min(lim):.2f} m/s) | arrival dist (nav) "
            f"{arrival_nav:.2f} m (truth) {arrival_tru:.2f} m -> target RMS <= {limit} m, "
            f"speed <= V, arrival <= 3 m: {_verdict(ok)}"
        )
        ax = axes[0, col]
        for s in segs:
            pts = np.array([s.position(x) for x in np.linspace(0, 1, 100)])
            ax.plot(pts[:, 0], pts[:, 1], "k--", lw=1)
        ax.plot(tru[:, 0], tru[:, 1], label="truth")
        est = np.array([s.position for s in f.log.estimate[i0:]])
        ax.plot(est[:, 0], est[:, 1], alpha=0.7, label="navigation solution")
        ax.set_title(f"Figure 7 path, {label} (AB 8, BC 3, CD 8 m/s)")
        ax.axis("equal")
        ax.legend()
        ax = axes[1, col]
        ax.plot(t, speed, label="ground speed (truth)")
        ax.plot(t, ref, label="speed reference")
        ax.plot(t, np.minimum(lim, 12.0), label="V = sqrt(phi_max g R) (clipped at 12)")
        ax.set_ylabel("m/s")
        ax.legend()
        ax = axes[2, col]
        ax.plot(t, ct_nav, label="cross-track (nav)")
        ax.plot(t, ct_tru, alpha=0.6, label="cross-track (truth vs path)")
        ax.set_xlabel("sim time s")
        ax.set_ylabel("m")
        ax.legend()
    fig.tight_layout()
    fig.savefig(out / "path.png", dpi=90)
    plt.close(fig)
    print(f"  plot: {out / 'path.png'}")
    return ok_all


# ---------------------------------------------------------------------- latency
def bench_latency(out: Path, seed: int, trials: int = 200) -> bool:
    """Segment sent at a random instant -> Request-Segment raised by the PFCM in the kernel tick."""
    rng = random.Random(seed)
    f = SimFlight(seed=seed)
    f.start_engine()
    up = takeoff(f, 10.0)
    sp = up.outputs[-1].hover_point
    integral = up.integral
    latencies: list[float] = []
    for k in range(trials):
        hold = HoverController(sp, integral=integral)

        def hold_ctl(
            s: EstimatedState, now: float, hold: HoverController = hold
        ) -> AttitudeCommand:
            return hold.update(s, f.dt).command

        f.fly(hold_ctl, rng.uniform(0.1, 0.4))
        integral = hold.loop.integral
        # the executor sends somewhere inside the coming 20 ms; the kernel reads its mailbox at
        # the start of the next tick (Communicate), takes the segment and raises the event
        sent = f.now - rng.uniform(0.0, f.dt)
        here = f.state().position
        seg = PathSegment.straight(here, (here[0] + 20.0, here[1], here[2]), 2.0, 2.0, k)
        pf = PathFollower()
        pf.start(f.state(), seg, integral)
        events: list[float] = []

        def ctl(
            s: EstimatedState, now: float, pf: PathFollower = pf, ev: list[float] = events
        ) -> AttitudeCommand:
            o = pf.update(s, now)
            if PathEvent.REQUEST_SEGMENT in o.events:
                ev.append(now)
            return o.command

        f.tick(ctl)
        latencies.append(events[0] - sent)
        sp = HoverSetpoint(f.state().position, f.state().heading)
    lat = np.array(latencies) * 1000.0
    p50, p99, mx = np.percentile(lat, 50), np.percentile(lat, 99), lat.max()
    ok = p99 <= 50.0
    print(
        f"latency: Request-Segment after a segment is sent, {trials} trials (sim time, in-process "
        f"50 Hz kernel): p50 {p50:.1f} ms p99 {p99:.1f} ms max {mx:.1f} ms -> target p99 <= 50 ms: "
        f"{_verdict(ok)}"
    )
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.hist(lat, bins=20)
    ax.set_xlabel("Request-Segment latency, ms (sim time)")
    fig.tight_layout()
    fig.savefig(out / "latency.png", dpi=90)
    plt.close(fig)
    print(f"  plot: {out / 'latency.png'}")
    return bool(ok)


# ---------------------------------------------------------------------- braking
def bench_braking(out: Path, runs: int) -> bool:
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    stops: list[tuple[float, float]] = []
    ok_all = True
    for seed in range(runs):
        f = SimFlight(seed=100 + seed, placement=FIGURE7_START)
        f.start_engine()
        up = takeoff(f, 12.0)
        segs = figure7_path(f.state().position)
        run = fly_path(f, segs, up.integral, withhold_from=1)
        stopped = run.outputs[-1].status.name == "STOPPED"
        end_e = segs[0].end[0]
        est_e = np.array([s.position[0] for s in f.log.estimate[run.first_tick :]])
        tru = f.log.truth[run.first_tick :]
        tru_e = np.array([s.position_enu[0] for s in tru])
        t = np.array(f.log.time[run.first_tick :])
        hp = run.outputs[-1].hover_point
        held = hover(f, HoverSetpoint(hp, f.state().heading), 10.0, run.integral) if hp else None
        hovering = held is not None and held.outputs[-1].status is HoverStatus.STABLE
        margin = end_e - float(np.max(est_e))
        stops.append((margin, end_e - float(np.max(tru_e))))
        ok = stopped and margin >= -0.5 and hovering
        ok_all &= ok
        axes[0].plot(t - t[0], end_e - est_e, label=f"seed {100 + seed}")
        axes[1].plot(t - t[0], [math.hypot(*s.velocity_enu[:2]) for s in tru])
    m = np.array(stops)
    print(
        f"braking: next segment withheld, {runs} runs: stopped and hovering before the end of "
        f"the current segment in {sum(1 for s in stops if s[0] >= -0.5)}/{runs}; stop margin to "
        f"the segment end (nav) min {m[:, 0].min():.2f} m mean {m[:, 0].mean():.2f} m, (truth) "
        f"min {m[:, 1].min():.2f} m -> target every time: {_verdict(ok_all)}"
    )
    axes[0].axhline(0.0, color="k", lw=1)
    axes[0].set_ylabel("distance to the end of segment AB, m (nav)")
    axes[0].set_xlabel("s since segment start")
    axes[0].legend()
    axes[1].set_ylabel("ground speed m/s (truth)")
    axes[1].set_xlabel("s since segment start")
    fig.tight_layout()
    fig.savefig(out / "braking.png", dpi=90)
    plt.close(fig)
    print(f"  plot: {out / 'braking.png'}")
    return ok_all


# ---------------------------------------------------------------------- landing
def bench_landing(out: Path, runs: int) -> bool:
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    vz_all: list[float] = []
    vh_all: list[float] = []
    ok_all = True
    for seed in range(runs):
        wind = (0.0, 0.0, 0.0) if seed % 2 == 0 else (3.0, 3.0, 0.0)
        f = SimFlight(seed=200 + seed, wind=wind)
        f.start_engine()
        up = takeoff(f, 15.0)
        st = hover(f, up.outputs[-1].hover_point, 40.0, up.integral, until_stable=True)
        here = f.state()
        target = LandingTarget(here.position[0] + 5.0, here.position[1] - 5.0, 0.0, here.heading)
        down = land(f, target, st.integral)
        vz, vh = touchdown_velocity(f, down.first_tick)
        vz_all.append(vz)
        vh_all.append(vh)
        ok = down.ok and vz <= 0.35 and vh <= 0.15
        ok_all &= ok
        t = np.array(f.log.time[down.first_tick :])
        tru = f.log.truth[down.first_tick :]
        axes[0].plot(t - t[0], [s.height_above_ground for s in tru], label=f"seed {200 + seed}")
        axes[1].plot(t - t[0], [s.velocity_enu[2] for s in tru])
    print(
        f"landing: {runs} runs (calm and 4.2 m/s wind alternating): touchdown vertical speed max "
        f"{max(vz_all):.3f} m/s mean {np.mean(vz_all):.3f} m/s, horizontal max {max(vh_all):.3f} "
        f"m/s mean {np.mean(vh_all):.3f} m/s -> target <= 0.35 / <= 0.15 m/s: {_verdict(ok_all)}"
    )
    axes[0].set_ylabel("skid height above ground m (truth)")
    axes[0].set_xlabel("s since landing engaged")
    axes[0].legend()
    axes[1].set_ylabel("vertical speed m/s (truth)")
    axes[1].set_xlabel("s since landing engaged")
    fig.tight_layout()
    fig.savefig(out / "landing.png", dpi=90)
    plt.close(fig)
    print(f"  plot: {out / 'landing.png'}")
    return ok_all


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("what", choices=("hover", "path", "latency", "braking", "landing", "all"))
    parser.add_argument("--out", type=Path, default=Path("out/control"))
    parser.add_argument("--runs", type=int, default=5, help="runs of braking and landing")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    benches: dict[str, Callable[[], bool]] = {
        "hover": lambda: bench_hover(args.out, args.seed),
        "path": lambda: bench_path(args.out, args.seed),
        "latency": lambda: bench_latency(args.out, args.seed),
        "braking": lambda: bench_braking(args.out, args.runs),
        "landing": lambda: bench_landing(args.out, args.runs),
    }
    chosen = list(benches) if args.what == "all" else [args.what]
    results = {name: benches[name]() for name in chosen}
    print("summary: " + ", ".join(f"{k} {_verdict(v)}" for k, v in results.items()))
    return 0 if all(results.values()) else 1


if __name__ == "__main__":
    raise SystemExit(main())
