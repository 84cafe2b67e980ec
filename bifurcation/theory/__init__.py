"""The paper's closed forms (Vasconcelos, PRL 76, 4865 (1996), Eqs. 6-18), corrected, and its errata.

``linear`` holds the formulas (numpy float64 or mpmath); ``errata.ERRATA`` records every printed
formula we found wrong, with the numbers that show it; ``reference`` holds the independent mpmath
references (exact piecewise solutions) that both are tested against (it imports neither).
"""

from . import errata, linear
from .errata import ERRATA, Erratum
from .linear import (
    alpha,
    creep_coefficient,
    creep_time_asymptotic,
    delta0_piecewise_linear,
    delta_creep,
    displacement_creep,
    displacement_limit_linear,
    displacement_limit_piecewise_linear,
    displacement_linear,
    max_velocity_creep,
    omega,
    stop_time_creep,
    tau1,
    tau2,
    velocity_linear,
)

__all__ = ["ERRATA", "Erratum", "alpha", "creep_coefficient", "creep_time_asymptotic",
           "delta0_piecewise_linear", "delta_creep", "displacement_creep", "displacement_limit_linear",
           "displacement_limit_piecewise_linear", "displacement_linear", "max_velocity_creep", "omega",
           "stop_time_creep", "tau1", "tau2", "velocity_linear"]
