"""A third-party-shaped vehicle FMU for the tests (built with pythonfmu, FMI 2).

Different shape from our plant: an acceleration-command input ``a_cmd``
(m/s², first-order lag of 0.2 s), speed output in km/h, other names, no wheel
outputs. ``fail_at`` makes ``do_step`` fail from that time on (FMI error).
"""

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class PointMass(Fmi2Slave):
    author = "crd tests"
    description = "Point-mass car driven by an acceleration command"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.a_cmd = 0.0
        self.a_act = 0.0
        self.s_m = 0.0
        self.speed_kmh = 0.0
        self.fail_at = 1.0e9
        self.lag_s = 0.2
        self.v_start_kmh = 0.0
        self.register_variable(Real("a_cmd", causality=Fmi2Causality.input))
        self.register_variable(Real("s_m", causality=Fmi2Causality.output))
        self.register_variable(Real("speed_kmh", causality=Fmi2Causality.output))
        self.register_variable(Real("a_act", causality=Fmi2Causality.output))
        self.register_variable(Real("fail_at", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))
        self.register_variable(Real("lag_s", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))
        self.register_variable(Real("v_start_kmh", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))

    def exit_initialization_mode(self):
        self.speed_kmh = self.v_start_kmh

    def do_step(self, current_time, step_size):
        if current_time >= self.fail_at:
            return False
        self.a_act += (self.a_cmd - self.a_act) * step_size / self.lag_s
        v = max(0.0, self.speed_kmh / 3.6 + self.a_act * step_size)
        self.s_m += v * step_size
        self.speed_kmh = v * 3.6
        return True
