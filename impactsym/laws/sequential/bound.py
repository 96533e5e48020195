"""Sec. III-C's termination bound for two surfaces, certified."""

from __future__ import annotations


from ...arithmetic import all_rational, rational_matrix, sign_of
from ...errors import DomainError, ImpactInputError
from ...mechanics import check_gradients, check_mass_matrix

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule
sp = LazyModule("sympy", globals(), "sp")


def termination_bound(mass_matrix, gradients):
    """The paper's bound ``N = ⌈S_total / (2 S_0)⌉`` for two surfaces (sec. III-C), exactly.

    ``S_0`` is the valid lune of the kinetic sphere, whose dihedral angle is ``π − θ`` (``θ`` the
    kinetic angle between the contacts), so ``S_total / (2 S_0) = π / (π − θ)`` in any dimension.
    The ceiling is certified (:func:`impactsym.arithmetic.certified_ceiling`; an exact tie by
    :func:`impactsym.arithmetic.certified_sign`).

    Returns
    -------
    int

    Examples
    --------
    >>> termination_bound("1,0;0,1", "1,0;-1,1"), termination_bound("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1")
    (4, 3)
    """
    from ..two_surface import _Data, _certified_bound

    M = check_mass_matrix(mass_matrix, exact=True)
    H = check_gradients(gradients, M.shape[0], exact=True)
    if H.rows != 2:
        raise ImpactInputError("gradients", f"the bound of sec. III-C is for exactly two surfaces, got {H.rows}")
    # pi/(pi - theta) = pi/beta with beta = atan2(sqrt(Delta), -g): certified with Arb balls (the
    # two-surface law's bound), exact ties (beta = pi/K) decided exactly
    if all_rational(M, H):
        Mq, Hq = rational_matrix(M), rational_matrix(H)
        gram = Hq * Mq.solve(Hq.transpose())
    else:
        gram = (H * M.LUsolve(H.T)).applyfunc(sp.radsimp)
    d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], gram[0, 0], gram[1, 1])
    if sign_of(d.D) == 0:
        raise DomainError("gradients: the two surfaces are parallel (kinetic angle 0 or pi): the wedge is "
                          "degenerate, no bound")
    return _certified_bound(d, {})
