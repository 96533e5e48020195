"""Checks of Acary & Taha that transcribe a printed formula, kept beside the paper's audit
(:mod:`paper_checks.acary_taha`) rather than in the library: a transcription is the paper's text,
not impactsym's mechanics.
"""

from __future__ import annotations

import sympy as sp

from derivations.memo import simplify
from derivations.rational_zero import is_zero

from impactsym.mechanics import kinetic_angle_cos
from impactsym.models.acary_taha import pool

__all__ = ["pool_kinetic_angle_check"]


def pool_kinetic_angle_check():
    """Verify eq. 42, ``n₁·n₂ = −½ cos θ``, for symbolic θ from the general kinetic-angle function
    (:func:`impactsym.mechanics.kinetic_angle_cos`) applied to
    :func:`impactsym.models.acary_taha.pool` (both constraint forms of eq. 24).

    Returns
    -------
    dict
        ``{constraint: (derived cos θ₁₂, equals the print)}`` for ``"distance"`` and ``"squared"``.

    Examples
    --------
    >>> r = pool_kinetic_angle_check()
    >>> r["distance"]
    (-cos(theta)/2, True)
    >>> r["squared"][1]
    True

    References
    ----------
    Acary & Taha, eq. 42 (and eq. 24 for the two constraint forms).
    """
    theta = sp.Symbol("theta", real=True)
    printed = -sp.cos(theta) / 2  # transcription of eq. 42
    out = {}
    for constraint in ("distance", "squared"):
        sc = pool(theta, constraint=constraint)
        c = simplify(kinetic_angle_cos(sc.M, sc.H[0, :], sc.H[1, :]))
        out[constraint] = (c, is_zero(c - printed))
    return out
