"""RMAX flight model: JSBSim rigid body + Python rotor, flapping, drive train and fuselage drag.

JSBSim integrates the rigid body (rotating WGS84 Earth, gravity, atmosphere, wind, skid contact);
each 200 Hz step this class computes the rotor and airframe loads from the air-relative state and
writes them as body-frame force/moment components into the model's ``external_reactions``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import jsbsim

from hdrc3_base.errors import ConfigError
from sim.geodesy import GeodeticOrigin, LocalFrame
from sim.powertrain import Powertrain
from sim.rmax_params import RmaxParams
from sim.rotor import flap_step, ground_effect_factor, lag, rotor_loads
from sim.truth_state import TruthState

FT = 0.3048
"""Metres per foot."""
IN = 0.0254
"""Metres per inch."""
N_TO_LBF = 0.22480894387
NM_TO_LBFFT = 0.73756214928
SLUG_TO_KG = 14.5939029372
KG_TO_LBS = 2.20462262185
RHO_SLUGFT3_TO_KGM3 = 515.378818

MODEL_DIR = Path(__file__).resolve().parent / "jsbsim_models"
"""Directory holding ``rmax.xml``."""

WINCH_Z = 0.25
"""m, structural height of the payload hook's winch above the skid bottoms, on the shaft axis
(written into the model's ``hook`` force location at load)."""

TerrainHeight = Callable[[float, float], float]
"""``terrain_height(east, north) -> up`` in metres of the local ENU frame."""


def flat_terrain(east: float, north: float) -> float:
    """Flat ground at ENU height 0."""
    return 0.0


@dataclass(frozen=True, slots=True)
class ServoCommand:
    """Normalised servo positions the YACS (or a test) sends to the swashplate and tail rotor."""

    collective: float = 0.0
    """Main rotor collective, 0 (minimum pitch) .. 1 (maximum pitch)."""
    longitudinal: float = 0.0
    """Longitudinal cyclic, -1 .. 1, positive tilts the disc forward (nose down)."""
    lateral: float = 0.0
    """Lateral cyclic, -1 .. 1, positive tilts the disc right (roll right)."""
    pedal: float = 0.0
    """Tail rotor, -1 .. 1, positive yaws the nose right."""


@dataclass(frozen=True, slots=True)
class InitialPlacement:
    """Where an aircraft starts: on the ground (or ``height`` above it, level), engine off."""

    east: float = 0.0
    """m, local ENU."""
    north: float = 0.0
    """m, local ENU."""
    heading: float = 0.0
    """rad, clockwise from north."""
    height: float = 0.0
    """Skid bottoms above the terrain, m (0: standing on the ground)."""


@dataclass(frozen=True, slots=True)
class RigidBodyState:
    """What JSBSim integrates for one aircraft, in the units of its ``ic/`` properties.

    JSBSim's Python API has no state setter (``FGPropagate`` only reads); a state is restored
    by writing it as initial conditions and calling ``run_ic()``, which also restarts the
    multi-step integrators' histories (see ``sim/WORLD_SIM.md``, "Checkpoints", for the error).
    """

    latitude: float
    """Geodetic latitude, rad."""
    longitude: float
    """Longitude, rad."""
    altitude: float
    """Altitude of the CG above sea level, ft."""
    euler: tuple[float, float, float]
    """Roll, pitch, heading, rad."""
    velocity_ned: tuple[float, float, float]
    """CG velocity relative to the ground, ft/s, NED."""
    rates: tuple[float, float, float]
    """Body rates p, q, r relative to the Earth, rad/s."""
    force: tuple[float, float, float]
    """External body force of the last step, lbf (seeds the integrators' first derivative)."""
    moment: tuple[float, float, float]
    """External body moment of the last step, lbf ft."""


_IC = {
    "latitude": ("position/lat-geod-rad", "ic/lat-geod-rad"),
    "longitude": ("position/long-gc-rad", "ic/long-gc-rad"),
    "altitude": ("position/h-sl-ft", "ic/h-sl-ft"),  # ic/geod-alt-ft ignores writes
}
"""Scalar fields of RigidBodyState: (JSBSim property read, ``ic/`` property written)."""
_IC_VECTORS = {
    "euler": (
        ("attitude/phi-rad", "ic/phi-rad"),
        ("attitude/theta-rad", "ic/theta-rad"),
        ("attitude/psi-rad", "ic/psi-true-rad"),
    ),
    "velocity_ned": (
        ("velocities/v-north-fps", "ic/vn-fps"),
        ("velocities/v-east-fps", "ic/ve-fps"),
        ("velocities/v-down-fps", "ic/vd-fps"),
    ),
    "rates": (
        ("velocities/p-rad_sec", "ic/p-rad_sec"),
        ("velocities/q-rad_sec", "ic/q-rad_sec"),
        ("velocities/r-rad_sec", "ic/r-rad_sec"),
    ),
}
"""Vector fields of RigidBodyState read and written through properties."""
_HANDLES = "_fdm"
"""Attributes that belong to the JSBSim instance (``_fdm`` and every ``_n_*`` node handle)."""


def _clip(value: float, low: float, high: float) -> float:
    return low if value < low else high if value > high else value


class FlightModel:
    """One simulated RMAX, stepped at a fixed rate (200 Hz by default)."""

    def __init__(
        self,
        params: RmaxParams | None = None,
        *,
        placement: InitialPlacement | None = None,
        origin: tuple[float, float, float] = (58.4, 15.6, 0.0),
        terrain_height: TerrainHeight = flat_terrain,
        fuel: float | None = None,
        payload: float = 0.0,
        rate_hz: float = 200.0,
    ) -> None:
        """Load the JSBSim model and place the aircraft on the ground with the engine off.

        Args:
            params: Aircraft parameters (default: the RMAX of ``RmaxParams()``).
            placement: Start position and heading (default: ENU origin, heading north).
            origin: Geodetic origin of the local ENU frame (lat deg, lon deg, alt m).
            terrain_height: Ground height under a horizontal position, m.
            fuel: Fuel on board, kg (default: full tank).
            payload: Payload mass, kg.
            rate_hz: Step rate, Hz.

        """
        self.params = p = params or RmaxParams()
        place = placement or InitialPlacement()
        fuel_kg = p.fuel_capacity if fuel is None else fuel
        if not 0.0 <= fuel_kg <= p.fuel_capacity:
            raise ConfigError(f"fuel {fuel_kg} kg outside [0, {p.fuel_capacity}]")
        if not (math.isfinite(payload) and payload >= 0.0):
            raise ConfigError(f"payload must be a finite mass >= 0 kg, got {payload}")
        if not (math.isfinite(rate_hz) and rate_hz > 0.0):
            raise ConfigError(f"rate must be positive, got {rate_hz}")
        self.dt = 1.0 / rate_hz
        self._terrain = terrain_height
        self._frame = LocalFrame(GeodeticOrigin(*origin))
        self.powertrain = Powertrain(p, fuel_kg)
        self._payload = payload
        self._servo = ServoCommand()
        self.engine_switch = False
        """Engine switch as last set by the RC transmitter."""
        self.steps = 0
        self.flap_lon = 0.0
        """Tip-path-plane tilt forward relative to the shaft, rad."""
        self.flap_lat = 0.0
        """Tip-path-plane tilt right relative to the shaft, rad."""
        self.main_inflow = 0.0
        self.tail_inflow = 0.0
        self.main_thrust = 0.0
        """Last main rotor thrust, N."""
        self.main_power = 0.0
        """Last main rotor aerodynamic power, W."""
        self.tail_power = 0.0
        """Last tail rotor aerodynamic power, W."""
        self._sense = 1.0 if p.main_rotor_ccw else -1.0
        # state as of the last step (filled by _read_state)
        self.p = self.q = self.r = 0.0
        """Body rates p, q, r, rad/s (FRD)."""
        self.roll = self.pitch = self.heading = 0.0
        """Euler angles 3-2-1, rad."""
        self.position_enu = (0.0, 0.0, 0.0)
        """CG position, m, local ENU."""
        self.velocity_enu = (0.0, 0.0, 0.0)
        """CG velocity, m/s, local ENU."""
        self.height_above_ground = 0.0
        """Skid bottoms above the terrain below, m."""
        self.on_ground = True
        """True while the skids carry weight."""
        self._wind_ned = (0.0, 0.0, 0.0)
        self._hook_force = (0.0, 0.0, 0.0)
        self._fdm = self._load()
        self._bind_nodes()
        self._set_masses()
        self._place(place)
        self._read_state()

    # ------------------------------------------------------------------ setup
    def _load(self) -> jsbsim.FGFDMExec:
        root = str(MODEL_DIR)
        jsbsim.FGJSBBase().debug_lvl = 0  # type: ignore[no-untyped-call]  # silences the banner
        fdm = jsbsim.FGFDMExec(root_dir=root)
        fdm.set_debug_level(0)
        fdm.set_dt(self.dt)  # before load_model: filters and lags cache dt at load time
        if not fdm.load_model_with_paths("rmax", root, root, root, False):
            raise ConfigError(f"JSBSim could not load {root}/rmax.xml")
        return fdm

    def _place(self, place: InitialPlacement) -> None:
        fdm = self._fdm
        ground = self._terrain(place.east, place.north)
        fix = self._frame.to_geodetic(place.east, place.north, ground)
        lat, lon, alt = fix.latitude, fix.longitude, fix.altitude
        if not fdm.run_ic():  # first pass computes the mass balance (CG height with payload)
            raise ConfigError("JSBSim rejected the initial conditions")
        cg_alt = alt + place.height + self._n_cg_z.get_double_value() * IN + 0.005
        fdm["ic/lat-geod-deg"] = lat
        fdm["ic/long-gc-deg"] = lon
        fdm["ic/terrain-elevation-ft"] = alt / FT
        fdm["ic/h-sl-ft"] = cg_alt / FT
        fdm["ic/psi-true-deg"] = math.degrees(place.heading)
        fdm["ic/phi-deg"] = 0.0
        fdm["ic/theta-deg"] = 0.0
        for name in ("ic/u-fps", "ic/v-fps", "ic/w-fps", "ic/p-rad_sec", "ic/q-rad_sec"):
            fdm[name] = 0.0
        fdm["ic/r-rad_sec"] = 0.0
        if not fdm.run_ic():
            raise ConfigError("JSBSim rejected the initial conditions")

    def _bind_nodes(self) -> None:
        pm = self._fdm.get_property_manager()

        def node(name: str) -> jsbsim.FGPropertyNode:
            found = pm.get_node(name)
            if found is None:
                raise ConfigError(f"JSBSim property {name} missing from the RMAX model")
            return found

        self._n_uvw = tuple(node(f"velocities/{a}-aero-fps") for a in "uvw")
        self._n_pqr = tuple(node(f"velocities/{a}-rad_sec") for a in "pqr")
        self._n_euler = tuple(node(f"attitude/{a}-rad") for a in ("phi", "theta", "psi"))
        self._n_ned = tuple(node(f"velocities/v-{a}-fps") for a in ("north", "east", "down"))
        self._n_ecef = tuple(node(f"position/ecef-{a}-ft") for a in "xyz")
        self._n_alt = node("position/geod-alt-ft")
        self._n_rho = node("atmosphere/rho-slugs_ft3")
        self._n_terrain = node("position/terrain-elevation-asl-ft")
        self._n_gear_z = node("forces/fbz-gear-lbs")
        self._n_force = tuple(node(f"external_reactions/f{a}/magnitude") for a in "xyz")
        self._n_moment = tuple(node(f"external_reactions/m{a}/magnitude-lbsft") for a in "xyz")
        self._n_wind = tuple(node(f"atmosphere/wind-{a}-fps") for a in ("north", "east", "down"))
        self._n_fuel = node("inertia/pointmass-weight-lbs")
        self._n_payload = node("inertia/pointmass-weight-lbs[1]")
        self._n_total_f = tuple(node(f"forces/fb{a}-total-lbs") for a in "xyz")
        self._n_mass = node("inertia/mass-slugs")
        self._n_cg_x = node("inertia/cg-x-in")
        self._n_cg_z = node("inertia/cg-z-in")
        self._n_hook = tuple(node(f"external_reactions/hook/{a}") for a in "xyz")
        self._n_hook_force = node("external_reactions/hook/magnitude")
        node("external_reactions/hook/location-z-in").set_double_value(WINCH_Z / IN)

    def _set_masses(self) -> None:
        self._n_fuel.set_double_value(self.powertrain.fuel * KG_TO_LBS)
        self._n_payload.set_double_value(self._payload * KG_TO_LBS)

    # ------------------------------------------------------------ checkpoint
    def rigid_body(self) -> RigidBodyState:
        """JSBSim's state now (with the external loads of the last step)."""
        fdm = self._fdm

        def vector(values: list[float]) -> tuple[float, float, float]:
            return (values[0], values[1], values[2])

        values: dict[str, object] = {
            name: fdm.get_property_value(read) for name, (read, _) in _IC.items()
        }
        for name, props in _IC_VECTORS.items():
            values[name] = vector([fdm.get_property_value(read) for read, _ in props])
        values["force"] = vector([n.get_double_value() for n in self._n_force])
        values["moment"] = vector([n.get_double_value() for n in self._n_moment])
        return RigidBodyState(**values)  # type: ignore[arg-type]  # fields named by _IC tables

    def _restore_rigid_body(self, state: RigidBodyState) -> None:
        """Put JSBSim in ``state`` (ConfigError if it refuses)."""
        fdm = self._fdm
        if not fdm.run_ic():  # mass balance first, as in _place
            raise ConfigError("JSBSim rejected the initial conditions")
        east, north, up = self.position_enu  # as in _read_state: terrain below the CG
        # JSBSim keeps the altitude kind set last (above sea level or ground) when the terrain
        # or the latitude change: terrain first, the altitude after everything it depends on
        fdm["ic/terrain-elevation-ft"] = state.altitude - (up - self._terrain(east, north)) / FT
        for name, (_, write) in _IC.items():
            fdm[write] = getattr(state, name)
        for name, props in _IC_VECTORS.items():
            for (_, write), value in zip(props, getattr(state, name), strict=True):
                fdm[write] = value
        for nodes, values in ((self._n_force, state.force), (self._n_moment, state.moment)):
            for n, v in zip(nodes, values, strict=True):
                n.set_double_value(v)
        if not fdm.run_ic():
            raise ConfigError("JSBSim rejected the checkpointed state")

    def __getstate__(self) -> dict[str, object]:
        """Pickle support: Python state plus JSBSim's state as a RigidBodyState."""
        state = {
            k: v for k, v in self.__dict__.items() if k != _HANDLES and not k.startswith("_n_")
        }
        state["_rigid_body"] = self.rigid_body()
        return state

    def __setstate__(self, state: dict[str, object]) -> None:
        """Unpickle: a fresh JSBSim instance put into the pickled state."""
        body = state.pop("_rigid_body")
        assert isinstance(body, RigidBodyState)
        self.__dict__.update(state)
        self._fdm = self._load()
        self._bind_nodes()
        self._set_masses()
        for n, v in zip(self._n_wind, self._wind_ned, strict=True):
            n.set_double_value(v / FT)
        self.set_hook_force(self._hook_force)
        self._restore_rigid_body(body)
        self._read_state()

    # ---------------------------------------------------------------- inputs
    def set_servos(self, servo: ServoCommand) -> None:
        """Servo positions used from the next step on."""
        self._servo = servo

    @property
    def servos(self) -> ServoCommand:
        """Servo positions currently applied."""
        return self._servo

    def collective_pitch(self) -> float:
        """Main rotor blade pitch the current collective servo position gives, rad."""
        p = self.params
        return p.collective_min + _clip(self._servo.collective, 0.0, 1.0) * (
            p.collective_max - p.collective_min
        )

    def set_wind(
        self,
        mean_enu: tuple[float, float, float],
        gust_enu: tuple[float, float, float] = (0.0, 0.0, 0.0),
    ) -> None:
        """Velocity of the air mass (where it blows to), m/s ENU: mean plus gust."""
        east = mean_enu[0] + gust_enu[0]
        north = mean_enu[1] + gust_enu[1]
        down = -(mean_enu[2] + gust_enu[2])
        if not all(math.isfinite(v) for v in (east, north, down)):
            raise ConfigError(f"wind must be finite, got {mean_enu} + {gust_enu}")
        ned = (north, east, down)
        if ned != self._wind_ned:
            self._wind_ned = ned
            for n, v in zip(self._n_wind, ned, strict=True):
                n.set_double_value(v / FT)

    def set_payload(self, mass: float) -> None:
        """Change the carried payload, kg (pick-up or release)."""
        if not (math.isfinite(mass) and mass >= 0.0):
            raise ConfigError(f"payload must be a finite mass >= 0 kg, got {mass}")
        self._payload = mass
        self._set_masses()

    @property
    def payload(self) -> float:
        """Carried payload, kg."""
        return self._payload

    def set_hook_force(self, force_enu: tuple[float, float, float]) -> None:
        """Pull of the payload hook's cable on the winch, N ENU, from the next step on."""
        east, north, up = force_enu
        magnitude = math.sqrt(east * east + north * north + up * up)
        self._hook_force = force_enu
        if magnitude == 0.0:
            self._n_hook_force.set_double_value(0.0)
            return
        nx, ny, nz = self._n_hook
        nx.set_double_value(north / magnitude)
        ny.set_double_value(east / magnitude)
        nz.set_double_value(-up / magnitude)
        self._n_hook_force.set_double_value(magnitude * N_TO_LBF)

    @property
    def hook_force(self) -> tuple[float, float, float]:
        """Cable pull on the winch applied in the next step, N ENU."""
        return self._hook_force

    def hook_anchor(self) -> tuple[float, float, float]:
        """Where the winch cable leaves the fuselage, m local ENU."""
        # structural (x aft, z up, inches) offset from the CG, turned into body FRD metres
        fwd = -(0.0 - self._n_cg_x.get_double_value()) * IN
        down = self._n_cg_z.get_double_value() * IN - WINCH_Z
        cr, sr = math.cos(self.roll), math.sin(self.roll)
        cp, sp = math.cos(self.pitch), math.sin(self.pitch)
        ch, sh = math.cos(self.heading), math.sin(self.heading)
        # body FRD -> NED for 3-2-1 Euler angles, applied to (fwd, 0, down)
        north = ch * cp * fwd + (ch * sp * cr + sh * sr) * down
        east = sh * cp * fwd + (sh * sp * cr - ch * sr) * down
        d = -sp * fwd + cp * cr * down
        e0, n0, u0 = self.position_enu
        return (e0 + east, n0 + north, u0 - d)

    # ------------------------------------------------------------------ step
    def step(self) -> None:
        """Advance the aircraft by one step of ``dt``."""
        p = self.params
        dt = self.dt
        servo = self._servo
        nu, nv, nw = self._n_uvw
        u = nu.get_double_value() * FT
        v = nv.get_double_value() * FT
        w = nw.get_double_value() * FT
        pr, qr, rr = self.p, self.q, self.r
        rho = self._n_rho.get_double_value() * RHO_SLUGFT3_TO_KGM3
        omega = self.powertrain.omega
        sense = self._sense

        # --- main rotor: thrust along the tilted tip-path-plane normal
        sx = math.sin(self.flap_lon)
        sy = math.sin(self.flap_lat)
        nz = -math.sqrt(max(0.0, 1.0 - sx * sx - sy * sy))
        h = p.hub_height
        hu = u - qr * h  # air-relative hub velocity: V + omega x (0, 0, -h)
        hv = v + pr * h
        climb = hu * sx + hv * sy + w * nz
        inplane = math.sqrt(max(0.0, hu * hu + hv * hv + w * w - climb * climb))
        pitch = self.collective_pitch()
        hub_above_ground = self.height_above_ground + p.skid_height + h
        ground = ground_effect_factor(hub_above_ground, p.main_rotor.radius)
        main = rotor_loads(
            p.main_rotor, pitch, omega, rho, inplane, climb, self.main_inflow, ground
        )
        thrust = main.thrust
        fx = thrust * sx
        fy = thrust * sy
        fz = thrust * nz
        mx = h * fy + p.hub_stiffness * self.flap_lat
        my = -h * fx - p.hub_stiffness * self.flap_lon
        mz = sense * main.torque

        # --- tail rotor: thrust along +y (CCW main rotor) opposing the main rotor torque
        omega_t = omega * p.tail_gear_ratio
        tv = v - rr * p.tail_arm + pr * p.tail_height
        tu = u - qr * p.tail_height
        tw = w + qr * p.tail_arm
        mid = 0.5 * (p.tail_pitch_max + p.tail_pitch_min)
        half = 0.5 * (p.tail_pitch_max - p.tail_pitch_min)
        # more tail thrust turns the nose against the main rotor torque: left for CCW, right for CW
        tail_pitch = mid - sense * _clip(servo.pedal, -1.0, 1.0) * half
        tail = rotor_loads(
            p.tail_rotor,
            tail_pitch,
            omega_t,
            rho,
            math.sqrt(tu * tu + tw * tw),
            sense * tv,
            self.tail_inflow,
        )
        fty = sense * tail.thrust
        fy += fty
        mx += p.tail_height * fty
        mz -= p.tail_arm * fty

        # --- fuselage drag at the CG and vertical fin behind it
        k = 0.5 * rho
        fx -= k * p.drag_area_x * u * abs(u)
        fy -= k * p.drag_area_y * v * abs(v)
        fz -= k * p.drag_area_z * w * abs(w)
        fin_v = v - rr * p.fin_arm
        fin = -k * p.fin_area * fin_v * abs(fin_v)
        fy += fin
        mz -= p.fin_arm * fin

        nf = self._n_force
        nf[0].set_double_value(fx * N_TO_LBF)
        nf[1].set_double_value(fy * N_TO_LBF)
        nf[2].set_double_value(fz * N_TO_LBF)
        nm = self._n_moment
        nm[0].set_double_value(mx * NM_TO_LBFFT)
        nm[1].set_double_value(my * NM_TO_LBFFT)
        nm[2].set_double_value(mz * NM_TO_LBFFT)
        self._fdm.run()
        self.steps += 1

        # --- rotor states: inflow lag, flapping lag with blow-back, drive train
        tip = omega * p.main_rotor.radius
        mu_u = hu / tip if tip > 1.0 else 0.0
        mu_v = hv / tip if tip > 1.0 else 0.0
        back = p.blowback_gain * (4.0 / 3.0 * pitch - self.main_inflow) * 2.0
        tau_f = p.flap_time_constant
        demand_lon = _clip(servo.longitudinal, -1.0, 1.0) * p.cyclic_max - back * mu_u
        demand_lat = _clip(servo.lateral, -1.0, 1.0) * p.cyclic_max - back * mu_v
        self.flap_lon = flap_step(self.flap_lon, demand_lon, qr, dt, tau_f)
        self.flap_lat = flap_step(self.flap_lat, demand_lat, -pr, dt, tau_f)
        tau_min = p.min_inflow_time_constant
        self.main_inflow = lag(
            self.main_inflow, main.inflow_target, dt, max(tau_min, main.inflow_time_constant)
        )
        self.tail_inflow = lag(
            self.tail_inflow, tail.inflow_target, dt, max(tau_min, tail.inflow_time_constant)
        )
        self.main_thrust = thrust
        self.main_power = main.power
        self.tail_power = tail.power
        load = (main.power + tail.power) / omega if omega > 1.0 else 0.0
        self.powertrain.step(dt, self.engine_switch, load)
        if self.powertrain.running:
            self._n_fuel.set_double_value(self.powertrain.fuel * KG_TO_LBS)
        self._read_state()

    def _read_state(self) -> None:
        """Cache the state the rotor model and the YACS read next step; follow the terrain."""
        # explicit reads: generator expressions cost more than the JSBSim calls themselves
        np_, nq, nr = self._n_pqr
        self.p = np_.get_double_value()
        self.q = nq.get_double_value()
        self.r = nr.get_double_value()
        nphi, ntheta, npsi = self._n_euler
        self.roll = nphi.get_double_value()
        self.pitch = ntheta.get_double_value()
        self.heading = npsi.get_double_value()
        nn, ne, nd = self._n_ned
        self.velocity_enu = (
            ne.get_double_value() * FT,
            nn.get_double_value() * FT,
            -nd.get_double_value() * FT,
        )
        nx, ny, nz = self._n_ecef
        x = nx.get_double_value() * FT
        y = ny.get_double_value() * FT
        z = nz.get_double_value() * FT
        east, north, up = self._frame.from_ecef(x, y, z)
        self.position_enu = (east, north, up)
        ground = self._terrain(east, north)
        # the local vertical equals the ENU up axis to ~1e-3 rad over a few km
        alt = self._n_alt.get_double_value() * FT
        self._n_terrain.set_double_value((alt - (up - ground)) / FT)
        # skid bottoms are at structural z = 0: the CG sits cg-z above them (moves with payload)
        self.height_above_ground = up - ground - self._n_cg_z.get_double_value() * IN
        self.on_ground = self._n_gear_z.get_double_value() < -0.5

    # ---------------------------------------------------------------- output
    @property
    def time(self) -> float:
        """Simulated time since start, s."""
        return self.steps * self.dt

    @property
    def mass(self) -> float:
        """Current total mass, kg (empty + fuel + payload)."""
        return self.params.empty_mass + self.powertrain.fuel + self._payload

    def truth(self) -> TruthState:
        """Exact state now."""
        mass_slug = self._n_mass.get_double_value()
        sf = tuple(n.get_double_value() / mass_slug * FT for n in self._n_total_f)
        heading = self.heading % (2.0 * math.pi)
        return TruthState(
            time=self.time,
            position_enu=self.position_enu,
            velocity_enu=self.velocity_enu,
            roll=self.roll,
            pitch=self.pitch,
            heading=heading,
            body_rates=(self.p, self.q, self.r),
            specific_force_body=(sf[0], sf[1], sf[2]),
            rotor_rpm=self.powertrain.omega * 60.0 / (2.0 * math.pi),
            engine_running=self.powertrain.running,
            on_ground=self.on_ground,
            height_above_ground=self.height_above_ground,
            mass=self.mass,
        )
