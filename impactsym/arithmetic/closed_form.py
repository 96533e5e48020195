"""Certified signs, comparisons and canonical forms of closed-form real numbers (SymPy).

Every branch of an impact law (is contact *i* approaching? is Δ ≥ 0? is ``p_j`` ≥ 0?) is a sign
test. For exact input it is decided exactly; for algebraic and transcendental numbers it is
decided by interval evaluation at rising precision until the enclosure excludes zero, and by the
minimal polynomial when the number may be zero. A sign that cannot be certified raises
:class:`~impactsym.errors.UndecidableSign`; it is never guessed.

>>> import sympy as sp
>>> certified_sign(sp.Rational(-1, 3)), certified_sign(sp.sqrt(2) - sp.Rational(141421, 100000))
(-1, 1)
>>> certified_sign(sp.sqrt(3) / 2 - sp.sin(sp.pi / 3))
0
>>> certified_sign(sp.sqrt(8) - 2 * sp.sqrt(2))
0
>>> certified_sign(sp.sqrt(2 - sp.sqrt(2)) / 2 - sp.sqrt(sp.Rational(1, 2) - sp.sqrt(2) / 4))
0
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

from . import LazyModule
from ..errors import UndecidableSign

#: SymPy, imported on first use: the rational paths (python-flint) run without it
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["certified_sign", "certified_compare", "tidy", "arb_tree"]

_MAX_DIGITS = 2000


def _rational_sign(x: sp.Expr) -> int | None:
    if x.is_Rational:
        return int(bool(x > 0)) - int(bool(x < 0))
    return None


def certified_sign(expr, *, max_digits: int = _MAX_DIGITS) -> int:
    """The sign (-1, 0, 1) of a real exact number, certified.

    Parameters
    ----------
    expr : sympy.Expr or int or Fraction
        A closed-form real number (no free symbols).
    max_digits : int
        Largest precision tried before giving up.

    Raises
    ------
    UndecidableSign
        When neither an exact zero test nor interval evaluation up to ``max_digits`` decides.
    """
    try:
        return _certified_sign_cached(expr, max_digits)
    except TypeError as exc:  # an unhashable argument: decided without the memo
        if "unhashable" not in str(exc):
            raise
        return _certified_sign(expr, max_digits)


def _certified_sign(expr, max_digits: int) -> int:
    x = sp.sympify(expr)
    if x.free_symbols:
        raise UndecidableSign(f"cannot take the sign of an expression with free symbols {x.free_symbols}")
    s = _rational_sign(x)
    if s is not None:
        return s
    s = _ball_sign(x)
    if s is not None:
        return s
    s = _multiquadratic_sign(x)
    if s is not None:
        return s
    # (no early ``x.is_zero``: SymPy's assumption inference on a large expression costs more than
    # the enclosure below, and a zero is still recognized by ``_exact_zero`` after it)
    # Interval evaluation: mpmath-backed evalf with the error estimate; accept only when the
    # value's magnitude exceeds its error bound (sympy's evalf is rigorous for the closed-form
    # functions it knows: its result carries accuracy, and strict=True refuses otherwise).
    digits = 15
    while digits <= max_digits:
        try:
            val = x.evalf(digits, strict=True, maxn=4 * digits)
        except Exception:  # PrecisionExhausted: the value may be 0
            val = None
        if val is not None and val.is_Number and val != 0:
            return 1 if val > 0 else -1
        # Maybe exactly zero: try an exact zero test for algebraic numbers.
        if digits == 15 or digits >= 120:
            z = _exact_zero(x)
            if z is True:
                return 0
        if digits == 15:
            # strict evalf refuses an expression with a sub-sum that is exactly zero (it cannot
            # certify that sub-sum's sign), although the whole need not be zero: an unevaluated
            # form (built under evaluate(False)) such as (a − a)/2048 + 1 is 1. Its expansion is
            # the same number; where it is rational that is the sign, else it is evaluated instead.
            e = sp.expand(x)
            s = _rational_sign(e)
            if s is not None:
                return s
            x = e
        digits *= 2
    raise UndecidableSign(f"the sign of {x} could not be certified at {max_digits} digits")


class _NoBall(Exception):
    """The expression holds a node :func:`arb_tree` does not evaluate (a Float, ``I``, ...)."""


def _power(b, n: int, one):
    """``b**n`` for an integer ``n >= 0`` by repeated squaring, from ``one`` (the products of the
    element's own type: for a ball that holds 0 they are valid where Arb's general power is
    ``nan``; in a multiquadratic field they stay exact)."""
    acc = one
    while n:
        if n & 1:
            acc = acc * b
        n >>= 1
        if n:
            b = b * b
    return acc


def _arb_ipow(b, n: int):
    """``b**n`` for an integer ``n >= 0`` on Arb balls (:func:`_power`)."""
    from flint import arb

    return _power(b, n, arb(1))


def _sum_or_product(x, node):
    """The sum or product of ``node`` of ``x``'s terms, in the order of ``x.args`` (``None`` if
    ``x`` is neither an ``Add`` nor a ``Mul``): the two trees' common step."""
    if not (x.is_Add or x.is_Mul):
        return None
    acc = node(x.args[0])
    for a in x.args[1:]:
        acc = acc + node(a) if x.is_Add else acc * node(a)
    return acc


