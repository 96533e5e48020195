"""The single-impact law on rational data in python-flint alone: checked, computed and verified
without SymPy or NumPy (the start-up path of ``impactsym reflect``).

``G_u(e) = I − (1+e) M⁻¹uᵀu / (u M⁻¹ uᵀ)`` and ``G_u(e) v`` (Seghete & Murphey, sec. II-A), stated
once in :mod:`impactsym.laws._reflection` and evaluated here on ``fmpq``. The input is checked as
strictly as :func:`impactsym.laws.reflection.reflect` checks it (:mod:`impactsym.mechanics`):
``M`` square, symmetric and positive definite (exact elimination, Sylvester's criterion), ``u``
non-zero of length ``n``, ``v`` of length ``n``, ``0 ≤ e ≤ 1``. The command line gives any input
this module refuses to the general path, which words the error as it always has.

Every result is verified exactly before it is returned (:func:`verify_rational_reflection`);
a failed check raises :class:`~impactsym.errors.VerificationError` (a bug, exit status 1).

>>> G, vplus, p = rational_reflection([[2, 0], [0, 1]], [-1, 1], 1, [1, 0])
>>> G
[1/3, 2/3]
[4/3, -1/3]
>>> vplus.transpose(), p
([1/3, 4/3], 4/3)
>>> rational_reflection([[1, 2], [2, 1]], [1, 0])
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: mass_matrix: not positive definite (leading principal minor 2 is -3)
"""

from __future__ import annotations

from typing import Sequence

from flint import fmpq, fmpq_mat

from . import _reflection as _r
from ..errors import DomainError, ImpactInputError, VerificationError

__all__ = ["rational_reflection", "verify_rational_reflection"]


def _q(x) -> fmpq:
    """An ``int``, ``Fraction`` or ``fmpq`` as ``fmpq`` (exactly)."""
    if isinstance(x, fmpq):
        return x
    if isinstance(x, int):
        return fmpq(x)
    return fmpq(int(x.numerator), int(x.denominator))


def _check_mass_matrix(M: Sequence[Sequence], argument: str = "mass_matrix") -> fmpq_mat:
    n = len(M)
    if n == 0 or any(len(row) != n for row in M):
        shape = (n, len(M[0]) if n else 0)
        raise ImpactInputError(argument, f"must be a non-empty square matrix, got shape {shape}")
    F = [[_q(x) for x in row] for row in M]
    for i in range(n):
        for j in range(i + 1, n):
            if F[i][j] != F[j][i]:
                raise ImpactInputError(argument, f"not symmetric (entry ({i}, {j}) is {F[i][j]} but ({j}, {i}) is {F[j][i]})")
    A = [row[:] for row in F]
    minor = fmpq(1)
    for k in range(n):  # the k-th pivot of elimination without pivoting is minor_k / minor_(k-1)
        pivot = A[k][k]
        minor *= pivot
        if pivot <= 0:
            raise ImpactInputError(argument, f"not positive definite (leading principal minor {k + 1} is {minor})")
        for i in range(k + 1, n):
            f = A[i][k] / pivot
            if f != 0:
                for j in range(k + 1, n):
                    A[i][j] -= f * A[k][j]
    return fmpq_mat(n, n, [x for row in F for x in row])


def _check_vector(x: Sequence, n: int, argument: str) -> list[fmpq]:
    if len(x) != n:
        raise ImpactInputError(argument, f"has length {len(x)}, expected {n} (the mass matrix is {n}×{n})")
    return [_q(a) for a in x]


