"""A third-party planar vehicle FMU for the tests: CommonRoad's single-track model "ST" (built with pythonfmu, FMI 2).

The vehicle dynamics are the independent package's (PyPI ``commonroad-vehicle-models``, ``vehicle_dynamics_st``;
Althoff and Wuersching, "CommonRoad: Vehicle Models", 2020a, section 7) with CommonRoad vehicle 2 (BMW 320i) as
it ships, none of crd's plant parameters. Only the actuator shell around it is this fixture's:

* ``a_cmd`` (m/s²), the longitudinal acceleration asked for, reaches the model through a first-order lag
  ``lag_s`` and is bounded by the road's friction ``mu`` (``|a| <= mu g``) and at standstill (no reversing);
* the road-wheel angle asked for is ``delta_cmd + delta_overlay`` (rad: the driver's and an ECU's overlay);
  the steering velocity input moves the wheel toward it as fast as vehicle 2's limits allow (0.4 rad/s);
* the state ``[x, y, delta, v, psi, psi_dot, beta]`` is integrated with the classical Runge-Kutta scheme at
  ``substep_s``.

Outputs are the centre of gravity's (the ST model's reference point): ``x``, ``y``, ``psi``, ``psi_dot``, the
velocity in the vehicle frame ``v_lon``, ``v_lat``, and ``a_lon``, the lagged acceleration applied.
"""

import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real

G_MPS2 = 9.80665


class StVehicle(Fmi2Slave):
    author = "crd tests"
    description = "CommonRoad ST model (vehicle 2) with an acceleration and road-wheel angle command"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        from vehiclemodels.parameters_vehicle2 import parameters_vehicle2

        self._p = parameters_vehicle2()
        self.a_cmd = self.delta_cmd = self.delta_overlay = 0.0
        self.mu = 1.0
        self.x = self.y = self.psi = self.psi_dot = self.v_lon = self.v_lat = self.a_lon = 0.0
        self.v_start, self.y_start, self.psi_start = 0.0, 0.0, 0.0
        self.lag_s, self.substep_s = 0.2, 0.001
        self._state = [0.0] * 7
        for name in ("a_cmd", "delta_cmd", "delta_overlay", "mu"):
            self.register_variable(Real(name, causality=Fmi2Causality.input))
        for name in ("x", "y", "psi", "psi_dot", "v_lon", "v_lat", "a_lon"):
            self.register_variable(Real(name, causality=Fmi2Causality.output))
        for name in ("v_start", "y_start", "psi_start", "lag_s", "substep_s"):
            self.register_variable(Real(name, causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.tunable))

    def exit_initialization_mode(self):
        self._state = [0.0, self.y_start, 0.0, self.v_start, self.psi_start, 0.0, 0.0]
        self._publish()

    def _rates(self, state, u):
        from vehiclemodels.vehicle_dynamics_st import vehicle_dynamics_st

        return vehicle_dynamics_st(state, u, self._p)

    def _rk4(self, u, h_s):
        s = self._state
        k1 = self._rates(s, u)
        k2 = self._rates([a + 0.5 * h_s * b for a, b in zip(s, k1)], u)
        k3 = self._rates([a + 0.5 * h_s * b for a, b in zip(s, k2)], u)
        k4 = self._rates([a + h_s * b for a, b in zip(s, k3)], u)
        self._state = [a + h_s / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4) for a, b1, b2, b3, b4 in zip(s, k1, k2, k3, k4)]

    def do_step(self, current_time, step_size):
        steering = self._p.steering
        n = max(1, int(round(step_size / self.substep_s)))
        h_s = step_size / n
        delta_target = self.delta_cmd + self.delta_overlay
        for _ in range(n):
            limit = self.mu * G_MPS2
            self.a_lon += (min(max(self.a_cmd, -limit), limit) - self.a_lon) * h_s / self.lag_s
            v = self._state[3]
            accel = max(self.a_lon, -v / h_s)  # braking ends at standstill: no reversing
            rate = min(max((delta_target - self._state[2]) / h_s, steering.v_min), steering.v_max)
            self._rk4([rate, accel], h_s)
            self._state[3] = max(self._state[3], 0.0)
        self._publish()
        return True

    def _publish(self):
        x, y, _delta, v, psi, psi_dot, beta = self._state
        self.x, self.y, self.psi, self.psi_dot = x, y, psi, psi_dot
        self.v_lon, self.v_lat = v * math.cos(beta), v * math.sin(beta)
