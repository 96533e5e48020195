"""Certification with Arb balls (python-flint ``arb``) and their exact reads.

An Arb value is made and read inside one ``ctx.workprec`` block (issue 9): :func:`enclose`
is called inside the block; :func:`ball_ends`, :func:`certified_ceil` and :func:`arb_to_mpf` read
only exactly representable quantities of a ball (its midpoint and radius, with ``man_exp``), so
their result does not depend on the precision in force when they are called.

>>> from flint import ctx
>>> with ctx.workprec(100):
...     q = enclose(sp.sqrt(2), 100) * 3
>>> certified_ceil(q)
5
"""

from __future__ import annotations

import math

from flint import arb, fmpq

from .closed_form import arb_tree, certified_sign

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from . import LazyModule
mpmath = LazyModule("mpmath", globals(), "mpmath")
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["enclose", "enclose_narrow", "arf_fmpq", "ball_ends", "certified_ceil", "certified_ceiling", "nearest_int", "arb_to_mpf"]


def enclose(x, prec: int) -> arb:
    """An Arb ball enclosing the exact number ``x`` (fmpq or int exactly; SymPy by strict evalf);
    call inside ``ctx.workprec(prec)``.

    >>> from flint import ctx
    >>> with ctx.workprec(100):
    ...     b = enclose(sp.sqrt(2), 100)
    ...     ok = (b * b - 2).contains(0)
    >>> ok
    True
    """
    if isinstance(x, arb):
        return x
    if isinstance(x, fmpq):
        return arb(x)
    if isinstance(x, int):
        return arb(x)
    x = sp.sympify(x)
    if x.is_Rational:
        return arb(fmpq(int(x.p), int(x.q)))
    digits = int(prec * 0.30103) + 10
    if certified_sign(x) == 0:
        return arb(0)
    # SymPy's evalf with strict=True either reaches `digits` correct significant digits or raises;
    # the binary value it returns is taken exactly, and widened by a relative 10^-(digits-3).
    from sympy.core.evalf import PrecisionExhausted

    try:
        val = x.evalf(digits, strict=True)
    except PrecisionExhausted:
        # an unevaluated form (built under evaluate(False)) with a sub-sum that is exactly zero,
        # which strict evalf cannot certify, although the whole is not zero (certified_sign above
        # decided it by the expansion): the expansion is the same number
        x = sp.expand(x)
        if x.is_Rational:
            return arb(fmpq(int(x.p), int(x.q)))
        val = x.evalf(digits, strict=True)
    sgn, man, exp, _ = val._mpf_
    man = -int(man) if sgn else int(man)
    mid = arb(fmpq(man * 2**exp)) if exp >= 0 else arb(fmpq(man, 2 ** (-exp)))
    return mid + arb(0, abs(mid) * arb(10) ** (-(digits - 3)))


def enclose_narrow(x, prec: int) -> arb:
    """An Arb ball enclosing the exact number ``x`` with a radius below ``2^-(prec+24)·|mid|``
    (or ``2^-2prec`` absolutely): no wider than :func:`enclose`'s evalf ball (``10^-(d-3)·|mid|``
    at ``d = ⌊0.30103·prec⌋ + 10`` digits), for a check that only reads the ball (not its
    midpoint into an output); call inside ``ctx.workprec(prec)``.

    Exact numbers are taken as :func:`enclose` takes them; a SymPy expression by ball
    arithmetic on its tree (:func:`~impactsym.arithmetic.closed_form.arb_tree`) at ``prec + 64``
    bits, then ``2·prec + 64``, and by :func:`enclose` when neither is narrow enough (or the tree
    holds a node Arb does not evaluate): the balls of the laws' nested algebraic iterates
    without SymPy's strict ``evalf`` at ``0.3·prec`` digits (tens of milliseconds a number, and
    an expansion when an unevaluated sub-sum is exactly zero).

    >>> from flint import ctx
    >>> with ctx.workprec(200):
    ...     b = enclose_narrow(sp.sqrt(2) - 1, 200)
    ...     ok = ((b + 1) ** 2 - 2).contains(0) and b.rad() < 2.0 ** -220
    >>> ok
    True
    """
    if isinstance(x, (arb, fmpq, int)):
        return enclose(x, prec)
    x = sp.sympify(x)
    if x.is_Rational:
        return enclose(x, prec)
    for wp in (prec + 64, 2 * prec + 64):
        b = arb_tree(x, wp)
        if b is None:
            break
        # exact reads of the radius and midpoint (no rounding at any precision)
        rad, mid = arf_fmpq(b.rad()), abs(arf_fmpq(b.mid()))
        if rad <= mid / (fmpq(2) ** (prec + 24)) or rad <= 1 / (fmpq(2) ** (2 * prec)):
            return b
    return enclose(x, prec)


