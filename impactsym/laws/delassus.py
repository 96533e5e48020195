"""The Delassus operator ``W = H M⁻¹ Hᵀ`` and the exact arithmetic shared by the multi-contact laws.

Every multi-contact law (impulse ratio, Newton/Moreau, Poisson, sequential) works with
``W = H M⁻¹ Hᵀ`` (the matrix of eq. 7, ``Δv = W p``) and with ``w = H v`` (relative normal
velocities). Its branch decisions are signs. They are decided

* in exact rational arithmetic (python-flint ``fmpq_mat``) when every entry is rational, which
  includes float input, taken at its exact binary value (``CONVENTIONS.md``: a float sign is
  re-decided exactly, never guessed);
* by :func:`impactsym.exact.certified_sign` when an entry is irrational (``sqrt(3)/2``, ``cos(pi/5)``).

Numbers of the form ``x + y√d`` (``x, y, d`` rational, ``d ≥ 0``), which is what a root of the
impulse-ratio quadratic produces, get their sign exactly by :func:`sign_surd`.

>>> import sympy as sp
>>> R = rational_matrix(sp.Matrix([[1, sp.Rational(1, 2)], [0, 3]]))
>>> R.solve(rational_matrix(sp.Matrix([1, 3])))[0, 0]
1/2
>>> rational_matrix(sp.Matrix([[sp.sqrt(2)]])) is None
True
>>> sign_surd(sp.Rational(3, 2), -1, 2)   # 3/2 - sqrt(2) > 0
1
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import flint
import numpy as np
import sympy as sp

from ..exact import certified_sign
from ..numbers import float_to_rational

__all__ = ["ExactLinearAlgebra", "exact_data", "exact_rank", "rational_matrix", "to_sympy_rational", "to_sympy_matrix", "sign_of", "sign_surd", "delassus"]


def _fmpq(x) -> flint.fmpq | None:
    if isinstance(x, flint.fmpq):
        return x
    if isinstance(x, (float, np.floating)):
        r = float_to_rational(float(x))
        return flint.fmpq(int(r.p), int(r.q))
    if isinstance(x, (int, np.integer)):
        return flint.fmpq(int(x))
    x = sp.sympify(x)
    if x.is_Rational:
        return flint.fmpq(int(x.p), int(x.q))
    return None


def rational_matrix(A: Any) -> flint.fmpq_mat | None:
    """``A`` (SymPy matrix, nested list or float array) as an exact ``fmpq_mat``; ``None`` if an
    entry is irrational. A 1-D input becomes a column. Floats are taken at their binary value.

    >>> rational_matrix([0.5, 0.1])
    [                              1/2]
    [3602879701896397/36028797018963968]
    """
    if isinstance(A, sp.MatrixBase):
        rows, cols = A.shape
        entries = list(A)
    else:
        arr = np.asarray(A, dtype=object)
        if arr.ndim == 1:
            arr = arr.reshape(-1, 1)
        rows, cols = arr.shape
        entries = list(arr.ravel())
    out = []
    for x in entries:
        q = _fmpq(x)
        if q is None:
            return None
        out.append(q)
    return flint.fmpq_mat(rows, cols, out)


def to_sympy_rational(x: flint.fmpq) -> sp.Rational:
    """An ``fmpq`` as a SymPy ``Rational``.

    >>> to_sympy_rational(flint.fmpq(-2, 6))
    -1/3
    """
    return sp.Rational(int(x.p), int(x.q))


def to_sympy_matrix(A: flint.fmpq_mat) -> sp.Matrix:
    """An ``fmpq_mat`` as a SymPy matrix of ``Rational``.

    >>> to_sympy_matrix(flint.fmpq_mat(1, 2, [1, flint.fmpq(1, 2)]))
    Matrix([[1, 1/2]])
    """
    return sp.Matrix(A.nrows(), A.ncols(), [to_sympy_rational(A[i, j]) for i in range(A.nrows()) for j in range(A.ncols())])


def sign_of(x) -> int:
    """Exact sign of an ``fmpq``, a SymPy number or an int (certified for irrational SymPy numbers).

    >>> sign_of(flint.fmpq(-1, 3)), sign_of(sp.sqrt(2) - sp.Rational(3, 2)), sign_of(0)
    (-1, -1, 0)
    """
    if isinstance(x, flint.fmpq):
        return (x > 0) - (x < 0)
    return certified_sign(x)


def sign_surd(x, y, d) -> int:
    """Exact sign of ``x + y√d`` for rational ``x, y`` and rational ``d ≥ 0``.

    Decided by comparing ``x²`` with ``y²d`` when ``x`` and ``y√d`` have opposite signs; no
    square root is evaluated.

    >>> sign_surd(-1, 1, 1), sign_surd(-2, 1, 3), sign_surd(0, -1, 5)
    (0, -1, -1)
    """
    sx, sy, sd = sign_of(x), sign_of(y), sign_of(d)
    if sd < 0:
        raise ValueError("sign_surd: d must be non-negative")
    if sd == 0 or sy == 0:
        return sx
    if sx == 0:
        return sy
    if sx == sy:
        return sx
    return sx * sign_of(x * x - y * y * d)


def delassus(M, H):
    """``W = H M⁻¹ Hᵀ`` (symmetric, positive semi-definite; eq. 7 reads ``Δv = W p``).

    Exact (SymPy) for SymPy input, ``fmpq_mat`` for ``fmpq_mat`` input, float otherwise.

    >>> delassus(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]))
    Matrix([
    [ 2, -1],
    [-1,  2]])
    """
    if isinstance(M, flint.fmpq_mat):
        return H * M.solve(H.transpose())
    if isinstance(M, sp.MatrixBase):
        return H * M.LUsolve(H.T)
    H = np.asarray(H, dtype=float)
    return H @ np.linalg.solve(np.asarray(M, dtype=float), H.T)


def exact_data(*mats):
    """The given matrices/vectors in one exact arithmetic: all ``fmpq_mat`` when every entry is
    rational (floats at their binary value), else all SymPy matrices (exact, possibly irrational).

    Returns ``(kind, mats)`` with ``kind`` ``"rational"`` or ``"sympy"``.

    >>> kind, (A, b) = exact_data(np.eye(2), [0.5, 1])
    >>> kind, b[0, 0]
    ('rational', 1/2)
    >>> exact_data(sp.Matrix([[sp.sqrt(2)]]), sp.Matrix([1]))[0]
    'sympy'
    """
    rats = [rational_matrix(m) for m in mats]
    if all(r is not None for r in rats):
        return "rational", rats
    out = []
    for m in mats:
        if isinstance(m, sp.MatrixBase):
            out.append(sp.Matrix(m))
        else:
            arr = np.asarray(m, dtype=object)
            if arr.ndim == 1:
                arr = arr.reshape(-1, 1)
            out.append(sp.Matrix([[float_to_rational(x) if isinstance(x, (float, np.floating)) else sp.sympify(x)
                                   for x in row] for row in arr]))
    return "sympy", out


class ExactLinearAlgebra:
    """The few exact operations the multi-contact laws need, in one arithmetic: ``"rational"``
    (python-flint ``fmpq_mat``) or ``"sympy"`` (exact SymPy matrices, certified signs).

    >>> la = ExactLinearAlgebra("rational")
    >>> A = rational_matrix(sp.Matrix([[2, -1], [-1, 2]]))
    >>> la.solve(la.extract(A, [0], [0]), la.column([1]))[0, 0], la.solve(rational_matrix(sp.Matrix([[1, 1], [1, 1]])), la.column([1, 1]))
    (1/2, None)
    """

    def __init__(self, kind: str):
        if kind not in ("rational", "sympy"):
            raise ValueError(f"kind must be 'rational' or 'sympy', got {kind!r}")
        self.kind = kind

    def extract(self, A, rows, cols):
        if self.kind == "sympy":
            return A.extract(list(rows), list(cols))
        return flint.fmpq_mat(len(rows), len(cols), [A[i, j] for i in rows for j in cols])

    def column(self, values):
        if self.kind == "sympy":
            return sp.Matrix(list(values))
        vals = [v if isinstance(v, flint.fmpq) else _fmpq(v) for v in values]
        return flint.fmpq_mat(len(vals), 1, vals)

    def zeros(self, r, c):
        return sp.zeros(r, c) if self.kind == "sympy" else flint.fmpq_mat(r, c)

    def rows(self, A) -> int:
        return A.rows if self.kind == "sympy" else A.nrows()

    def solve(self, A, b):
        """``A⁻¹ b``, or ``None`` when ``A`` is singular (decided exactly)."""
        n = self.rows(A)
        if n == 0:
            return self.zeros(0, 1)
        if self.kind == "rational":
            if A.rank() < n:
                return None
            return A.solve(b)
        det = sp.simplify(A.det(method="berkowitz"))
        if sign_of(det) == 0:
            return None
        return A.LUsolve(b).applyfunc(tidy)

    def rank(self, A) -> int:
        if self.kind == "rational":
            return A.rank()
        return exact_rank(A)

    def to_sympy(self, X):
        if self.kind == "sympy":
            return X
        if isinstance(X, flint.fmpq_mat):
            return to_sympy_matrix(X)
        return to_sympy_rational(X) if isinstance(X, flint.fmpq) else sp.sympify(X)


def exact_rank(A) -> int:
    """The rank of a matrix of exact SymPy numbers, decided exactly (no rounding, no ``nsimplify``).

    Rational and algebraic entries (``sqrt(2)``, ``cos(pi/5)`` once SymPy writes it as a surd) are
    reduced in their number field (``DomainMatrix`` over ``QQ`` or ``QQ<...>``); any other entries by
    Gaussian elimination whose every zero test is :func:`impactsym.exact.certified_sign` (which
    raises rather than guess).

    Parameters
    ----------
    A : sympy.Matrix of numbers (no free symbols)

    Returns
    -------
    int

    Raises
    ------
    ValueError
        ``A`` has free symbols.

    Examples
    --------
    A non-singular matrix whose determinant is ``-13*sqrt(2)/10**34`` (``nsimplify`` rounds it to a
    singular one):

    >>> A = sp.Matrix([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2 - sp.Rational(13, 10**34)]])
    >>> exact_rank(A), exact_rank(sp.Matrix([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2]]))
    (2, 1)
    >>> exact_rank(sp.Matrix([[sp.pi, 1], [1, 1 / sp.pi]])), exact_rank(sp.Matrix([[sp.pi, 1], [1, sp.E]]))
    (1, 2)
    """
    from sympy.polys.matrices import DomainMatrix

    A = sp.Matrix(A)
    if A.free_symbols:
        raise ValueError(f"A: exact_rank needs numbers, got the symbols {sorted(map(str, A.free_symbols))}")
    if A.rows == 0 or A.cols == 0:
        return 0
    try:
        dM = DomainMatrix.from_Matrix(A, extension=True)
    except Exception:  # noqa: BLE001 - no number field found: fall back to certified elimination
        dM = None
    if dM is not None and (dM.domain.is_ZZ or dM.domain.is_QQ or dM.domain.is_AlgebraicField):
        return dM.to_field().rank()
    rows = [[sp.sympify(x) for x in A.row(i)] for i in range(A.rows)]
    rank, col = 0, 0
    while rank < len(rows) and col < A.cols:
        pivot = next((i for i in range(rank, len(rows)) if certified_sign(rows[i][col]) != 0), None)
        if pivot is None:
            col += 1
            continue
        rows[rank], rows[pivot] = rows[pivot], rows[rank]
        pr = rows[rank]
        for i in range(rank + 1, len(rows)):
            f = rows[i][col] / pr[col]
            rows[i] = [sp.radsimp(rows[i][j] - f * pr[j]) for j in range(A.cols)]
        rank += 1
        col += 1
    return rank


def tidy(x):
    """A canonical-looking exact form of a closed-form number (value unchanged): rationals stay,
    nested square roots are denested (``sqrt(10*sqrt(5) + 30)`` → ``sqrt(5) + 5``... when SymPy can),
    denominators rationalized; a number whose minimal polynomial is linear becomes that rational.

    >>> tidy(sp.sympify("(-sqrt(10)*sqrt(sqrt(5) + 3) - 3 + sqrt(5))**2/64"))
    1
    >>> tidy(sp.sympify("7/29 + (-8*sqrt(5) + 5*sqrt(2*sqrt(5) + 6) + 11*sqrt(10*sqrt(5) + 30))/116"))
    2*sqrt(5)/29 + 22/29
    """
    x = sp.sympify(x)
    if x.is_Rational:
        return x
    if x.free_symbols:
        return sp.simplify(x)
    y = sp.radsimp(sp.sqrtdenest(sp.expand(x)))
    y = sp.radsimp(sp.simplify(y))
    if y.is_Rational:
        return y
    # a rational in disguise? guess it from 40 digits, then confirm exactly (certified sign 0)
    try:
        val = y.evalf(40)
        if val.is_real:
            guess = Fraction(str(sp.Float(val, 40))).limit_denominator(10**12)
            r = sp.Rational(guess.numerator, guess.denominator)
            if abs(val - r) < sp.Float("1e-30") * (1 + abs(r)) and certified_sign(y - r) == 0:
                return r
    except Exception:  # noqa: BLE001 - a number SymPy cannot evaluate: keep the simplified form
        pass
    return y
