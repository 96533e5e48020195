"""Verification of an outcome before a law returns it (exact, or certified by an Arb ball).

A law that labels an outcome *exact* or *certified* checks it here first; a failed check raises
:class:`~impactsym.errors.VerificationError` (a bug: the CLI exits with status 1) and the outcome
is never returned. The checks are those of ``CONVENTIONS.md``:

* ``H_i v⁺ ≥ 0`` on every closed contact the law closes (exactly; or: the ball of ``H_i v⁺`` is
  not certainly negative);
* the kinetic energy the law prescribes: ``v⁺ᵀMv⁺ = e · vᵀMv`` (exactly; or: the ball of the
  difference contains 0);
* the momentum balance ``M(v⁺ − v) = Hᵀp`` with ``p ≥ 0`` where the law requires it.

Exact checks run in python-flint ``fmpq`` for rational data, and with certified signs
(:func:`impactsym.arithmetic.certified_sign`) for algebraic data; no SymPy ``simplify``.

Examples
--------
>>> import sympy as sp
>>> M, H, v = sp.eye(2), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, -2])
>>> verify_exact("demo", M, H, v, sp.Matrix([1, 2]), sp.Matrix([6, 4]))
>>> verify_exact("demo", M, H, v, sp.Matrix([1, 0]), None)
Traceback (most recent call last):
...
impactsym.errors.VerificationError: demo: verification of the outcome failed: H_2 v+ = -1 < 0 on a closed contact (a bug in impactsym; the outcome was not returned)
"""

from __future__ import annotations

from flint import arb, ctx, fmpq

from .arithmetic import RationalField, enclose, enclose_narrow, in_row_space, sign_surd, to_fmpq
from .errors import VerificationError

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from .arithmetic import LazyModule, sympy_instance
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["verify_exact", "verify_balls", "enclose"]


def _is_rational(x) -> bool:
    return isinstance(x, (fmpq, int)) or bool(getattr(sp.sympify(x), "is_Rational", False))  # sp: first use


_q = to_fmpq


def _entries(A):
    """Rows of a matrix-like (SymPy, fmpq_mat, nested lists) as a list of lists."""
    if hasattr(A, "nrows"):
        return [[A[i, j] for j in range(A.ncols())] for i in range(A.nrows())]
    if sympy_instance(A, "MatrixBase"):
        return [[A[i, j] for j in range(A.cols)] for i in range(A.rows)]
    return [list(r) for r in A]


def _vector(v):
    if hasattr(v, "nrows"):
        return [v[i, 0] for i in range(v.nrows())]
    if sympy_instance(v, "MatrixBase"):
        return list(v)
    return list(v)


