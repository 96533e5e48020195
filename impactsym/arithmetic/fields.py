"""The two exact fields of the laws, with certified signs.

* :class:`RationalField`: python-flint ``fmpq``; signs are exact comparisons.
* :class:`AlgebraicField`: SymPy numbers (algebraic, or any closed form); every sign is
  :func:`~impactsym.arithmetic.closed_form.certified_sign` (it raises rather than guess).

Both offer the same small interface (``num``, ``sign``, ``norm``, ``to_sympy``, ``zero``,
``one``, ``surd_sign``) so that one algorithm serves both; the linear algebra on them is
:mod:`impactsym.arithmetic.linalg`.

>>> F = field_of(sp.Matrix([1, sp.Rational(1, 2)]))
>>> F.name, F.sign(F.num("-1/3")), field_of(sp.Matrix([sp.sqrt(2)])).name
('rational', -1, 'algebraic')
"""

from __future__ import annotations

import flint

from . import LazyModule
from .closed_form import _quadratic_surd, certified_sign
from .rational import all_rational, to_fmpq, to_sympy_rational

#: SymPy, imported on first use: the rational paths (python-flint) run without it
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["sign_of", "sign_surd", "compare_surds", "RationalField", "AlgebraicField", "field_of"]


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
    >>> sign_surd(flint.fmpq(3, 2), -1, 2)   # 3/2 - sqrt(2) > 0
    1
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


def compare_surds(x, y, F) -> int:
    """Exact sign of ``(a1 + b1√q1) − (a2 + b2√q2)`` for ``x = (a1, b1, q1)``, ``y = (a2, b2, q2)``
    (``q ≥ 0``) in the field ``F``: by squaring for rationals (no root evaluated), certified for
    algebraic numbers.

    >>> Q = RationalField
    >>> x, y = (Q.num(0), Q.num(1), Q.num(2)), (Q.num(0), Q.num(1), Q.num(3))   # √2 against √3
    >>> compare_surds(x, y, Q), compare_surds(y, x, Q), compare_surds(x, x, Q)
    (-1, 1, 0)
    >>> compare_surds((Q.num(1), Q.num(1), Q.num(2)), (Q.num(0), Q.num(1), Q.num(3)), Q)   # 1 + √2 > √3
    1
    """
    a1, b1, q1 = x
    a2, b2, q2 = y
    if F is AlgebraicField:
        return certified_sign(a1 + b1 * sp.sqrt(q1) - a2 - b2 * sp.sqrt(q2))
    if F.sign(b2) == 0 or F.sign(q2) == 0:
        return F.surd_sign(a1 - a2, b1, q1)
    if F.sign(b1) == 0 or F.sign(q1) == 0:
        return -F.surd_sign(a2 - a1, b2, q2)
    if q1 == q2:
        return F.surd_sign(a1 - a2, b1 - b2, q1)
    # A = (a1 - a2) + b1√q1 against C = b2√q2
    sA = F.surd_sign(a1 - a2, b1, q1)
    sC = F.sign(b2)
    if sA != sC:
        return (sA > sC) - (sA < sC)
    A2 = ((a1 - a2) * (a1 - a2) + b1 * b1 * q1, 2 * (a1 - a2) * b1, q1)
    d = F.surd_sign(A2[0] - b2 * b2 * q2, A2[1], A2[2])
    return sA * d


class RationalField:
    """Exact rationals with python-flint ``fmpq``.

    >>> RationalField.num(0.5), RationalField.to_sympy(flint.fmpq(2, 4))
    (1/2, 1/2)
    """

    name = "rational"
    zero = flint.fmpq(0)
    one = flint.fmpq(1)
    num = staticmethod(to_fmpq)
    to_sympy = staticmethod(to_sympy_rational)

    @staticmethod
    def sign(x) -> int:
        return (x > 0) - (x < 0)

    @staticmethod
    def norm(x):
        return x

    @staticmethod
    def surd_sign(alpha, beta, q) -> int:
        """Sign of ``alpha + beta·√q`` (``q ≥ 0``), exactly (:func:`sign_surd`)."""
        return sign_surd(alpha, beta, q)


class _SympyInteger:
    """A class attribute that is SymPy's ``Integer(n)``, made when first read (not at import)."""

    def __init__(self, n: int):
        self.n = n

    def __get__(self, obj, owner):
        return sp.Integer(self.n)


class AlgebraicField:
    """Exact SymPy numbers; every sign certified.

    >>> AlgebraicField.sign(sp.sqrt(2) - 1), AlgebraicField.norm((1 + sp.sqrt(2)) ** 2)
    (1, 2*sqrt(2) + 3)
    """

    name = "algebraic"
    zero = _SympyInteger(0)
    one = _SympyInteger(1)

    @staticmethod
    def num(x):
        return sp.sympify(x)

    @staticmethod
    def sign(x) -> int:
        return certified_sign(x)

    @staticmethod
    def norm(x):
        if x.is_Rational:
            return x
        y = sp.expand(x)
        # a rational or r + q√n has no denominator to rationalize: radsimp returns it as it is
        # (about 0.2 ms a call, most of an elimination's time on the pool's mostly rational rows)
        if y.is_Rational or _quadratic_surd(y):
            return y
        return sp.radsimp(y)

    @staticmethod
    def to_sympy(x):
        return x

    @staticmethod
    def surd_sign(alpha, beta, q) -> int:
        return certified_sign(alpha + beta * sp.sqrt(q))


def field_of(*mats):
    """:class:`RationalField` when every entry of the SymPy matrices is rational, else
    :class:`AlgebraicField`."""
    return RationalField if all_rational(*mats) else AlgebraicField
