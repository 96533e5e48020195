"""Exact rationals: conversions between python-flint ``fmpq``/``fmpq_mat`` and SymPy.

Rational data (integers, ``Rational``, ``Fraction`` and floats, taken at their exact binary
value) are computed with python-flint; everything else stays a SymPy expression. These are the
only conversions the laws use.

>>> as_fmpq(0.5), as_fmpq(sp.Rational(-2, 6)), as_fmpq(sp.sqrt(2)) is None
(1/2, -1/3, True)
>>> to_sympy_rational(to_fmpq("3/4"))
3/4
"""

from __future__ import annotations

import math
import sys
from fractions import Fraction
from typing import Any

import flint
import numpy as np

from . import LazyModule
from . import sympy_instance as _sympy_instance
from ..errors import ImpactInputError

#: SymPy, imported on first use: the rational paths (python-flint) run without it
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["float_to_rational", "as_fmpq", "to_fmpq", "bits", "rational_matrix", "to_sympy_rational", "to_sympy_matrix",
           "exact_data", "all_rational", "float_vector", "rational_sqrt"]


def _finite_float(x) -> float:
    xf = float(x)
    if not math.isfinite(xf):
        raise ImpactInputError("value", f"must be finite, got {xf}")
    return xf


def _float_fraction(x) -> Fraction:
    return Fraction(_finite_float(x))


def float_to_rational(x: float) -> sp.Rational:
    """The exact binary value of a float, as a SymPy ``Rational`` (never re-rounded).

    >>> float_to_rational(0.1)
    3602879701896397/36028797018963968
    >>> float_to_rational(float("inf"))
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: value: must be finite, got inf
    """
    f = _float_fraction(x)
    return sp.Rational(f.numerator, f.denominator)


def as_fmpq(x) -> flint.fmpq | None:
    """``x`` as an exact ``fmpq`` (a float at its binary value), or ``None`` when ``x`` is not
    rational (``sqrt(2)``, ``pi``).

    >>> as_fmpq(0.1), as_fmpq(3), as_fmpq(sp.pi)
    (3602879701896397/36028797018963968, 3, None)
    """
    if isinstance(x, flint.fmpq):
        return x
    if isinstance(x, (float, np.floating)):
        return flint.fmpq(*_finite_float(x).as_integer_ratio())  # Fraction(x)'s terms: its binary value
    if isinstance(x, (int, np.integer)):
        return flint.fmpq(int(x))
    if isinstance(x, Fraction):
        return flint.fmpq(x.numerator, x.denominator)
    if isinstance(x, flint.fmpz):
        return flint.fmpq(x)
    x = sp.sympify(x)
    if x.is_Rational:
        return flint.fmpq(int(x.p), int(x.q))
    return None


def to_fmpq(x) -> flint.fmpq:
    """Like :func:`as_fmpq`, but an irrational ``x`` raises ``ValueError``.

    >>> to_fmpq("1/3")
    1/3
    """
    q = as_fmpq(x)
    if q is None:
        raise ValueError(f"x: {x} is not rational")
    return q


def bits(x: flint.fmpq) -> int:
    """Bit length of the larger of numerator and denominator.

    >>> bits(flint.fmpq(-5, 16))
    5
    """
    return max(int(x.p).bit_length(), int(x.q).bit_length())


def rational_sqrt(q: flint.fmpq) -> flint.fmpq | None:
    """``√q`` when it is rational (``q ≥ 0`` a square of a rational), else ``None``.

    >>> rational_sqrt(flint.fmpq(9, 4)), rational_sqrt(flint.fmpq(2))
    (3/2, None)
    """
    p, d = int(q.p), int(q.q)
    if p < 0:
        return None
    rp, rd = math.isqrt(p), math.isqrt(d)
    if rp * rp == p and rd * rd == d:
        return flint.fmpq(rp, rd)
    return None


def all_rational(*mats) -> bool:
    """Whether every entry of the given SymPy matrices is a SymPy ``Rational``.

    >>> all_rational(sp.Matrix([1, sp.Rational(1, 2)])), all_rational(sp.Matrix([sp.sqrt(2)]))
    (True, False)
    """
    return all(x.is_Rational for m in mats for x in m)


def rational_matrix(A: Any) -> flint.fmpq_mat | None:
    """``A`` (SymPy matrix, nested list or float array) as an exact ``fmpq_mat``; ``None`` if an
    entry is irrational. A 1-D input becomes a column. Floats are taken at their binary value.

    >>> rational_matrix([0.5, 0.1])
    [                              1/2]
    [3602879701896397/36028797018963968]
    """
    if _sympy_instance(A, "MatrixBase"):
        rows, cols = A.shape
        entries = list(A)
    elif isinstance(A, np.ndarray) and A.dtype.kind == "f" and A.ndim in (1, 2):
        rows, cols = (A.shape[0], 1) if A.ndim == 1 else A.shape
        entries = A.ravel().tolist()  # (Python floats: what the object array below holds)
    else:
        arr = np.asarray(A, dtype=object)
        if arr.ndim == 1:
            arr = arr.reshape(-1, 1)
        rows, cols = arr.shape
        entries = list(arr.ravel())
    out = []
    for x in entries:
        q = as_fmpq(x)
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


def float_vector(vel) -> np.ndarray:
    """The nearest floats of a vector: exact SymPy (a rational correctly rounded, anything else
    through 17 digits), an ``mpmath.matrix`` or anything NumPy reads.

    >>> float_vector(sp.Matrix([sp.Rational(1, 3), sp.sqrt(2)]))
    array([0.33333333, 1.41421356])
    """
    if _sympy_instance(vel, "MatrixBase"):
        return np.array([float(Fraction(int(x.p), int(x.q))) if x.is_Rational else float(sp.N(x, 17)) for x in vel])
    mpmath = sys.modules.get("mpmath")  # an mpmath matrix exists only once mpmath is loaded
    if mpmath is not None and isinstance(vel, mpmath.matrix):
        return np.array([float(vel[i]) for i in range(vel.rows)])
    return np.asarray(vel, dtype=float)
