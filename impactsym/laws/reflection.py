"""The single-impact law: ``q̇⁺ = G_u(e) q̇⁻`` (Seghete & Murphey, sec. II-A, eqs. 1a–1b).

``G_u(e) = I − (1+e) M⁻¹uᵀu / (u M⁻¹ uᵀ)``; ``e = 1`` is the elastic reflection ``G_u``. The
formula is derived in :mod:`derivations.reflection` (and proved there); this module is the
checked, user-facing entry point, reachable three ways:

* **exact** (integers, rationals, decimal text, SymPy numbers): a SymPy matrix, exact;
* **mpmath** (``dps=...``): an ``mpmath.matrix`` at that many digits (inputs converted exactly:
  floats by their binary value, rationals at the working precision);
* **float64** (floats or NumPy arrays): the generated kernel ``impactsym.kernels.reflection_map``.
  Its normwise error is below ``FLOAT_ERROR_FACTOR · n · κ(M) · eps · ‖G‖`` (measured in
  ``tests/test_reflection_numeric.py`` against 50-digit references, κ up to 1e12).

References
----------
Seghete & Murphey, sec. II-A (``G_u``), sec. III-C (its properties, eq. 5).

Examples
--------
>>> reflection_map("11/10,0;0,1", "-1,1")
Matrix([
[ 1/21, 20/21],
[22/21, -1/21]])
>>> reflect("1,0;0,1", "1,0", "-1,-1").T
Matrix([[1, -1]])
>>> reflect([[1.0, 0.0], [0.0, 1.0]], [1.0, 0.0], [-1.0, -1.0], restitution=0.5)
array([ 0.5, -1. ])
>>> reflection_map("1,0;0,1", "1,0", restitution="3/2")
Traceback (most recent call last):
...
impactsym.errors.DomainError: restitution: must lie in [0, 1], got 3/2
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..arithmetic import all_rational, rational_matrix, to_sympy_matrix
from .. import kernels
from . import _reflection as _r
from ..errors import DomainError, ImpactInputError
from ..exact import certified_sign
from ..mechanics import check_gradient, check_mass_matrix, check_velocity
from ..numbers import float_to_rational, is_exact, to_exact

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ..arithmetic import LazyModule
mpmath = LazyModule("mpmath", globals(), "mpmath")
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["reflection_map", "reflect", "impulse_multiplier", "check_restitution", "FLOAT_ERROR_FACTOR"]

#: the constant C of the float path's stated bound ‖G_float − G‖ ≤ C · n · κ(M) · eps · ‖G‖ (max-norms)
FLOAT_ERROR_FACTOR = 8


def check_restitution(e: Any, argument: str = "restitution", *, exact: bool | None = None):
    """Check ``0 ≤ e ≤ 1``; returns ``e`` exact (SymPy) or as a float.

    >>> check_restitution("1/2"), check_restitution(0.25)
    (1/2, 0.25)
    >>> check_restitution(float("nan"))
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: restitution: must be a finite real number, got nan
    """
    if exact is None:
        exact = is_exact(e)
    if exact:
        val = to_exact(e, argument)
        if certified_sign(val) < 0 or certified_sign(val - 1) > 0:
            raise DomainError(f"{argument}: must lie in [0, 1], got {val}")
        return val
    val = float(e)
    if not np.isfinite(val):
        raise ImpactInputError(argument, f"must be a finite real number, got {val}")
    if not 0.0 <= val <= 1.0:
        raise DomainError(f"{argument}: must lie in [0, 1], got {val!r}")
    return val


def _mp(x) -> mpmath.mpf:
    if isinstance(x, (float, np.floating)):
        return mpmath.mpf(float(x))  # exact binary value
    x = to_exact(x) if not isinstance(x, sp.Basic) else x
    if x.is_Rational:
        return mpmath.mpf(int(x.p)) / int(x.q)
    return mpmath.mpf(sp.N(x, mpmath.mp.dps + 10)._mpf_)


def _checked(M, u, v=None, e=1, dps=None):
    exact = is_exact(M, u, e) and (v is None or is_exact(v))
    # the mpmath path takes exact values of whatever is given
    Mx = check_mass_matrix(M, exact=exact)
    n = Mx.shape[0]
    ux = check_gradient(u, n, exact=exact)
    vx = None if v is None else check_velocity(v, n, exact=exact)
    ex = check_restitution(e, exact=exact)
    return exact, Mx, ux, vx, ex


def _mp_parts(Mx, ux, ex, exact):
    n = Mx.shape[0]
    Mm = mpmath.matrix([[_mp(Mx[i, j]) for j in range(n)] for i in range(n)])
    um = mpmath.matrix([_mp(ux[i]) for i in range(n)])
    w, s = _r.mpmath_parts(Mm, um)
    return Mm, um, w, s, _r.gain(s, _mp(ex))


def _rational_parts(Mx, ux, ex):
    """``w = M⁻¹uᵀ`` and ``c = (1+e)/(u w)`` exactly over the rationals (python-flint, O(n³))."""
    from flint import fmpq

    u = rational_matrix(ux)
    w, s = _r.fmpq_parts(rational_matrix(Mx), u)
    return u, w, _r.gain(s, fmpq(int(ex.p), int(ex.q)))


def reflection_map(mass_matrix, gradient, restitution=1, *, dps: int | None = None):
    """``G_u(e) = I − (1+e) M⁻¹uᵀu / (u M⁻¹ uᵀ)`` for one gradient covector ``u``.

    Parameters
    ----------
    mass_matrix : matrix-like (n×n), symmetric positive definite
    gradient : vector-like (n,), non-zero covector ``u = Dφ``
    restitution : number in [0, 1], default 1 (elastic)
    dps : int, optional
        Evaluate with mpmath at ``dps`` digits (returns ``mpmath.matrix``).

    Returns
    -------
    sympy.Matrix (exact input), numpy.ndarray (float input) or mpmath.matrix (``dps`` given).

    Raises
    ------
    ImpactInputError
        Wrong shapes, NaN/inf, non-symmetric or non-positive-definite mass matrix, zero gradient.
    DomainError
        Restitution outside [0, 1].
    """
    exact, Mx, ux, _, ex = _checked(mass_matrix, gradient, None, restitution)
    n = Mx.shape[0]
    if dps is not None:
        with mpmath.workdps(dps):
            _, um, w, _, c = _mp_parts(Mx, ux, ex, exact)
            return _r.reflection_matrix(mpmath.eye(n), w, um.T, c)
    if exact and all_rational(Mx, ux, sp.Matrix([ex])):  # rational input: exact linear algebra in python-flint
        from flint import fmpq, fmpq_mat

        from .reflection_rational import verify_rational_reflection

        u, w, c = _rational_parts(Mx, ux, ex)
        G = _r.reflection_matrix(fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)]), w, u, c)
        verify_rational_reflection(rational_matrix(Mx), u, fmpq(int(ex.p), int(ex.q)), G)  # u G = -e u, M(G - I) = u^T r
        return to_sympy_matrix(G)
    if exact:
        w, s = _r.sympy_parts(Mx, ux)
        return _r.reflection_matrix(sp.eye(n), w, ux, _r.gain(s, ex)).applyfunc(sp.radsimp)
    return kernels.reflection_map(Mx, ux, ex)


def reflect(mass_matrix, gradient, velocity, restitution=1, *, dps: int | None = None):
    """``q̇⁺ = G_u(e) q̇⁻``, without forming ``G``.

    Same arguments and paths as :func:`reflection_map`, plus ``velocity`` (n,). Returns a
    column ``sympy.Matrix`` (exact), a 1-D ``numpy.ndarray`` (float) or an ``mpmath.matrix``.
    The velocity need not approach the surface: ``G_u`` is a linear map on all of ``TQ``.

    >>> reflect("2,0;0,1", "-1,1", "1,0").T
    Matrix([[1/3, 4/3]])
    """
    exact, Mx, ux, vx, ex = _checked(mass_matrix, gradient, velocity, restitution)
    n = Mx.shape[0]
    if dps is not None:
        with mpmath.workdps(dps):
            _, um, w, _, c = _mp_parts(Mx, ux, ex, exact)
            vm = mpmath.matrix([_mp(vx[i]) for i in range(n)])
            uv = sum(um[i] * vm[i] for i in range(n))
            return _r.reflect_along(vm, w, uv, c)[0]
    if exact and all_rational(Mx, ux, vx, sp.Matrix([ex])):
        u, w, c = _rational_parts(Mx, ux, ex)
        v = rational_matrix(vx)
        vq, pq = _r.reflect_along(v, w, (u * v)[0, 0], c)  # p = -(1+e) u v / (u M^-1 u^T)
        out = to_sympy_matrix(vq)
        _verify_reflection(Mx, ux, vx, ex, out, sp.Rational(int(pq.p), int(pq.q)))
        return out
    if exact:
        w, s = _r.sympy_parts(Mx, ux)
        out, p = _r.reflect_along(vx, w, (ux * vx)[0, 0], _r.gain(s, ex))
        out = out.applyfunc(sp.radsimp)
        _verify_reflection(Mx, ux, vx, ex, out, sp.radsimp(p))
        return out
    return kernels.reflect(Mx, ux, vx, ex)


def _verify_reflection(Mx, ux, vx, ex, vplus, p):
    """Verify an exact reflection before returning it: ``M(v⁺ − v) = uᵀp`` and Newton's
    ``u v⁺ = −e u v`` (so ``T⁺ = T⁻`` when ``e = 1``, and ``u v⁺ ≥ 0`` when ``v`` approaches),
    exactly for rational data, on 512-bit Arb balls for algebraic data
    (:mod:`impactsym.verify`)."""
    from flint import ctx

    from ..errors import VerificationError
    from ..arithmetic import enclose_narrow as enclose  # (a ball read only by the check below)
    from ..verify import ALGEBRAIC_CHECK_BITS, verify_exact

    verify_exact("reflection", Mx, ux, vx, vplus, [p], closed=[], impulse_nonnegative=False,
                 energy_ratio=1 if ex == 1 else None)
    n = Mx.shape[0]
    rel = sum((ux[i] * (vplus[i] + ex * vx[i]) for i in range(n)), sp.Integer(0))
    if all(x.is_Rational for x in list(ux) + list(vplus) + list(vx) + [sp.sympify(ex)]):
        bad = rel != 0
    else:
        prec = ALGEBRAIC_CHECK_BITS
        with ctx.workprec(prec):
            ball = sum((enclose(ux[i], prec) * (enclose(vplus[i], prec) + enclose(ex, prec) * enclose(vx[i], prec))
                        for i in range(n)), enclose(0, prec))
            bad = not ball.contains(0)
    if bad:
        raise VerificationError("reflection", f"Newton's law: u v+ + e u v = {rel} != 0")


def impulse_multiplier(mass_matrix, gradient, velocity, restitution=1):
    """The impulse ``p = −λ = −(1+e) u q̇⁻ / (u M⁻¹ uᵀ)`` of ``M(q̇⁺ − q̇⁻) = uᵀp``.

    Seghete & Murphey's ``λ = 2 u q̇⁻ / (u M⁻¹ uᵀ)`` (e = 1) is ``−p``: ``p ≥ 0`` for an
    approaching velocity (``u q̇⁻ < 0``).

    >>> impulse_multiplier("1,0;0,1", "1,0", "-1,0")
    2
    """
    exact, Mx, ux, vx, ex = _checked(mass_matrix, gradient, velocity, restitution)
    if exact:
        _, s = _r.sympy_parts(Mx, ux)
        return sp.radsimp(-_r.gain(s, ex) * (ux * vx)[0, 0])
    s = float(ux @ np.linalg.solve(Mx, ux))
    return -_r.gain(s, ex) * float(ux @ vx)
