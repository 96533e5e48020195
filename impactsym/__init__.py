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

from ._lazy import lazy_attributes

#: every public name, and the module it lives in: imported on first use (PEP 562), so that
#: ``import impactsym`` (and the CLI's start-up) costs no SymPy, NumPy or SciPy until a law is used
_LAZY = {
    "validity_domain": "domains", "plot_domain": "domains",
    "DomainError": "errors", "ImpactError": "errors", "ImpactInputError": "errors",
    "NonTermination": "errors", "UndecidableSign": "errors",
    "impulse_multiplier": "laws.reflection", "reflect": "laws.reflection", "reflection_map": "laws.reflection",
    "impulse_ratio_law": "laws.impulse_ratio",
    "energetic": "laws.classical", "han_gilmore": "laws.classical", "newton_moreau": "laws.classical",
    "poisson": "laws.classical",
    "apply_coupling": "laws.coupling", "coupling_decision": "laws.coupling", "impact_degree": "laws.coupling",
    "resolve_two_surfaces": "laws.two_surface",
    "resolve_sequential": "laws.sequential",
    **{name: "mechanics" for name in ("check_gradient", "check_gradients", "check_mass_matrix", "check_velocity",
                                      "kinetic_angle", "kinetic_angle_cos", "kinetic_energy", "m_normal",
                                      "relative_velocity")},
}


__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, globals())


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