def _arb_functions():
    """SymPy function class -> its Arb enclosure (arguments: balls); Arb returns ``nan`` outside
    a function's real domain (``log`` of a ball holding 0, ``acos`` beyond ±1)."""
    from flint import arb

    return {sp.sin: arb.sin, sp.cos: arb.cos, sp.tan: arb.tan, sp.exp: arb.exp, sp.log: arb.log,
            sp.atan: arb.atan, sp.asin: arb.asin, sp.acos: arb.acos, sp.Abs: abs,
            sp.atan2: lambda y, x: arb.atan2(y, x)}


_ARB_FUNCTIONS: dict = {}


def arb_tree(x, prec: int):
    """An Arb ball enclosing the real closed-form number ``x`` (SymPy), by ball arithmetic on its
    expression tree at working precision ``prec``; ``None`` when the tree holds a node it does
    not evaluate (a Float, ``I``, a function outside ``sin cos tan exp log atan asin acos Abs
    atan2``, a root of a number not certainly positive) or the ball is not finite (a division by
    a ball holding 0, a function outside its domain). Every operation is Arb's, so the ball is
    rigorous whatever the working precision (which only sets its width); the tree is read as
    built, so an unevaluated sub-sum that is exactly zero is a narrow ball around 0 (where
    SymPy's strict ``evalf`` refuses). The ball is made and should be read inside one
    ``ctx.workprec(prec)`` block (it is made inside such a block here).

    >>> from flint import arb
    >>> b = arb_tree(sp.sqrt(2) * sp.pi - sp.Rational(1, 3), 100)
    >>> b.overlaps(arb("4.1095496048250329136825476567") + arb(0, 1e-28)), b.rad() < 2.0 ** -90
    (True, True)
    >>> arb_tree(sp.sqrt(-2 + sp.sqrt(3)), 100) is None, arb_tree(sp.Float(0.5), 100) is None
    (True, True)
    """
    from flint import ctx

    with ctx.workprec(prec):
        try:
            b = _arb_node(x)
        except (_NoBall, RecursionError, ZeroDivisionError, ValueError):
            return None
        return b if b.is_finite() else None


def _arb_node(x):
    from flint import arb, fmpq

    if x.is_Rational:
        return arb(int(x.p)) if x.q == 1 else arb(fmpq(int(x.p), int(x.q)))
    acc = _sum_or_product(x, _arb_node)
    if acc is not None:
        return acc
    if x.is_Pow:
        base, e = x.args
        b = _arb_node(base)
        if e.is_Integer:
            n = int(e)
            return _arb_ipow(b, n) if n >= 0 else 1 / _arb_ipow(b, -n)
        if not b > 0:  # a real power needs a positive base (SymPy's principal branch is complex)
            raise _NoBall
        if e.is_Rational:
            p, q = int(e.p), int(e.q)
            r = b.sqrt() if q == 2 else b.root(q)
            return _arb_ipow(r, p) if p >= 0 else 1 / _arb_ipow(r, -p)
        return (_arb_node(e) * b.log()).exp()
    if x is sp.pi:
        return arb.pi()
    if x is sp.E:
        return arb.const_e()
    if x.is_Function:
        if not _ARB_FUNCTIONS:
            _ARB_FUNCTIONS.update(_arb_functions())
        f = _ARB_FUNCTIONS.get(x.func)
        if f is None:
            raise _NoBall
        return f(*(_arb_node(a) for a in x.args))
    raise _NoBall