def arf_fmpq(x: arb) -> fmpq:
    """The exact rational value of an exactly representable Arb number (a midpoint or radius):
    read with ``man_exp``, so no rounding at any working precision.

    >>> arf_fmpq(arb("0.375"))
    3/8
    """
    man, exp = x.man_exp()
    man, exp = int(man), int(exp)
    return fmpq(man * 2**exp) if exp >= 0 else fmpq(man, 2 ** (-exp))


def ball_ends(q: arb) -> tuple[fmpq, fmpq]:
    """Exact rational ends ``[mid − rad, mid + rad]`` of a finite Arb ball (exact reads).

    >>> ball_ends(arb(3))
    (3, 3)
    >>> lo, hi = ball_ends(arb(1, 0.5))   # Arb rounds a radius up
    >>> lo <= fmpq(1, 2) and hi >= fmpq(3, 2)
    True
    """
    mid, rad = arf_fmpq(q.mid()), arf_fmpq(q.rad())
    return mid - rad, mid + rad


def nearest_int(x: fmpq) -> int:
    """The integer nearest ``x`` (halves round up).

    >>> nearest_int(fmpq(5, 2)), nearest_int(fmpq(-7, 3))
    (3, -2)
    """
    return int((x + fmpq(1, 2)).floor())


def certified_ceil(q: arb):
    """``⌈q⌉`` when the ball ``q`` certainly holds no integer (decided on its exact ends), else
    ``None``. Reads only exact quantities of ``q``, so it does not depend on the precision in
    force when it is called (a ``q.lower()`` outside the block that made ``q`` is rounded to 53
    bits: the bug of issue 9).

    >>> certified_ceil(arb(1, 0.5)) is None, certified_ceil(arb("2.5", 0.25))
    (True, 3)
    """
    if not q.is_finite():
        return None
    lo, hi = ball_ends(q)
    f = lo.floor()
    if lo > f and hi < f + 1:
        return int(f) + 1
    return None


def certified_ceiling(ball_at, tie_check, *, min_tie: int = 1, start_bits: int = 64, max_bits: int = 1 << 16):
    """``⌈x⌉`` of a real ``x`` given as Arb balls at rising precision, with an exact tie test.

    ``ball_at(prec)`` returns a ball of ``x`` made inside ``ctx.workprec(prec)`` (it is read here
    only exactly). The precision doubles from ``start_bits`` until the ball holds no integer
    (:func:`certified_ceil`); when the ball is narrower than 1/2 but still holds the integer ``j``
    (``j ≥ min_tie``), ``tie_check(j)`` may decide exactly that ``x = j`` (``True``; ``False`` or
    ``None``: not decided), once per ``j``.

    Returns
    -------
    tuple or None
        ``(ceiling, how, prec)`` with ``how`` ``"arb"`` or ``"exact_tie"``; ``None`` when nothing
        decided it within ``max_bits``.

    Examples
    --------
    >>> from flint import ctx
    >>> def ball_at(prec):
    ...     with ctx.workprec(prec):
    ...         return arb.pi() / arb(3).sqrt()
    >>> certified_ceiling(ball_at, lambda j: None)
    (2, 'arb', 64)
    >>> certified_ceiling(lambda prec: arb(3), lambda j: j == 3)
    (3, 'exact_tie', 64)
    """
    prec, tried = start_bits, set()
    while prec <= max_bits:
        q = ball_at(prec)
        m = certified_ceil(q)
        if m is not None:
            return m, "arb", prec
        if q.is_finite():
            lo, hi = ball_ends(q)
            if hi - lo < fmpq(1, 2):
                j = nearest_int((lo + hi) / 2)
                if j >= min_tie and j not in tried:
                    tried.add(j)
                    if tie_check(j) is True:
                        return j, "exact_tie", prec
        prec *= 2
    return None


def arb_mid_float(x: arb) -> float:
    """``float(arb_to_mpf(x))`` at mpmath's default precision (53 bits), bit for bit, without
    mpmath: the midpoint rounded to 53 significant bits (to nearest, ties to even), then to a float
    (``±inf`` beyond the range, gradual underflow below), as mpmath's ``to_float`` does.

    >>> arb_mid_float(arb("0.5")), arb_mid_float(arb(1) / 3) == 1 / 3, arb_mid_float(arb(0))
    (0.5, True, 0.0)
    """
    from .literals import _round_nearest_even

    man, exp = x.mid().man_exp()
    man, exp = int(man), int(exp)
    if man == 0:
        return 0.0
    m, e = _round_nearest_even(abs(man), exp, 53)
    try:
        f = math.ldexp(m, e)
    except OverflowError:
        f = math.inf
    return -f if man < 0 else f


def arb_to_mpf(x: arb) -> mpmath.mpf:
    """The midpoint of ``x`` as an mpmath number, exactly (call inside an ``mpmath.workdps`` block
    wide enough for the result).

    >>> arb_to_mpf(arb("0.5"))
    mpf('0.5')
    """
    man, exp = x.mid().man_exp()
    return mpmath.mpf((int(man), int(exp)))