def verify_exact(law: str, M, H, v, vplus, p, *, closed=None, energy_ratio=1, impulse_nonnegative=True,
                 energy_at_most=None) -> None:
    """Check an exact outcome exactly; raise :class:`~impactsym.errors.VerificationError` if any
    condition fails.

    Parameters
    ----------
    law : str
        The law's name, for the message.
    M, H, v : the exact data (SymPy matrices, fmpq_mat, or nested lists of exact numbers)
    vplus : the exact post-impact velocity
    p : the exact impulse (``M(v⁺ − v) = Hᵀp``), or ``None`` to require only that
        ``M(v⁺ − v)`` lies in the row space of ``Hᵀ`` (no sign check then)
    closed : iterable of int, optional
        The contacts the law closes (default: every row of ``H``).
    energy_ratio : exact number or None
        ``T⁺ = energy_ratio · T⁻``; ``None`` skips the energy check.
    energy_at_most : exact number or None
        ``T⁺ ≤ energy_at_most · T⁻`` (dissipative laws).
    impulse_nonnegative : bool
        Require ``p ≥ 0``.

    Examples
    --------
    >>> import sympy as sp
    >>> verify_exact("demo", sp.eye(1), sp.Matrix([[1]]), sp.Matrix([-1]), sp.Matrix([1]), sp.Matrix([2]))
    >>> verify_exact("demo", sp.eye(1), sp.Matrix([[1]]), sp.Matrix([-1]), sp.Matrix([2]), sp.Matrix([3]))
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: demo: verification of the outcome failed: kinetic energy: v+^T M v+ = 4, expected 1 * v^T M v = 1 (a bug in impactsym; the outcome was not returned)
    """
    Mr, Hr = _entries(M), _entries(H)
    vr, vp = _vector(v), _vector(vplus)
    pr = _vector(p) if p is not None else None
    every = [x for row in Mr + Hr for x in row] + vr + vp + (pr or []) + ([energy_ratio] if energy_ratio is not None else [])
    if not all(_is_rational(x) for x in every):
        _verify_algebraic(law, Mr, Hr, vr, vp, pr, closed, energy_ratio, impulse_nonnegative, energy_at_most)
        return
    conv, sign, show = _q, (lambda x: (x > 0) - (x < 0)), str
    Mr = [[conv(x) for x in row] for row in Mr]
    Hr = [[conv(x) for x in row] for row in Hr]
    vr, vp = [conv(x) for x in vr], [conv(x) for x in vp]
    zero = fmpq(0)
    n, k = len(vr), len(Hr)
    closed = range(k) if closed is None else closed

    def dot(a, b):
        return sum((x * y for x, y in zip(a, b) if x != 0 and y != 0), zero)

    for i in closed:
        w = dot(Hr[i], vp)
        if sign(w) < 0:
            raise VerificationError(law, f"H_{i + 1} v+ = {show(w)} < 0 on a closed contact")
    if energy_ratio is not None:
        e = conv(energy_ratio)
        Tp = dot(vp, [dot(row, vp) for row in Mr])
        Tm = dot(vr, [dot(row, vr) for row in Mr])
        if sign(Tp - e * Tm) != 0:
            raise VerificationError(law, f"kinetic energy: v+^T M v+ = {show(Tp)}, expected {show(e)} * v^T M v = {show(Tm)}")
    if energy_at_most is not None:
        e = conv(energy_at_most)
        Tp = dot(vp, [dot(row, vp) for row in Mr])
        Tm = dot(vr, [dot(row, vr) for row in Mr])
        if sign(Tp - e * Tm) > 0:
            raise VerificationError(law, f"kinetic energy: v+^T M v+ = {show(Tp)} > {show(e)} * v^T M v = {show(Tm)}")
    jump = [dot(row, [a - b for a, b in zip(vp, vr)]) for row in Mr]
    if pr is not None:
        pr = [conv(x) for x in pr]
        for j in range(n):
            r = jump[j] - sum((Hr[i][j] * pr[i] for i in range(k) if Hr[i][j] != 0), zero)
            if sign(r) != 0:
                raise VerificationError(law, f"momentum: (M(v+ - v) - H^T p)_{j + 1} = {show(r)} != 0")
        if impulse_nonnegative:
            for i in closed:
                if sign(pr[i]) < 0:
                    raise VerificationError(law, f"impulse p_{i + 1} = {show(pr[i])} < 0")
    else:
        _in_row_space(law, Hr, jump)


#: working precision (bits) of the equality checks of algebraic outcomes
ALGEBRAIC_CHECK_BITS = 512


def _verify_algebraic(law, Mr, Hr, vr, vp, pr, closed, energy_ratio, impulse_nonnegative, energy_at_most=None):
    """Algebraic (or transcendental) data: every condition on Arb balls at
    :data:`ALGEBRAIC_CHECK_BITS` bits (signs: not certainly negative; equalities: the difference
    contains 0). An exact zero test of a grazing contact or of an equality (``simplify``,
    minimal polynomials) costs seconds and may not decide at all; a wrong outcome misses these
    conditions by far more than 2^-512."""
    if pr is None:
        raise VerificationError(law, "an algebraic outcome must come with its impulse to be verified")
    prec = ALGEBRAIC_CHECK_BITS
    with ctx.workprec(prec):
        # (balls no wider than enclose's evalf balls, read only by the checks below)
        vel = [enclose_narrow(x, prec) for x in vp]
        imp = [enclose_narrow(x, prec) for x in pr]
    verify_balls(law, Mr, Hr, vr, vel, imp, prec, closed=closed, energy_ratio=energy_ratio,
                 impulse_nonnegative=impulse_nonnegative, energy_at_most=energy_at_most)