#: working precisions (bits) of the ball test of a sign, before the evalf ladder below it
_BALL_SIGN_BITS = (96, 384)


def _ball_sign(x) -> int | None:
    """The sign of ``x`` when a ball of :func:`arb_tree` excludes 0 (certain: Arb's comparisons
    are), else ``None``. A few tenths of a millisecond where SymPy's strict ``evalf`` of the
    laws' nested iterates takes tens of milliseconds, and, on an unevaluated form with an exactly
    zero sub-sum (which strict evalf refuses), seconds of assumption queries in ``_exact_zero``."""
    from flint import ctx

    for prec in _BALL_SIGN_BITS:
        b = arb_tree(x, prec)
        if b is None:
            return None
        with ctx.workprec(prec):
            if b > 0:
                return 1
            if b < 0:
                return -1
    return None


#: most distinct primes under the square roots of a number decided in its multiquadratic field
#: (an inverse takes one conjugate per prime, each doubling the terms: 2^k of them)
_MQ_MAX_PRIMES = 6
#: largest radicand (bits) factored to find the square-free part of a square root
_MQ_MAX_RADICAND_BITS = 64
#: largest integer exponent taken exactly (the coefficients grow linearly with it)
_MQ_MAX_POWER = 1 << 12


class _MQ:
    """An element ``Σ c_m √m`` of a multiquadratic field ``Q(√p₁, …, √p_k)``: ``{m: c_m}`` with
    ``m`` square-free positive integers (``1``: the rational part) and ``fmpq`` coefficients ``≠ 0``.
    The ``√m`` of distinct square-free ``m`` are linearly independent over ``Q`` (Besicovitch), so
    the element is zero exactly when the dict is empty."""

    __slots__ = ("t",)

    def __init__(self, t):
        self.t = t

    @staticmethod
    def _accumulate(t: dict, m: int, c) -> None:
        # t[m] += c, the key dropped where the coefficient becomes 0 (no zero is ever stored)
        c2 = t.get(m, 0) + c
        if c2:
            t[m] = c2
        else:
            t.pop(m, None)

    def __add__(self, o):
        t = dict(self.t)
        for m, c in o.t.items():
            self._accumulate(t, m, c)
        return _MQ(t)

    def __mul__(self, o):
        from math import gcd

        t: dict = {}
        for m1, c1 in self.t.items():
            for m2, c2 in o.t.items():
                g = gcd(m1, m2)
                self._accumulate(t, (m1 // g) * (m2 // g), c1 * c2 * g)
        return _MQ(t)

    def primes(self):
        from flint import fmpz

        ps = set()
        for m in self.t:
            if m > 1:
                ps.update(int(p) for p, _ in fmpz(m).factor())
        return ps

    def inverse(self):
        """``1/self`` by one conjugation (``√p → −√p``) per prime: the product of ``self`` and its
        conjugates over ``p₁ … p_j`` has no ``√p_i`` with ``i ≤ j``, so it ends rational."""
        ps = sorted(self.primes())
        if len(ps) > _MQ_MAX_PRIMES:
            raise _NoBall
        from flint import fmpq

        num, den = _MQ({1: fmpq(1)}), self
        for p in ps:
            conj = _MQ({m: (-c if m % p == 0 else c) for m, c in den.t.items()})
            num, den = num * conj, den * conj
        if not den.t:
            raise ZeroDivisionError
        if list(den.t) != [1]:  # (the norm is rational; otherwise no decision here, the ladder decides)
            raise _NoBall
        r = den.t[1]
        return _MQ({m2: c / r for m2, c in num.t.items()})


def _mq_node(x) -> _MQ:
    from flint import fmpq, fmpz

    if x.is_Rational:
        return _MQ({1: fmpq(int(x.p), int(x.q))} if x.p else {})
    acc = _sum_or_product(x, _mq_node)
    if acc is not None:
        return acc
    if x.is_Pow:
        base, e = x.args
        if e.is_Integer:
            return _mq_node_pow(_mq_node(base), int(e))
        if e.is_Rational and e.q == 2 and base.is_Rational and base > 0:
            # (p/q)^(k/2) = (√(pq)/q)^k, √(pq) = s√m with m square-free
            p, q = int(base.p), int(base.q)
            if (p * q).bit_length() > _MQ_MAX_RADICAND_BITS:
                raise _NoBall
            s, m = 1, 1
            for f, k in fmpz(p * q).factor():
                s *= int(f) ** (k // 2)
                if k % 2:
                    m *= int(f)
            root = _MQ({m: fmpq(s, q)})
            return _mq_node_pow(root, int(e.p))
        raise _NoBall
    raise _NoBall


def _mq_node_pow(b: _MQ, n: int) -> _MQ:
    from flint import fmpq

    if abs(n) > _MQ_MAX_POWER:
        raise _NoBall
    if n < 0:
        b, n = b.inverse(), -n
    return _power(b, n, _MQ({1: fmpq(1)}))


def multiquadratic(x) -> dict | None:
    """``x`` (a SymPy number built from rationals by ``+ × ÷``, integer powers and square roots
    of positive rationals) as ``{m: c_m}``, ``x = Σ c_m √m`` over distinct square-free ``m``
    (``fmpq`` coefficients, none zero: ``{}`` is exactly 0); ``None`` for any other number (a
    nested radical, ``pi``, a function) or more than six primes under the roots. Exact (python-flint
    rationals), so it decides a zero that the ball of :func:`arb_tree` can only bracket.

    >>> sorted(multiquadratic(sp.sqrt(2) * (1 + sp.sqrt(6)) / (2 - sp.sqrt(3))).items())   # 6 + 2√2 + 4√3 + √6
    [(1, 6), (2, 2), (3, 4), (6, 1)]
    >>> multiquadratic(sp.sqrt(8) - 2 * sp.sqrt(2)), multiquadratic(sp.sqrt(1 + sp.sqrt(2))) is None
    ({}, True)
    """
    try:
        return _mq_node(x).t
    except (_NoBall, ZeroDivisionError, RecursionError):
        return None


def _multiquadratic_sign(x) -> int | None:
    """The sign of ``x`` decided in its multiquadratic field (:func:`multiquadratic`): ``0``
    when the exact element is zero, else the sign of ``Σ c_m √m`` on Arb balls at rising precision
    (certain to end: the sum is not zero, and it has no cancelling sub-sums left); ``None`` when
    ``x`` is not such a number."""
    from flint import arb, ctx, fmpq

    t = multiquadratic(x)
    if t is None:
        return None
    if not t:
        return 0
    prec = 128
    while prec <= 1 << 16:
        with ctx.workprec(prec):
            b = sum((arb(c) * arb(m).sqrt() for m, c in t.items()), arb(0))
            if b > 0:
                return 1
            if b < 0:
                return -1
        prec *= 4
    return None


def _exact_zero(x: sp.Expr) -> bool | None:
    # denested and expanded to 0 is a proof (both are identities); a few milliseconds where the
    # assumption system (``is_zero``) takes tens on the nested radicals of the pool's angles
    # (``sqrt(2 - sqrt(2))/2 - sqrt(1/2 - sqrt(2)/4)``). Only a proof of zero is taken from it.
    try:
        if sp.expand(sp.sqrtdenest(sp.expand(x))) == 0:
            return True
    except Exception:  # pragma: no cover - a transformation failure is no decision
        pass
    if x.is_zero is not None:
        return bool(x.is_zero)
    try:
        # no nsimplify here: it rounds a tiny non-zero number (pi - acos(-1 + 1e-300)) to 0,
        # which is a guess, not a proof
        simp = sp.radsimp(sp.simplify(x))
        if simp == 0:
            return True
    except Exception:  # pragma: no cover - simplify failures are not decisions
        pass
    try:
        poly = sp.minimal_polynomial(x, sp.Dummy("z"))
        if sp.Poly(poly).degree() == 1 and sp.Poly(poly).nth(0) == 0:
            return True
        # A non-zero algebraic number has a minimal polynomial other than z.
        return False if poly.free_symbols else None
    except Exception:
        return None


def certified_compare(a, b, **kw) -> int:
    """Certified sign of ``a - b`` (-1, 0 or 1).

    >>> import sympy as sp
    >>> certified_compare(sp.sqrt(2), sp.Rational(3, 2))
    -1
    """
    return certified_sign(sp.sympify(a) - sp.sympify(b), **kw)


def tidy(x):
    """A canonical-looking exact form of a closed-form number (value unchanged): rationals stay,
    nested square roots are denested (``sqrt(10*sqrt(5) + 30)`` → ``sqrt(5) + 5``... when SymPy can),
    denominators rationalized; a number whose minimal polynomial is linear becomes that rational.

    >>> tidy(sp.sympify("(-sqrt(10)*sqrt(sqrt(5) + 3) - 3 + sqrt(5))**2/64"))
    1
    >>> tidy(sp.sympify("7/29 + (-8*sqrt(5) + 5*sqrt(2*sqrt(5) + 6) + 11*sqrt(10*sqrt(5) + 30))/116"))
    2*sqrt(5)/29 + 22/29
    """
    try:
        return _tidy_cached(x)
    except TypeError as exc:  # an unhashable argument: computed without the memo
        if "unhashable" not in str(exc):
            raise
        return _tidy(x)


def _surd_term(t) -> bool:
    """``t`` is ``√n`` or ``q·√n`` as SymPy builds it (``q`` rational, ``n`` an integer > 1)."""
    if t.is_Mul:
        if len(t.args) != 2 or not t.args[0].is_Rational:
            return False
        t = t.args[1]
    return t.is_Pow and t.exp is sp.S.Half and t.base.is_Integer and t.base > 1


def _quadratic_surd(x) -> bool:
    """``x`` is ``r + q·√n`` (``r``, ``q`` rational, ``n > 1`` an integer) in the form SymPy's
    constructors give it: the canonical element of ``Q(√n)``, which ``tidy`` leaves as it is."""
    if x.is_Add:
        if len(x.args) != 2:
            return False
        a, b = x.args
        return (a.is_Rational and _surd_term(b)) or (b.is_Rational and _surd_term(a))
    return _surd_term(x)


def _surd_sum(e) -> bool:
    """``e`` is a sum of rationals and rational multiples of square roots of integers, as SymPy's
    ``expand`` gives it (``Σ qᵢ√nᵢ + r``, the ``nᵢ > 1`` square-free and distinct, so ``e`` is
    irrational): an element of a multiquadratic field written on its basis."""
    return e.is_Add and all(a.is_Rational or _surd_term(a) for a in e.args)


def _tidy(x):
    x = sp.sympify(x)
    if x.is_Rational:
        return x
    if _quadratic_surd(x):
        # r + q√n: nothing to denest, no denominator to rationalize, and irrational (SymPy
        # evaluates the √ of a perfect square); the generic route (expand, sqrtdenest, radsimp,
        # simplify, a 40-digit rational guess) returns the same expression at ~10 ms a number
        # (tests/test_arithmetic.py compares the two routes)
        return x
    if not x.free_symbols:
        e = sp.expand(x)
        if _surd_sum(e):
            # Σ qᵢ√nᵢ + r (the laws' p₁·w entries on the pool's angles): nothing to denest, and
            # simplify gives the expanded sum back (its candidates are the sum over a common
            # denominator, which its last step multiplies out again), so the generic route ends in
            # radsimp of the expanded sum, irrational; the same expression without simplify's
            # search (tests/test_arithmetic.py compares the two routes)
            return sp.radsimp(e)
    return _tidy_generic(x)


def _tidy_generic(x):
    # simplify through its SymPy-only memo (the same expression: sp.simplify's), which the mutation
    # tests keep when they clear impactsym's caches (this function's own memo, _tidy_cached, is cleared)
    from .remembered import simplify_remembered

    if x.free_symbols:
        return simplify_remembered(x)
    y = sp.radsimp(sp.sqrtdenest(sp.expand(x)))
    y = sp.radsimp(simplify_remembered(y))
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


#: memos of the two pure functions above (typed: an Integer and a Float never share an entry);
#: the laws and the paper checks ask the same signs and canonical forms again and again
_certified_sign_cached = lru_cache(maxsize=8192, typed=True)(_certified_sign)
_tidy_cached = lru_cache(maxsize=8192, typed=True)(_tidy)
