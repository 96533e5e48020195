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
from .laws.impulse_ratio import impulse_ratio_law
from .laws.classical import energetic, han_gilmore, newton_moreau, poisson
from .laws.coupling import apply_coupling, coupling_decision, impact_degree
from .laws.two_surface import resolve_two_surfaces
from .laws.sequential import resolve_sequential
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
    "impulse_ratio_law", "newton_moreau", "poisson", "energetic", "han_gilmore",
    "apply_coupling", "coupling_decision", "impact_degree",
    "resolve_two_surfaces", "resolve_sequential",
    "check_mass_matrix", "check_gradient", "check_gradients", "check_velocity",
    "kinetic_energy", "m_normal", "kinetic_angle_cos", "kinetic_angle", "relative_velocity",
]
