"""The refusal test: is any non-zero velocity valid (``H v ≥ 0``)? Decided exactly.
"""

from __future__ import annotations

import itertools


from ...numbers import is_exact
from .common import _Algebraic, _Rational, _all_rational, _dot, _nullspace

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule
sp = LazyModule("sympy", globals(), "sp")


# ---------------------------------------------------------------------------------------------
# Refusal: is any non-zero velocity valid?
# ---------------------------------------------------------------------------------------------
def valid_velocity_witness(gradients, *, exact: bool | None = None):
    """A non-zero ``v`` with ``H v ≥ 0`` (exact), or ``None`` when none exists.

    Decided exactly: if ``rank H < n`` a null vector of ``H`` is a witness; otherwise the cone
    ``{v : H v ≥ 0}`` is pointed and is non-zero exactly when it has an extreme ray, which spans
    the null space of ``n − 1`` linearly independent rows of ``H``; every such subset is tried.
    Float input is decided on the floats' exact binary values.

    Parameters
    ----------
    gradients : matrix-like (k×n), the gradient rows ``H``

    Returns
    -------
    sympy.Matrix (n×1) or None

    Examples
    --------
    >>> valid_velocity_witness("1,0;-1,1").T
    Matrix([[0, 1]])
    >>> valid_velocity_witness("1;-1") is None
    True
    >>> valid_velocity_witness("1,0;0,1;-1,-1") is None
    True
    """
    H = gradients
    if not isinstance(H, sp.MatrixBase) or not is_exact(H):
        from ...numbers import to_exact_matrix

        H = to_exact_matrix(H, "gradients")
    k, n = H.shape
    F = _Rational if _all_rational(H) else _Algebraic
    rows = [[F.num(H[i, j]) for j in range(n)] for i in range(k)]
    r = witness_of_rows(rows, n, F)
    return None if r is None else sp.Matrix([F.to_sympy(x) for x in r])


def witness_of_rows(rows, n: int, F=_Rational):
    """:func:`valid_velocity_witness` of the rows ``H`` given as lists of field elements (``fmpq``
    for :class:`~impactsym.arithmetic.RationalField`): the witness as a list in that field, or
    ``None``. The float path uses it on the floats' exact binary values, without SymPy.

    >>> from flint import fmpq
    >>> witness_of_rows([[fmpq(1), fmpq(0)], [fmpq(-1), fmpq(1)]], 2)
    [0, 1]
    >>> witness_of_rows([[fmpq(1)], [fmpq(-1)]], 1) is None
    True
    """
    null = _nullspace(rows, n, F)
    if null:
        return list(null[0])
    for subset in itertools.combinations(range(len(rows)), n - 1):
        sub = [rows[i] for i in subset]
        ns = _nullspace(sub, n, F) if sub else [[F.one if j == 0 else F.zero for j in range(n)]] if n == 1 else None
        if ns is None or len(ns) != 1:
            continue
        r = ns[0]
        signs = {F.sign(_dot(row, r, F)) for row in rows}
        if signs <= {0, 1}:
            return list(r)
        if signs <= {0, -1}:
            return [-x for x in r]
    return None
