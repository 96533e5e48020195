"""impactsym: derive, prove and evaluate laws for simultaneous impacts between rigid bodies.

The package follows one data flow: **derive → generate → evaluate → check**. SymPy
derivations (``derivations/``) write the generated kernels (``impactsym.kernels``); the laws
(``impactsym.laws``) check their input and answer exactly, at high precision, or in floats.

>>> import impactsym as ims
>>> ims.reflection_map("1,0;0,1", "-1,1")
Matrix([
[0, 1],
[1, 0]])
"""

from .domains import plot_domain, validity_domain
from .errors import DomainError, ImpactError, ImpactInputError, NonTermination, UndecidableSign
from .laws.reflection import impulse_multiplier, reflect, reflection_map
from .mechanics import (
    check_gradient,
    check_gradients,
    check_mass_matrix,
    check_velocity,
    kinetic_angle,
    kinetic_angle_cos,
    kinetic_energy,
    m_normal,
    relative_velocity,
)

__version__ = "0.1.0"

__all__ = [
    "validity_domain", "plot_domain",
    "ImpactError", "ImpactInputError", "DomainError", "NonTermination", "UndecidableSign",
    "reflection_map", "reflect", "impulse_multiplier",
    "check_mass_matrix", "check_gradient", "check_gradients", "check_velocity",
    "kinetic_energy", "m_normal", "kinetic_angle_cos", "kinetic_angle", "relative_velocity",
]
