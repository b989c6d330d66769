"""Benchmark: HCSM macro-step time for a model the size of the RMAX PFC set.

The chapter's interpreter ran a 200 us worst-case macro step every 20 ms (1.06 GHz Celeron M).
This generates a synthetic model with the shape of Figure 12 -- 15 automata, nested superstates,
a 7-region concurrent container, ~200 events -- drives it like the 50 Hz PFC loop (a pulse every
step, an external event in some steps, guards on conditions that change) and reports the median,
p99 and worst macro step; then the same with a burst of 20 external events per step.

Run: .venv/bin/python bench/hcsm_step.py [--steps N] [--write-model PATH]
"""

from __future__ import annotations

import argparse
import gc
import random
import statistics
import time
from pathlib import Path

from hdrc3_hcsm.interpreter import Interpreter, StepStatus
from hdrc3_hcsm.loader import load_text
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.trace import TraceRecorder

RING = 8  # states per automaton ring
EVENTS_PER_AUTOMATON = 13
# name, label, superstates {ring index: regions}
AUTOMATA: list[tuple[str, str, dict[int, list[str]]]] = [
    ("Root", "A", {1: ["Run"]}),
    (
        "Run",
        "B",
        {
            1: [
                "Power-Switch",
                "Sync",
                "Sync-DRC",
                "Auto-Switch",
                "Control-Mode",
                "Visual-Navigation",
                "User-Interface",
            ]
        },
    ),
    ("Power-Switch", "C", {}),
    ("Sync", "D", {}),
    ("Sync-DRC", "E", {}),
    ("Auto-Switch", "F", {2: ["Mode-Switch"]}),
    ("Control-Mode", "G", {}),
    ("Visual-Navigation", "H", {}),
    ("User-Interface", "I", {3: ["UI-Timer"]}),
    ("UI-Timer", "J", {}),
    ("Mode-Switch", "K", {2: ["Traj3D"], 4: ["Landing"], 5: ["Traj3D-Flyto"], 6: ["Track"]}),
    ("Traj3D", "L", {}),
    ("Landing", "M", {}),
    ("Traj3D-Flyto", "N", {}),
    ("Track", "O", {}),
]


def generate_model() -> str:
    """Generate the synthetic PFC-sized model as .hcsm text."""
    lines = ["model Synthetic-PFC on PFC;", "computers PFC, PPC, DRC;"]
    ident = 1
    for name, _, _ in AUTOMATA:
        for e in range(EVENTS_PER_AUTOMATON):
            lines.append(f"event {name}-E{e}-EV = {ident} from DRC;")
            ident += 1
        lines.append(f"event {name}-Out-EV = {ident} to DRC;")
        ident += 1
        lines.append(f"condition {name}-C0-CO, {name}-C1-CO;")
        lines.append(f"flag {name}-F0-AC, {name}-F1-AC;")
        lines.append(f"slot {name}-D0-DO[64];")
    lines.append("root Root;")
    for k, (name, label, supers) in enumerate(AUTOMATA):
        nxt = AUTOMATA[(k + 1) % len(AUTOMATA)][0] if k + 1 < len(AUTOMATA) else None
        lines.append(f"automaton {label} {name} {{")
        for i in range(RING):
            st = f"{name}-S{i}-ST"
            if i == 0:
                lines.append(f"  init {st};")
            elif i in supers:
                lines.append(f"  super {st} = {' | '.join(supers[i])};")
            else:
                lines.append(f"  state {st};")
        n = 1
        for i in range(RING):
            src, dst = f"{name}-S{i}-ST", f"{name}-S{(i + 1) % RING}-ST"
            actions = [f"SET {name}-F0-AC"]
            if nxt is not None and i % 2 == 0:
                # Chains of internal events (acyclic: only to the next automaton) = micro steps.
                actions.append(f"SEND {nxt}-E{i}-EV data cache")
            if i % 3 == 0:
                actions += [f"GET {name}-D0-DO", f"PUT {name}-D0-DO"]
            if i == RING - 1:
                actions.append(f"SEND {name}-Out-EV to DRC")
            trig = f"{name}-E{i}-EV"
            lines.append(f"  {label}.{n}: {src} -> {dst} on {trig} / {', '.join(actions)};")
            n += 1
            if i in supers:
                continue  # superstates are left only by their (rare) event, not by pulses
            # Guarded pulse transitions, like Hover-Stable-CO in Mode Switch.
            guard = f"[{name}-C0-CO AND NOT {name}-C1-CO]"
            lines.append(f"  {label}.{n}: {src} -> {dst} on pulse {guard} / SET {name}-F1-AC;")
            n += 1
        for e in range(RING, EVENTS_PER_AUTOMATON):
            st = f"{name}-S{e % RING}-ST"
            lines.append(f"  {label}.{n}: {st} -> {st} on {name}-E{e}-EV / SET {name}-F1-AC;")
            n += 1
        lines.append("}")
    return "\n".join(lines) + "\n"


