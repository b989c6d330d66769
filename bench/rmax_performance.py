"""Flight performance of the simulated RMAX against momentum theory, and its level-speed envelope.

Prints, for several take-off masses: trimmed hover thrust, main-rotor power and collective versus
momentum theory (ideal power T^1.5/sqrt(2 rho A), the model's figure of merit, and the closed-form
blade-element/momentum collective); then the power needed in level flight at increasing speeds
and the highest speed the velocity hold reached while holding altitude.

Run: .venv/bin/python bench/rmax_performance.py [--png out/rmax_power.png]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from sim.aircraft import Aircraft
from sim.rc_transmitter import FlightModeSwitch
from sim.rotor import figure_of_merit, hover_collective, momentum_hover_power
from sim.velocity_hold import VelocityHold, fly

RHO = 1.225
G = 9.80665


def airborne(payload: float) -> tuple[Aircraft, VelocityHold]:
    ac = Aircraft(payload=payload)
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(10.0)
    hold = VelocityHold()
    fly(ac, hold, 10.0, climb_rate=1.5)
    fly(ac, hold, 15.0)
    return ac, hold


def averaged(ac: Aircraft, seconds: float) -> tuple[float, float, float, float]:
    """Mean main thrust (N), main power (W), total shaft power (W), collective (rad)."""
    m = ac.model
    n = round(seconds / m.dt)
    thrust = power = total = pitch = 0.0
    for _ in range(n):
        ac.step()
        thrust += m.main_thrust / n
        power += m.main_power / n
        total += (m.main_power + m.tail_power) / n
        pitch += m.collective_pitch() / n
    return thrust, power, total, pitch


def hover_table() -> None:
    print("hover out of ground effect (>= 9 m), ISA sea level")
    print(
        f"{'mass kg':>8}{'T N':>8}{'P_main W':>10}{'P_ideal W':>10}{'FM':>6}"
        f"{'P_ideal/FM':>11}{'ratio':>7}{'coll deg':>9}{'BEMT deg':>9}{'P_shaft W':>10}"
    )
    for payload in (0.0, 15.0, 29.6):
        ac, _ = airborne(payload)
        p = ac.model.params
        thrust, power, total, pitch = averaged(ac, 2.0)
        tip = p.omega * p.main_rotor.radius
        ct = thrust / (RHO * p.main_rotor.disc_area * tip * tip)
        ideal = momentum_hover_power(thrust, RHO, p.main_rotor.disc_area)
        fm = figure_of_merit(p.main_rotor, ct)
        theory = hover_collective(p.main_rotor, ct)
        print(
            f"{ac.truth().mass:>8.1f}{thrust:>8.0f}{power:>10.0f}{ideal:>10.0f}{fm:>6.2f}"
            f"{ideal / fm:>11.0f}{power / (ideal / fm):>7.3f}{math.degrees(pitch):>9.2f}"
            f"{math.degrees(theory):>9.2f}{total:>10.0f}"
        )


def speed_sweep(png: Path | None) -> None:
    ac, hold = airborne(15.0)
    print(f"\nlevel flight, mass {ac.truth().mass:.1f} kg")
    print(f"{'target m/s':>11}{'reached m/s':>12}{'pitch deg':>10}{'P_shaft W':>10}{'held':>6}")
    speeds: list[float] = []
    powers: list[float] = []
    best = 0.0
    for target in (0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0):
        alt = ac.truth().position_enu[2]
        s = fly(ac, hold, 25.0, velocity_en=(0.0, target))
        _, _, total, _ = averaged(ac, 1.0)
        s = ac.truth()
        omega_ok = ac.model.powertrain.omega > 0.97 * ac.model.params.omega
        held = abs(s.velocity_enu[1] - target) < 0.5 and abs(s.position_enu[2] - alt) < 3.0
        held = held and omega_ok
        print(
            f"{target:>11.1f}{s.velocity_enu[1]:>12.2f}{math.degrees(s.pitch):>10.2f}"
            f"{total:>10.0f}{'yes' if held else 'no':>6}"
        )
        if not held:
            break
        best = target
        speeds.append(s.velocity_enu[1])
        powers.append(total)
    print(f"highest level speed held: {best:.0f} m/s")
    if png is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        png.parent.mkdir(parents=True, exist_ok=True)
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(speeds, [w / 1000.0 for w in powers], "o-")
        ax.set_xlabel("airspeed, m/s")
        ax.set_ylabel("rotor shaft power, kW")
        ax.set_title("Simulated RMAX level-flight power")
        ax.grid(True)
        fig.savefig(png, dpi=100)
        print(f"wrote {png}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--png", type=Path, default=None, help="write the power curve here")
    args = parser.parse_args()
    hover_table()
    speed_sweep(args.png)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