def _in_row_space(law, Hr, jump):
    """``jump`` (= M(v⁺ − v)) is a combination of the rows of H (exact ranks, python-flint)."""
    if not in_row_space(Hr, jump, RationalField):
        raise VerificationError(law, "momentum: M(v+ - v) is not in the row space of H^T")


def verify_balls(law: str, M, H, v, vel_balls, p_balls, prec: int, *, closed=None, energy_ratio=1,
                 impulse_nonnegative=True, check_signs=True, energy_at_most=None) -> None:
    """Check a certified outcome given as Arb balls against the exact data, at ``prec`` bits.

    A condition fails when the balls *certainly* violate it: ``H_i v⁺`` certainly negative, the
    energy difference or a momentum residual certainly non-zero, ``p_i`` certainly negative. Every
    ball is read inside the one ``ctx.workprec(prec)`` block.

    Examples
    --------
    >>> from flint import arb
    >>> import sympy as sp
    >>> verify_balls("demo", sp.eye(1), sp.Matrix([[1]]), sp.Matrix([-1]), [arb(1)], [arb(2)], 64)
    >>> verify_balls("demo", sp.eye(1), sp.Matrix([[1]]), sp.Matrix([-1]), [arb(-1)], [arb(0)], 64)
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: demo: verification of the outcome failed: H_1 v+ = -1.000000000 is certainly negative on a closed contact (a bug in impactsym; the outcome was not returned)
    """
    with ctx.workprec(prec):
        # (the data's balls no wider than enclose's evalf balls, read only by the checks below)
        Mr = [[enclose_narrow(x, prec) for x in row] for row in _entries(M)]
        Hr = [[enclose_narrow(x, prec) for x in row] for row in _entries(H)]
        vr = [enclose_narrow(x, prec) for x in _vector(v)]
        vp = list(vel_balls)
        pr = list(p_balls) if p_balls is not None else None
        k, n = len(Hr), len(vr)
        closed = range(k) if closed is None else closed

        def dot(a, b):
            acc = arb(0)
            for x, y in zip(a, b):
                acc += x * y
            return acc

        failure = None
        for i in (closed if check_signs else ()):
            w = dot(Hr[i], vp)
            if w < 0:
                failure = f"H_{i + 1} v+ = {w.str(10, radius=True)} is certainly negative on a closed contact"
                break
        if failure is None and energy_ratio is not None:
            e = enclose_narrow(energy_ratio, prec)
            diff = dot(vp, [dot(row, vp) for row in Mr]) - e * dot(vr, [dot(row, vr) for row in Mr])
            if not diff.is_finite() or not diff.contains(0):
                failure = f"kinetic energy: v+^T M v+ - e v^T M v = {diff.str(10, radius=True)} excludes 0"
        if failure is None and energy_at_most is not None:
            e = enclose_narrow(energy_at_most, prec)
            diff = dot(vp, [dot(row, vp) for row in Mr]) - e * dot(vr, [dot(row, vr) for row in Mr])
            if not diff.is_finite() or diff > 0:
                failure = f"kinetic energy: v+^T M v+ - e v^T M v = {diff.str(10, radius=True)} is certainly positive"
        if failure is None and pr is not None:
            for j in range(n):
                r = dot(Mr[j], [a - b for a, b in zip(vp, vr)]) - dot([Hr[i][j] for i in range(k)], pr)
                if not r.is_finite() or not r.contains(0):
                    failure = f"momentum: (M(v+ - v) - H^T p)_{j + 1} = {r.str(10, radius=True)} excludes 0"
                    break
            if failure is None and impulse_nonnegative:
                for i in closed:
                    if pr[i] < 0:
                        failure = f"impulse p_{i + 1} = {pr[i].str(10, radius=True)} is certainly negative"
                        break
    if failure is not None:
        raise VerificationError(law, failure)