# Events that leave a superstate. Like the real PFC set, the upper levels (Root, Run, the
# 7-region container) stay active; only Mode Switch changes its nested mode automaton now and then.
LEAVE_SUPER = {f"{name}-E{i}-EV" for name, _, supers in AUTOMATA for i in supers}
MODE_CHANGE = {e for e in LEAVE_SUPER if e.startswith("Mode-Switch-")}


def enabled_events(configuration: tuple[str, ...]) -> list[str]:
    """Ring events that trigger a transition in the active configuration (outside the timing)."""
    out = []
    for entry in configuration:
        path, state = entry.rsplit(":", 1)
        name = path.rsplit("/", 1)[-1].split("[")[0]
        ring = int(state.removeprefix(f"{name}-S").removesuffix("-ST"))
        event = f"{name}-E{ring}-EV"
        if event not in LEAVE_SUPER or event in MODE_CHANGE:
            out.append(event)
    return out


def percentile(sorted_values: list[float], q: float) -> float:
    """Nearest-rank percentile of an ascending list."""
    rank = max(0, min(len(sorted_values) - 1, round(q / 100 * len(sorted_values)) - 1))
    return sorted_values[rank]


def run(
    steps: int, burst: int, seed: int, traced: bool = False
) -> tuple[list[float], list[float], int, int, int, float]:
    """Run ``steps`` macro steps.

    Returns wall-clock and thread-CPU step times (us), transitions, micro steps, livelocks and
    the mean number of active machines. The CPU time excludes preemption by other
    processes on this shared machine; the wall-clock time includes it.
    """
    model = compile_model(load_text(generate_model(), "synthetic.hcsm"))
    rng = random.Random(seed)
    cond_values = {c: False for c in model.conditions}
    conditions = {c: (lambda c=c: cond_values[c]) for c in model.conditions}
    # With tracing, every micro step also builds a record with the active configuration.
    interp = Interpreter(model, conditions, trace=TraceRecorder(capacity=1000) if traced else None)
    events = [
        n for n in model.events.names[2:] if not n.endswith("-Out-EV") and n not in LEAVE_SUPER
    ]
    cond_names = sorted(cond_values)
    # Enter the nested configuration first (Root -> Run -> 7 regions) like system start-up.
    for name in ("Root-E0-EV", "Run-E0-EV", "Auto-Switch-E0-EV", "Auto-Switch-E1-EV"):
        interp.post_external(name)
        interp.execute(0.0)
    times: list[float] = []
    cpu: list[float] = []
    livelocks = 0
    active_total = 0
    gc.collect()
    gc.disable()  # Python's cycle collector is not part of the interpreter's cost
    try:
        for k in range(steps):
            # Conditions change slowly (sensor-derived), some guards become true now and then.
            for _ in range(2):
                c = rng.choice(cond_names)
                cond_values[c] = rng.random() < 0.3
            n_ext = burst if burst else (1 if rng.random() < 0.3 else 0)
            configuration = interp.configuration()
            active_total += len(configuration)
            enabled = enabled_events(configuration)
            for _ in range(n_ext):
                # Mostly events the active states expect (the DRC answers the PFC), some not.
                pool = enabled if rng.random() < 0.8 else events
                interp.post_external(rng.choice(pool), b"payload-0123456789")
            c0 = time.thread_time()
            t0 = time.perf_counter()
            result = interp.execute(k * 0.02)
            times.append((time.perf_counter() - t0) * 1e6)
            cpu.append((time.thread_time() - c0) * 1e6)
            livelocks += result.status is StepStatus.LIVELOCK
            interp.take_outbox()
            interp.flags.clear()
    finally:
        gc.enable()
    active = active_total / steps
    return times, cpu, interp.stats.transitions, interp.stats.micro_steps, livelocks, active


