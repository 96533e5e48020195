"""The papers' figures, drawn from the laws (Seghete & Murphey; Acary & Taha).

One function per figure, named after it (``sm_`` Seghete & Murphey, ``at_`` Acary & Taha). Each
returns ``(figure, source)``: the matplotlib ``Figure`` and a small dict of the *source data* it
drew, exact numbers as strings (SymPy ``str``). Every number comes from a call into the library
(:mod:`impactsym.laws`, :mod:`impactsym.domains`, :mod:`impactsym.simulate`,
:mod:`impactsym.compliant`, the scenes of :mod:`impactsym.models`); no formula of a paper is typed
here. Matplotlib (Agg backend) is imported inside the functions, so ``import impactsym`` stays light.

Modules: :mod:`._common` (shared helpers, :func:`save`, :func:`show`), :mod:`.seghete_murphey`,
:mod:`.acary_taha`, :mod:`.laws` (figures across laws) and :mod:`.readme` (the README's figures);
every public name is importable from here.

``python -m impactsym.figures DIR`` writes the README's figures (:data:`README_FIGURES`) into
``DIR`` as PNGs, each with a ``.json`` of its source data beside it; ``tests/test_figures.py``
regenerates the source data and compares it with the committed JSON (not the pixels).

Examples
--------
>>> fig, src = sm_fig4_configuration_space()
>>> src["v4a"], src["v4b"]
(['173/147', '278/147'], ['359/441', '922/441'])
>>> src["claim_sector_t"]
['23/19', '439/40']
"""

from __future__ import annotations

from ..errors import ImpactInputError  # noqa: F401  (was importable from here)
from ._common import _normal_cone_arc, save, show  # noqa: F401
from .acary_taha import (PLANAR_CHAIN, at_chain3_velocities, at_domain_over_theta, at_fig2_pool, at_fig3_domain,
                         at_fig4_bernoulli, at_fig5_planar_chain, at_fig5_transmission)
from .laws import (LAWS, MAX_DRAWN_REFLECTIONS, domain_figure, laws_side_by_side, laws_figure_from_json, outcomes_per_law, resolve_figure,
                   speed_against_error, two_surface_figure)
from .readme import README_FIGURES, main, write_readme_figures
from .seghete_murphey import (ordering_regions, sm_fig1_convex_corner, sm_fig2_concave_corner,
                              sm_fig4_configuration_space, sm_fig5_cradle_kinetic_plane, sm_sec3c_termination,
                              sm_three_surface_overgeneration)

__all__ = [
    "sm_fig1_convex_corner", "sm_fig2_concave_corner", "sm_fig4_configuration_space", "ordering_regions",
    "sm_fig5_cradle_kinetic_plane", "sm_sec3c_termination", "two_surface_figure", "sm_three_surface_overgeneration",
    "at_fig2_pool", "at_fig3_domain", "at_domain_over_theta", "domain_figure", "at_chain3_velocities", "at_fig4_bernoulli",
    "at_fig5_transmission", "at_fig5_planar_chain", "outcomes_per_law", "laws_side_by_side", "laws_figure_from_json", "resolve_figure", "speed_against_error",
    "README_FIGURES", "write_readme_figures", "save", "show",
]