_surd_sign = sign_surd


def verify_surd(law: str, M, H, v, alpha, beta, p_alpha, p_beta, d, *, energy_ratio=1, closed=None,
                check_signs=True) -> None:
    """Check exactly an outcome in ``Q(√d)`` over rational data: ``v⁺ = α + β√d``,
    ``p = p_α + p_β√d`` (fmpq entries, ``d ≥ 0`` rational), with the conditions of
    :func:`verify_exact` (``check_signs=False`` skips ``H v⁺ ≥ 0`` and ``p ≥ 0``, for an outcome
    the law itself labels invalid). Equalities are split into their rational and ``√d`` parts
    (when ``√d`` is irrational), signs are decided by comparing squares.

    >>> from flint import fmpq
    >>> one, zero = fmpq(1), fmpq(0)
    >>> verify_surd("demo", [[one]], [[one]], [-one], [zero], [one], [one], [one], fmpq(1))
    >>> verify_surd("demo", [[one]], [[one]], [-one], [zero], [one], [one], [one], fmpq(2))
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: demo: verification of the outcome failed: kinetic energy: v+^T M v+ - e v^T M v = 1 + 0 sqrt(2) != 0 (a bug in impactsym; the outcome was not returned)
    """
    Mr = [[_q(x) for x in row] for row in _entries(M)]
    Hr = [[_q(x) for x in row] for row in _entries(H)]
    vr, al, be = [_q(x) for x in _vector(v)], [_q(x) for x in _vector(alpha)], [_q(x) for x in _vector(beta)]
    pa, pb = [_q(x) for x in _vector(p_alpha)], [_q(x) for x in _vector(p_beta)]
    d = _q(d)
    zero = fmpq(0)
    n, k = len(vr), len(Hr)
    closed = range(k) if closed is None else closed
    num, den = int(d.p), int(d.q)
    import math

    if math.isqrt(num) ** 2 == num and math.isqrt(den) ** 2 == den:  # √d rational: fold it in
        root = fmpq(math.isqrt(num), math.isqrt(den))
        al = [a + b * root for a, b in zip(al, be)]
        pa = [a + b * root for a, b in zip(pa, pb)]
        be, pb, d = [zero] * n, [zero] * k, zero

    def dot(a, b):
        return sum((x * y for x, y in zip(a, b) if x != 0 and y != 0), zero)

    if check_signs:
        for i in closed:
            x, y = dot(Hr[i], al), dot(Hr[i], be)
            if _surd_sign(x, y, d) < 0:
                raise VerificationError(law, f"H_{i + 1} v+ = {x} + {y} sqrt({d}) < 0 on a closed contact")
            if _surd_sign(pa[i], pb[i], d) < 0:
                raise VerificationError(law, f"impulse p_{i + 1} = {pa[i]} + {pb[i]} sqrt({d}) < 0")
    if energy_ratio is not None:
        e = _q(energy_ratio)
        Mal, Mbe = [dot(row, al) for row in Mr], [dot(row, be) for row in Mr]
        rat = dot(al, Mal) + d * dot(be, Mbe) - e * dot(vr, [dot(row, vr) for row in Mr])
        irr = 2 * dot(al, Mbe)
        if rat != 0 or (d != 0 and irr != 0):
            raise VerificationError(law, f"kinetic energy: v+^T M v+ - e v^T M v = {rat} + {irr} sqrt({d}) != 0")
    for j in range(n):
        ra = dot(Mr[j], [a - b for a, b in zip(al, vr)]) - sum((Hr[i][j] * pa[i] for i in range(k)), zero)
        rb = dot(Mr[j], be) - sum((Hr[i][j] * pb[i] for i in range(k)), zero)
        if ra != 0 or (d != 0 and rb != 0):
            raise VerificationError(law, f"momentum: (M(v+ - v) - H^T p)_{j + 1} = {ra} + {rb} sqrt({d}) != 0")
