"""The planar plant FMU beside the independent single-track model "ST" of the CommonRoad vehicle
models (PyPI ``commonroad-vehicle-models``; Althoff and Wuersching, "CommonRoad: Vehicle Models",
2020a, section 7), with the same parameters, driven side by side.

Both models get the same road-wheel angle command every 10 ms communication step. The FMU runs
with its steering lag set to 0 (``steering_time_constant``); its steering rate limit is the
ST model's (0.4 rad/s, CommonRoad vehicle 2), and the ST model's steering-velocity input is
set every 1 ms so that it moves the wheel as fast as the rate limit lets it, as the FMU does.
The FMU holds its speed with a PI throttle controller; the ST model (whose input is the
longitudinal acceleration) gets the FMU's mean acceleration of each step, so both move at the
same speed and only their lateral and yaw dynamics differ. The ST state is integrated with the
classical Runge-Kutta scheme at 1 ms.

ST parameters: CommonRoad vehicle 2 (BMW 320i) with the FMU's mass, axle distances, yaw inertia
and centre-of-gravity height (read from the FMU's model description), so both describe one car.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
from fmpy import read_model_description
from vehiclemodels.parameters_vehicle2 import parameters_vehicle2
from vehiclemodels.vehicle_dynamics_st import vehicle_dynamics_st

from cosim.world.path_following import Path as PolylinePath
from cosim.world.path_following import Pose, PurePursuitParams, pursuit
from tests.fmu.plant_runner import initialise, open_plant

COMM_STEP_S = 0.01
ST_STEP_S = 0.001
G_MPS2 = 9.80665
PLANT_OUTPUTS = ("x", "y", "yaw", "yaw_rate", "ay", "v", "vy", "delta", "a")
#: (time, pose, speed) -> road-wheel angle command, rad
SteerCommand = Callable[[float, Pose, float], float]
RELEASED = {"throttle": 0.0, "brake": 0.0}


def plant_defaults(fmu: Path) -> dict[str, float]:
    """The FMU's parameter start values by name."""
    md = read_model_description(str(fmu))
    return {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter" and v.type != "Boolean"}


def st_parameters(defaults: dict[str, float]):
    """CommonRoad vehicle 2 with the plant's mass, geometry, yaw inertia and CG height."""
    p = parameters_vehicle2()
    p.m = defaults["mass"]
    p.a = defaults["cg_to_front_axle"]
    p.b = defaults["wheelbase"] - defaults["cg_to_front_axle"]
    p.I_z = defaults["yaw_inertia"]
    p.h_s = defaults["cg_height"]  # the ST code's load-transfer height
    # the ST model's axle cornering stiffness is mu C_S F_z = -p_ky1 F_z: the plant's per-load stiffness
    if not math.isclose(-p.tire.p_ky1, defaults["tyre_cornering_stiffness"], rel_tol=1e-12):
        raise ValueError(f"tyre_cornering_stiffness {defaults['tyre_cornering_stiffness']} != -p_ky1 {-p.tire.p_ky1}")
    if not (p.steering.max == defaults["steering_angle_max"] and p.steering.v_max == defaults["steering_rate_max"]):
        raise ValueError("the plant's steering limits differ from CommonRoad vehicle 2's")
    return p


class StModel:
    """The CommonRoad ST model, state [x, y, delta, v, psi, psi_dot, beta], integrated with RK4."""

    def __init__(self, params, v0_mps: float) -> None:
        self.p = params
        self.x = np.array([0.0, 0.0, 0.0, v0_mps, 0.0, 0.0, 0.0])
        self.ay_mps2 = 0.0

    def _f(self, x: np.ndarray, u: list[float]) -> np.ndarray:
        return np.array(vehicle_dynamics_st(x, u, self.p))

    def step(self, h_s: float, delta_cmd: float, accel_mps2: float) -> None:
        for _ in range(int(round(h_s / ST_STEP_S))):
            rate = (delta_cmd - self.x[2]) / ST_STEP_S
            u = [min(max(rate, self.p.steering.v_min), self.p.steering.v_max), accel_mps2]
            k1 = self._f(self.x, u)
            k2 = self._f(self.x + 0.5 * ST_STEP_S * k1, u)
            k3 = self._f(self.x + 0.5 * ST_STEP_S * k2, u)
            k4 = self._f(self.x + ST_STEP_S * k3, u)
            self.x = self.x + ST_STEP_S / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        f = self._f(self.x, u)
        v, beta = self.x[3], self.x[6]
        # vehicle-frame lateral acceleration: v (beta' + psi') across the velocity, plus v' sin(beta)
        self.ay_mps2 = v * (f[6] + self.x[5]) * math.cos(beta) + accel_mps2 * math.sin(beta)

    def pose(self) -> Pose:
        return Pose(float(self.x[0]), float(self.x[1]), float(self.x[4]))

    def record(self) -> dict[str, float]:
        x = self.x
        return {"x": x[0], "y": x[1], "yaw": x[4], "yaw_rate": x[5], "ay": self.ay_mps2, "v": x[3],
                "vy": x[3] * math.sin(x[6]), "delta": x[2]}


@dataclass(frozen=True)
class Manoeuvre:
    """Speed held at ``speed_mps`` from the start until x reaches ``release_x_m`` (then the throttle
    is released, as ISO 3888-2 asks at the entry gate); ``steer`` commands the road wheel."""

    speed_mps: float
    stop_s: float
    steer: SteerCommand
    release_x_m: float = math.inf


class SpeedHold:
    """PI throttle / brake controller holding the FMU at a speed (a test driver's right foot)."""

    KP, KI = 0.4, 0.4  # per m/s, per m

    def __init__(self, speed_mps: float, defaults: dict[str, float]) -> None:
        g = 9.80665
        resist = (0.5 * defaults["air_density"] * defaults["drag_area"] * speed_mps**2
                  + defaults["rolling_resistance"] * defaults["mass"] * g)
        self.target, self.feed, self.integral = speed_mps, resist / defaults["max_drive_force"], 0.0

    def command(self, v_mps: float, h_s: float) -> dict[str, float]:
        error = self.target - v_mps
        self.integral += error * h_s
        u = self.feed + self.KP * error + self.KI * self.integral
        return {"throttle": min(max(u, 0.0), 1.0), "brake": min(max(-u, 0.0), 1.0)}


def run_side_by_side(fmu: Path, manoeuvre: Manoeuvre) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Run both models through ``manoeuvre``; returns (plant, ST) arrays keyed "t" and each output."""
    defaults = plant_defaults(fmu)
    ratio = defaults["steering_ratio"]
    st = StModel(st_parameters(defaults), manoeuvre.speed_mps)
    hold = SpeedHold(manoeuvre.speed_mps, defaults)
    handle = open_plant(fmu, 2)
    plant_rows, st_rows = [], []
    try:
        initialise(handle, {"v0": manoeuvre.speed_mps, "steering_time_constant": 0.0})
        out = dict(zip(PLANT_OUTPUTS, handle.get(*PLANT_OUTPUTS)))
        for k in range(int(round(manoeuvre.stop_s / COMM_STEP_S))):
            t = k * COMM_STEP_S
            pose = Pose(out["x"], out["y"], out["yaw"])
            delta_plant = manoeuvre.steer(t, pose, out["v"])
            delta_st = manoeuvre.steer(t, st.pose(), float(st.x[3]))
            pedals = hold.command(out["v"], COMM_STEP_S) if out["x"] < manoeuvre.release_x_m else RELEASED
            handle.set(steering_wheel_angle=ratio * delta_plant, **pedals)
            v_before = out["v"]
            handle.slave.doStep(t, COMM_STEP_S)
            out = dict(zip(PLANT_OUTPUTS, handle.get(*PLANT_OUTPUTS)))
            st.step(COMM_STEP_S, delta_st, (out["v"] - v_before) / COMM_STEP_S)
            plant_rows.append([t + COMM_STEP_S, *(out[n] for n in PLANT_OUTPUTS)])
            st_rows.append([t + COMM_STEP_S, *(st.record().get(n, np.nan) for n in PLANT_OUTPUTS)])
        handle.slave.terminate()
    finally:
        handle.slave.freeInstance()
    columns = ("t", *PLANT_OUTPUTS)
    plant, ref = np.array(plant_rows), np.array(st_rows)
    return ({c: plant[:, i] for i, c in enumerate(columns)}, {c: ref[:, i] for i, c in enumerate(columns)})


# -- ISO 4138: steady-state circular driving, constant steering-wheel angle -----------------------
def steady_state(fmu: Path, ay_g: float, radius_m: float = 100.0, stop_s: float = 5.0) -> dict[str, float]:
    """Hold the kinematic steering angle of ``radius_m`` at the speed of ``ay_g`` on that circle
    (ISO 4138, constant steering-wheel angle method); means over the last second of each model:
    yaw rate, lateral acceleration, sideslip and the rear slip angle."""
    defaults = plant_defaults(fmu)
    wheelbase, lr = defaults["wheelbase"], defaults["wheelbase"] - defaults["cg_to_front_axle"]
    speed = math.sqrt(ay_g * G_MPS2 * radius_m)
    plant, ref = run_side_by_side(fmu, Manoeuvre(speed, stop_s, lambda t, pose, v: wheelbase / radius_m))
    late = plant["t"] > stop_s - 1.0
    out = {"speed_mps": speed, "delta_rad": wheelbase / radius_m}
    for name, run in (("plant", plant), ("st", ref)):
        r, v, vy = (float(np.mean(run[c][late])) for c in ("yaw_rate", "v", "vy"))
        beta = math.asin(vy / v)
        out |= {f"{name}_yaw_rate": r, f"{name}_ay": float(np.mean(run["ay"][late])), f"{name}_beta": beta,
                f"{name}_alpha_rear": beta - lr * r / v}
    return out


def rear_slip_ratio_expected(fmu: Path, ay_g: float) -> float:
    """Slip angle of the plant's lateral Magic Formula over the linear tyre's, both giving
    Fy / Fz = ay / g (steady state, no longitudinal force): the tyre curve's secant deficit."""
    d = plant_defaults(fmu)
    k, c, peak, e = (d["tyre_cornering_stiffness"], d["tyre_lateral_C"], d["tyre_lateral_D"], d["tyre_lateral_E"])
    b = k / (c * peak)
    alphas = np.linspace(0.0, 0.2, 200001)[1:]
    ba = b * alphas
    force = peak * np.sin(c * np.arctan(ba - e * (ba - np.arctan(ba))))
    return float(alphas[np.argmax(force >= ay_g)] / (ay_g / k))


# -- ISO 7401: step steer ---------------------------------------------------------------------------
def step_steer(fmu: Path, speed_mps: float = 80 / 3.6, ay_mps2: float = 4.0, start_s: float = 0.5,
               stop_s: float = 4.0) -> dict[str, float]:
    """A road-wheel step at the steering rate limit, sized for ``ay_mps2`` in the ST model's steady
    state (neutral or not: from its understeer gradient), at ``speed_mps``. Per model: the yaw-rate
    peak, the steady state (last 0.5 s), the overshoot, the response time (50 % of the steering
    input to 90 % of the steady-state yaw rate, ISO 7401) and the time from 50 % steering to the peak."""
    d = plant_defaults(fmu)
    p = st_parameters(d)
    g = 9.81  # the ST code's gravity
    load_f, load_r = p.m * g * p.b / (p.a + p.b), p.m * g * p.a / (p.a + p.b)
    k_c = -p.tire.p_ky1
    understeer = p.m / (p.a + p.b) * (p.b / (k_c * load_f) - p.a / (k_c * load_r))
    delta = ay_mps2 * ((p.a + p.b) + understeer * speed_mps**2) / speed_mps**2
    plant, ref = run_side_by_side(fmu, Manoeuvre(speed_mps, stop_s, lambda t, pose, v: delta if t >= start_s else 0.0))
    out = {"delta_rad": delta, "speed_mps": speed_mps}
    for name, run in (("plant", plant), ("st", ref)):
        t, r = run["t"], run["yaw_rate"]
        steady = float(np.mean(r[t > stop_s - 0.5]))
        t_half = _crossing(t, run["delta"], 0.5 * delta)
        k_peak = int(np.argmax(r))
        out |= {f"{name}_peak": float(r[k_peak]), f"{name}_steady": steady,
                f"{name}_overshoot": float(r[k_peak] / steady - 1.0),
                f"{name}_response_s": _crossing(t, r, 0.9 * steady) - t_half,
                f"{name}_peak_time_s": float(t[k_peak]) - t_half,
                f"{name}_ay_steady": float(np.mean(run["ay"][t > stop_s - 0.5]))}
    return out


def _crossing(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time y reaches ``level`` (rising), linearly interpolated between samples."""
    k = int(np.argmax(y >= level))
    if k == 0:
        raise ValueError(f"the signal never rises to {level}")
    return float(t[k - 1] + (level - y[k - 1]) / (y[k] - y[k - 1]) * (t[k] - t[k - 1]))



# -- ISO 3888-2: obstacle-avoidance double lane change -------------------------------------------------
#: CommonRoad vehicle 2 (BMW 320i) width w, m: the b of the ISO 3888-2 lane widths
VEHICLE_WIDTH_M = 1.61
ENTRY_X_M = 60.0


@dataclass(frozen=True)
class Gate:
    """One lane section of the course: x range, centre line and width, m."""

    start_x_m: float
    end_x_m: float
    centre_y_m: float
    width_m: float


def iso3888_2_gates(width_m: float = VEHICLE_WIDTH_M, entry_x_m: float = ENTRY_X_M) -> tuple[Gate, ...]:
    """ISO 3888-2 lane sections for a car of width b (docs: planar-protocol-facts S10, S11; the
    layout of Project Chrono's demo_VEH_HMMWV_DoubleLaneChange): section 1, 12 m long and
    1.1 b + 0.25 wide; a 13.5 m gap; section 2, 11 m long and b + 1 wide, with 1 m between
    section 1's left edge and section 2's right edge; a 12.5 m gap; section 3, 12 m long and
    3.0 m wide (Chrono's value), its right edge in line with section 1's. 61 m in all."""
    w1, w2, w3 = 1.1 * width_m + 0.25, width_m + 1.0, 3.0
    x = entry_x_m
    return (Gate(x, x + 12.0, 0.0, w1), Gate(x + 25.5, x + 36.5, w1 / 2 + 1.0 + w2 / 2, w2),
            Gate(x + 49.0, x + 61.0, (w3 - w1) / 2, w3))


def dlc_path(gates: tuple[Gate, ...], cg_to_rear_axle_m: float) -> PolylinePath:
    """The driver's path: each gate's centre line, held until the rear axle has left the gate
    (the centre of gravity ``cg_to_rear_axle_m`` past its end), then straight to the next gate's
    centre line at its entry; straight on before and after."""
    xs, ys = [gates[0].start_x_m - 100.0], [gates[0].centre_y_m]
    for gate in gates:
        xs += [gate.start_x_m, gate.end_x_m + cg_to_rear_axle_m]
        ys += [gate.centre_y_m, gate.centre_y_m]
    xs.append(gates[-1].end_x_m + 200.0)
    ys.append(gates[-1].centre_y_m)
    x = np.arange(xs[0], xs[-1], 0.25)
    return PolylinePath.from_points(x, np.interp(x, xs, ys))


def wheel_margins(run: dict[str, np.ndarray], gates: tuple[Gate, ...], lf: float, lr: float) -> list[float]:
    """Per gate, the smallest distance (m) of the outer wheel edges (front and rear axle, +-b/2,
    the points Chrono's demo checks) inside the gate's lane; negative: a cone is hit."""
    worst = [math.inf] * len(gates)
    c, s = np.cos(run["yaw"]), np.sin(run["yaw"])
    for along in (lf, -lr):
        for side in (VEHICLE_WIDTH_M / 2, -VEHICLE_WIDTH_M / 2):
            px = run["x"] + along * c - side * s
            py = run["y"] + along * s + side * c
            for i, gate in enumerate(gates):
                inside = (px >= gate.start_x_m) & (px <= gate.end_x_m)
                if inside.any():
                    slack = gate.width_m / 2 - np.abs(py[inside] - gate.centre_y_m)
                    worst[i] = min(worst[i], float(slack.min()))
    return worst


def double_lane_change(fmu: Path, speed_mps: float = 60 / 3.6, lookahead_time_s: float = 0.5) -> dict:
    """ISO 3888-2 driven by the pure-pursuit driver (cosim.world.path_following) in both models;
    the throttle is released at the entry gate. Returns the wheel margins per gate of each model,
    the largest lateral distance between the two tracks over the course, and the peak |ay|."""
    d = plant_defaults(fmu)
    lf, lr = d["cg_to_front_axle"], d["wheelbase"] - d["cg_to_front_axle"]
    gates = iso3888_2_gates()
    path = dlc_path(gates, lr)
    params = PurePursuitParams(wheelbase_m=d["wheelbase"], cg_to_rear_axle_m=lr, steering_ratio=d["steering_ratio"],
                               max_road_wheel_angle_rad=d["steering_angle_max"], lookahead_time_s=lookahead_time_s)
    stop_s = (gates[-1].end_x_m + 10.0) / speed_mps
    plant, ref = run_side_by_side(fmu, Manoeuvre(
        speed_mps, stop_s, lambda t, pose, v: pursuit(pose, v, path, params).road_wheel_angle_rad, gates[0].start_x_m))
    course = (plant["x"] >= gates[0].start_x_m) & (plant["x"] <= gates[-1].end_x_m)
    gap = np.abs(plant["y"][course] - np.interp(plant["x"][course], ref["x"], ref["y"]))
    return {"plant_margins_m": wheel_margins(plant, gates, lf, lr), "st_margins_m": wheel_margins(ref, gates, lf, lr),
            "track_gap_m": float(gap.max()), "plant_ay_max": float(np.abs(plant["ay"]).max()),
            "st_ay_max": float(np.abs(ref["ay"]).max()), "speed_exit_mps": float(plant["v"][-1])}
