"""A vehicle FMU that fails natively on request (built with pythonfmu, FMI 2), for the isolation tests.

``fault`` picks what happens from ``fault_at`` (s) on: 0 nothing, 1 ``abort()``
in doStep, 2 a segmentation fault in doStep, 3 an endless loop in doStep,
4 a NaN speed output, 5 an endless loop in terminate. Otherwise a point mass
under an acceleration command ``a_cmd`` (m/s²).
"""

import ctypes
import math
import os

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class Faulty(Fmi2Slave):
    author = "crd tests"
    description = "Point mass that crashes, hangs or returns NaN on request"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.a_cmd = 0.0
        self.s_m = 0.0
        self.v_mps = 0.0
        self.fault = 0
        self.fault_at = 1.0
        self.register_variable(Real("a_cmd", causality=Fmi2Causality.input))
        self.register_variable(Real("s_m", causality=Fmi2Causality.output))
        self.register_variable(Real("v_mps", causality=Fmi2Causality.output))
        self.register_variable(Integer("fault", causality=Fmi2Causality.parameter,
                                       variability=Fmi2Variability.tunable))
        self.register_variable(Real("fault_at", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))

    def do_step(self, current_time, step_size):
        if current_time >= self.fault_at:
            if self.fault == 1:
                os.abort()
            if self.fault == 2:
                ctypes.string_at(0)  # reads address 0: SIGSEGV
            if self.fault == 3:
                while True:
                    pass
            if self.fault == 4:
                self.v_mps = math.nan
                return True
        self.v_mps = max(0.0, self.v_mps + self.a_cmd * step_size)
        self.s_m += self.v_mps * step_size
        return True

    def terminate(self):
        if self.fault == 5:
            while True:
                pass