def report(
    label: str, steps: int, burst: int, seed: int, traced: bool = False
) -> tuple[dict[str, float], list[float]]:
    times, cpu, transitions, micro, livelocks, active = run(steps, burst, seed, traced)
    ordered = sorted(times)
    figures = {
        "median_us": statistics.median(ordered),
        "p99_us": percentile(ordered, 99),
        "max_us": ordered[-1],
        "transitions_per_step": transitions / steps,
        "micro_steps_per_step": micro / steps,
    }
    print(
        f"{label:<28} steps={steps:>6}  median={figures['median_us']:7.1f} us  "
        f"p99={figures['p99_us']:7.1f} us  max={figures['max_us']:8.1f} us  "
        f"transitions/step={figures['transitions_per_step']:5.2f}  "
        f"micro/step={figures['micro_steps_per_step']:5.2f}  livelocks={livelocks}  "
        f"mean active machines={active:.1f}"
    )
    over = sum(t > 200 for t in times)
    cpu_sorted = sorted(cpu)
    print(
        f"{'':<28} steps over 200 us (wall): {over} of {steps};  thread CPU time: "
        f"median={statistics.median(cpu_sorted):.1f} us  p99={percentile(cpu_sorted, 99):.1f} us  "
        f"p99.9={percentile(cpu_sorted, 99.9):.1f} us  max={cpu_sorted[-1]:.1f} us"
    )
    return figures, times


def plot(path: Path, runs: dict[str, list[float]]) -> None:
    """Histogram of macro-step times (log scale), one series per run."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for label, times in runs.items():
        ax.hist(times, bins=200, range=(0, 250), histtype="step", label=label)
    ax.axvline(200, color="red", linestyle="--", label="200 us budget")
    ax.set_yscale("log")
    ax.set_xlabel("macro step [us]")
    ax.set_ylabel("steps")
    ax.legend()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    print(f"wrote {path}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--write-model", type=Path, help="also write the synthetic .hcsm here")
    parser.add_argument("--plot", type=Path, help="write a PNG histogram of step times here")
    args = parser.parse_args()
    text = generate_model()
    if args.write_model:
        args.write_model.write_text(text, encoding="utf-8")
    model = compile_model(load_text(text, "synthetic.hcsm"))
    n_trans = sum(
        len(ts) for a in model.automata.values() for row in a.table for ts in row.values()
    )
    print(
        f"model: {len(model.automata)} automata, {len(model.events.names) - 2} events, "
        f"{n_trans} transitions"
    )
    normal, normal_times = report("50 Hz loop (0-1 ext/step)", args.steps, 0, args.seed)
    burst, burst_times = report("burst of 20 external", args.steps // 4, 20, args.seed)
    report("0-1 ext/step, trace on", args.steps // 4, 0, args.seed, traced=True)
    ok = normal["p99_us"] <= 200 and normal["median_us"] <= 50
    print(f"target p99 <= 200 us and median <= 50 us: {'MET' if ok else 'NOT MET'}")
    print(f"burst worst case: {burst['max_us']:.1f} us (p99 {burst['p99_us']:.1f} us)")
    if args.plot:
        plot(args.plot, {"0-1 ext/step": normal_times, "burst of 20": burst_times})


if __name__ == "__main__":
    main()