def rational_reflection(mass_matrix: Sequence[Sequence], gradient: Sequence, restitution=1,
                        velocity: Sequence | None = None):
    """``G_u(e)``, and ``G_u(e) v`` with its impulse ``p``, exactly over the rationals.

    Parameters
    ----------
    mass_matrix : rows of rationals (``int``, ``fractions.Fraction`` or ``fmpq``), symmetric positive definite
    gradient : the non-zero covector ``u`` (n rationals)
    restitution : rational in [0, 1], default 1
    velocity : n rationals, optional

    Returns
    -------
    (G, vplus, p) : ``fmpq_mat`` n×n, ``fmpq_mat`` n×1 (or ``None`` without ``velocity``), ``fmpq``
        (or ``None``); ``M(v⁺ − v) = uᵀp`` and ``u v⁺ = −e u v``. All verified before return.

    Raises
    ------
    ImpactInputError
        Shapes, a mass matrix that is not symmetric positive definite, a zero gradient.
    DomainError
        Restitution outside [0, 1].

    Examples
    --------
    >>> from fractions import Fraction
    >>> G, vplus, p = rational_reflection([[Fraction(11, 10), 0], [0, 1]], [-1, 1], Fraction(1, 2), [1, -2])
    >>> G.entries(), vplus.entries(), p
    ([2/7, 5/7, 11/14, 3/14], [-8/7, 5/14], 33/14)
    """
    M = _check_mass_matrix(mass_matrix)
    n = M.nrows()
    u = _check_vector(gradient, n, "gradient")
    if all(x == 0 for x in u):
        raise ImpactInputError("gradient", "is the zero covector (a constraint gradient must be non-zero)")
    e = _q(restitution)
    if e < 0 or e > 1:
        raise DomainError(f"restitution: must lie in [0, 1], got {e}")
    v = None if velocity is None else _check_vector(velocity, n, "velocity")
    urow = fmpq_mat(1, n, u)
    w, s = _r.fmpq_parts(M, urow)
    g = _r.gain(s, e)
    identity = fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])
    G = _r.reflection_matrix(identity, w, urow, g)
    vplus = p = None
    if v is not None:
        vcol = fmpq_mat(n, 1, v)
        vplus, p = _r.reflect_along(vcol, w, (urow * vcol)[0, 0], g)
    verify_rational_reflection(M, urow, e, G, v, vplus, p)
    return G, vplus, p


def verify_rational_reflection(M: fmpq_mat, u: fmpq_mat, e: fmpq, G: fmpq_mat, v=None, vplus=None, p=None) -> None:
    """Verify an exact reflection before it is returned, independently of how it was computed.

    * ``G``: Newton's law for every velocity, ``u G = −e u``, and the impulse direction,
      ``M(G − I) = uᵀr`` for one row ``r``. These two determine ``G``: the second gives
      ``G = I + M⁻¹uᵀr``, the first then ``(u M⁻¹ uᵀ) r = −(1+e) u``, so ``G = G_u(e)``
      (and ``G² = I`` when ``e = 1``).
    * ``v⁺`` (when given): the momentum balance ``M(v⁺ − v) = uᵀp``, Newton's ``u v⁺ = −e u v``,
      and ``v⁺ᵀMv⁺ = vᵀMv`` when ``e = 1``.

    Raises :class:`~impactsym.errors.VerificationError` naming the failed condition.

    >>> M, u = fmpq_mat([[2, 0], [0, 1]]), fmpq_mat([[1, 1]])
    >>> verify_rational_reflection(M, u, fmpq(1), fmpq_mat([[1, 0], [0, 1]]))
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: reflection: verification of the outcome failed: Newton's law: u G = [1, 1] != -e u (a bug in impactsym; the outcome was not returned)
    """
    n = M.nrows()
    identity = fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])
    uG = u * G
    if uG != u * (-e):
        raise VerificationError("reflection", f"Newton's law: u G = {uG.entries()} != -e u")
    D = M * (G - identity)
    k = next(j for j in range(n) if u[0, j] != 0)
    r = fmpq_mat(1, n, [D[k, j] / u[0, k] for j in range(n)])
    if D != u.transpose() * r:
        raise VerificationError("reflection", "M (G - I) is not u^T r for any row r")
    if vplus is None:
        return
    vcol = fmpq_mat(n, 1, list(v))
    if M * (vplus - vcol) != u.transpose() * p:
        raise VerificationError("reflection", f"momentum: M(v+ - v) - u^T p = {(M * (vplus - vcol) - u.transpose() * p).entries()} != 0")
    rel = (u * vplus)[0, 0] + e * (u * vcol)[0, 0]
    if rel != 0:
        raise VerificationError("reflection", f"Newton's law: u v+ + e u v = {rel} != 0")
    if e == 1:
        Tp, Tm = (vplus.transpose() * M * vplus)[0, 0], (vcol.transpose() * M * vcol)[0, 0]
        if Tp != Tm:
            raise VerificationError("reflection", f"kinetic energy: v+^T M v+ = {Tp}, expected v^T M v = {Tm}")
