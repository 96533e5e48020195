"""Two-surface impacts resolved in O(1): every first-surface choice, its exact reflection count and
its exit velocity, whatever the count (Seghete & Murphey, sec. III-B and III-C).

The sequential resolution of an impact against two surfaces (gradient rows ``H_A``, ``H_B``) is a
sequence of single impacts ``G_A``, ``G_B`` that is forced to alternate once the first surface is
chosen. :mod:`derivations.two_surface` reduces it, in any dimension, to reflections in a planar
wedge of opening ``β = π − φ`` (``φ`` the kinetic angle) and derives

* the count of the branch that starts with surface ``i`` (possible only if ``H_i v < 0``):
  ``m_i = ⌈ψ_i/β⌉``, ``ψ_A = atan2(−c_A√Δ, s_A c_B − g c_A)``, ``β = atan2(√Δ, −g)``, with
  ``s_i = H_i M⁻¹H_iᵀ``, ``g = H_A M⁻¹H_Bᵀ``, ``Δ = s_A s_B − g²``, ``c_i = H_i v`` (B: swap A and B);
* the exit: ``α_f = α ρ^k`` (``m = 2k``) or ``conj(α ρ^k)`` (``m = 2k + 1``) in ``Q(√−Δ)``, with
  ``α = (s_A c_B − g c_A) + c_A√−Δ``, ``ρ = (−g + √−Δ)²/(s_A s_B)``; then
  ``H v⁺ = (Im α_f/√Δ, (Re α_f + g Im α_f/√Δ)/s_A)`` and ``v⁺ = v + M⁻¹Hᵀ Γ⁻¹ (H v⁺ − H v)``;
* the paper's bound ``N = ⌈π/β⌉`` (the maximum count over all velocities).

How each answer is obtained
---------------------------
* **Count** (always certain): ``ψ/β`` is enclosed in an Arb ball (python-flint) at rising precision
  until the ball holds no integer; an integer inside the ball (an iterate possibly exactly on an
  edge, i.e. grazing) is decided exactly from the exact iterate. Float inputs are decided from
  their exact binary values. If neither settles it, :class:`~impactsym.errors.UndecidableSign` is
  raised (never a guess).
* **Exit velocity**: exact (SymPy ``Rational``) for rational input when its numbers have at most
  about ``max_exact_digits`` digits (they grow linearly with the count; the closed form above is
  evaluated in exact integer arithmetic with O(log m) multiplications); otherwise an
  ``mpmath.matrix`` plus floats, each component certified to ``digits`` significant digits
  (a component smaller than ``10^-digits`` times the largest: to ``10^-2digits`` times the
  largest, absolutely). Float input gives a float answer (rounded from a certified enclosure).

References
----------
Seghete & Murphey, sec. II-A (``G_u``), sec. III-B (branching over orderings; the claim of at most
two solutions for two surfaces), sec. III-C (termination, ``N = ⌈S_total/(2S₀)⌉``).

Examples
--------
>>> r = resolve_two_surfaces("11/10,0;0,1", "1,0;-1,1", "-1,-2")
>>> [(list(o.order), o.reflections) for o in r.outcomes]
[([0, 1, 0, 1], 4), ([1, 0, 1, 0], 4)]
>>> r.outcomes[0].velocity.T
Matrix([[173/147, 278/147]])
>>> r.bound
4
>>> big = resolve_two_surfaces("1,0;0,1", "1,0;-1000000,1", "-1,0")   # wedge of about 1e-6 rad
>>> big.outcomes[0].reflections, big.outcomes[0].exact, big.bound
(1570797, False, 3141593)
>>> big.outcomes[0].order
AlternatingOrder(first=0, length=1570797)
>>> mpmath.nstr(big.outcomes[0].velocity[1], 30), big.outcomes[0].digits
('0.999999999999946602376662304211', 30)
>>> resolve_two_surfaces("1,0;0,1", "1,0;2,0", "-1,0")
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: gradients: the two rows are parallel (Δ = s_1 s_2 − g² = 0): the wedge is degenerate (opening 0 or π)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq, fmpq_mat, fmpz

from ..arithmetic import (all_rational, arb_mid_float, arb_to_mpf, bits, certified_ceiling, certified_sign, enclose, float_vector,
                          rational_matrix, sign_of, to_fmpq, to_sympy_rational)
from ..errors import ImpactInputError, UndecidableSign, VerificationError
from ..mechanics import check_gradients, check_mass_matrix, check_velocity
from ..numbers import is_exact
from ..verify import verify_balls, verify_exact
from . import _reflection as _r

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ..arithmetic import LazyModule
mpmath = LazyModule("mpmath", globals(), "mpmath")
sp = LazyModule("sympy", globals(), "sp")

__all__ = [
    "resolve_two_surfaces",
    "branch_counts",
    "bound_at_most",
    "TwoSurfaceResolution",
    "TwoSurfaceOutcome",
    "AlternatingOrder",
    "DEFAULT_DIGITS",
    "DEFAULT_MAX_EXACT_DIGITS",
]

#: significant digits of a certified (non-exact) exit velocity, unless ``digits`` is given
DEFAULT_DIGITS = 30
#: a rational input gets an exact exit velocity when its numbers have at most about this many
#: digits (the size grows linearly with the count: about m · log10(s_A s_B) digits)
DEFAULT_MAX_EXACT_DIGITS = 2000
#: largest Arb precision (bits) tried before an undecided comparison raises
MAX_PRECISION_BITS = 1 << 16
#: largest bit size of an exact iterate computed to settle a possible tie (grazing) exactly
TIE_CHECK_BITS = 1 << 22
#: largest count for which an irrational (algebraic) input is iterated exactly
MAX_EXACT_ALGEBRAIC_REFLECTIONS = 24


class AlternatingOrder(Sequence):
    """The ordering of a branch: ``first, 1 − first, first, ...`` (``length`` surface indices).

    A list-like view that is never materialized (a branch may have 10⁹ reflections).

    >>> o = AlternatingOrder(1, 5)
    >>> list(o), o[-1], len(o), o == [1, 0, 1, 0, 1]
    ([1, 0, 1, 0, 1], 1, 5, True)
    """

    __slots__ = ("first", "length")

    def __init__(self, first: int, length: int):
        self.first, self.length = int(first), int(length)

    def __len__(self) -> int:
        return self.length

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(self.length))]
        if i < 0:
            i += self.length
        if not 0 <= i < self.length:
            raise IndexError("AlternatingOrder index out of range")
        return self.first if i % 2 == 0 else 1 - self.first

    def __eq__(self, other) -> bool:
        if isinstance(other, AlternatingOrder):
            return (self.length, self.first if self.length else 0) == (other.length, other.first if other.length else 0)
        if isinstance(other, (list, tuple)):
            return len(other) == self.length and all(a == b for a, b in zip(self, other))
        return NotImplemented

    def __hash__(self):
        return hash((self.first if self.length else 0, self.length))

    def __repr__(self) -> str:
        return f"AlternatingOrder(first={self.first}, length={self.length})"

    def to_json(self, limit: int = 10000):
        """The list of indices when ``length <= limit``, else ``{"first", "length", "alternating"}``."""
        if self.length <= limit:
            return list(self)
        return {"first": self.first, "length": self.length, "alternating": True}


@dataclass
class TwoSurfaceOutcome:
    """One branch: the ordering (surface indices, alternating), the count and the exit velocity.

    ``first`` is the index of the first surface, or ``None`` for the single outcome of a velocity
    that approaches neither surface (no impact: no reflection, ``v⁺ = v``, ``no_impact`` in JSON).
    ``velocity`` is a SymPy column (``exact``), a float64 array (float input), or an
    ``mpmath.matrix`` certified to ``digits`` significant digits per component, with ``error_bound``
    an upper bound of every component's error. ``impulse`` is ``p`` in ``M(v⁺ − v) = Hᵀp``, in the
    same form.
    """

    first: int | None
    order: AlternatingOrder
    reflections: int
    velocity: Any
    velocity_float: np.ndarray
    impulse: Any
    exact: bool
    digits: int | None = None
    error_bound: Any = None
    #: the certified Arb balls of ``velocity`` and their working precision (certified outcomes)
    _balls: Any = field(default=None, repr=False, compare=False)
    _prec: int | None = field(default=None, repr=False, compare=False)

    def as_dict(self) -> dict:
        """JSON-ready form (exact numbers as SymPy strings, mpmath values as strings)."""
        def text(v):
            if isinstance(v, sp.MatrixBase):
                return [str(x) for x in v]
            if isinstance(v, mpmath.matrix):
                return [mpmath.nstr(v[i], self.digits or 17) for i in range(v.rows)]
            return [float(x) for x in v]
        return {"order": self.order.to_json(), "first": self.first, "reflections": self.reflections,
                "velocity": text(self.velocity), "velocity_float": [float(x) for x in self.velocity_float],
                "exact": self.exact, "digits": self.digits, "no_impact": self.first is None}


@dataclass
class TwoSurfaceResolution:
    """Every branch of a two-surface impact and the quantities that govern it.

    Attributes
    ----------
    outcomes : list of TwoSurfaceOutcome
        One per surface that the velocity approaches, by first surface; a single outcome with no
        reflection when the velocity is already valid.
    by_first : dict
        ``{0: outcome or None, 1: outcome or None}`` (``None``: that surface is not approached, so
        no branch starts with it).
    bound : int
        The paper's ``N = ⌈S_total/(2S₀)⌉ = ⌈π/β⌉`` (certified), the maximum count over all velocities.
    kinetic_angle_cos : exact number or float
        ``cos φ = H_1M⁻¹H_2ᵀ/√(s_1 s_2)`` (computed on first access); the wedge opening is
        ``β = π − φ``.
    wedge_angle : mpmath.mpf
        ``β`` to ``digits`` digits (for float input made on first access: the float path of
        the sequential law reads only the outcomes and the bound, without mpmath).
    exact : bool
        Whether the input was exact.
    decisions : dict
        How the counts were certified: ``arb`` (an Arb ball excluded every integer),
        ``exact_tie`` (an integer was confirmed exactly: an iterate on an edge), ``max_bits``.
    """

    outcomes: list
    by_first: dict
    bound: int
    _wedge: Any = field(repr=False)  # the mpf β, or a function that makes it on first access
    exact: bool
    decisions: dict = field(default_factory=dict)
    _data: Any = field(default=None, repr=False)

    @property
    def wedge_angle(self):
        if callable(self._wedge):
            self._wedge = self._wedge()
        return self._wedge

    @property
    def kinetic_angle_cos(self):
        return _kinetic_cos(self._data, self.exact)

    def as_dict(self) -> dict:
        """JSON-ready form: ``outcomes`` (see :meth:`TwoSurfaceOutcome.as_dict`), ``bound``,
        ``wedge_angle`` and ``kinetic_angle_cos`` (exact string and float), ``decisions``.

        >>> d = resolve_two_surfaces("1,0;0,1", "1,0;-1,1", "-1,-2").as_dict()
        >>> d["bound"], d["outcomes"][0]["order"], d["outcomes"][0]["velocity"], d["kinetic_angle_cos"]
        (4, [0, 1, 0, 1], ['1', '2'], '-sqrt(2)/2')
        """
        c = self.kinetic_angle_cos
        return {"outcomes": [o.as_dict() for o in self.outcomes], "bound": self.bound,
                "wedge_angle": mpmath.nstr(self.wedge_angle, 17), "wedge_angle_float": float(self.wedge_angle),
                "kinetic_angle_cos": str(c), "kinetic_angle_cos_float": float(c),
                "exact": self.exact, "decisions": dict(self.decisions)}


# --------------------------------------------------------------------------- exact scalars
# (the arithmetic is impactsym.arithmetic's; ``_fmpq`` is the name the tests use)
_fmpq = to_fmpq
_floats = float_vector


#: expression -> its radsimp (the irrational path's exact forms: the sequential law's two-surface
#: selection resolves the same data again, and each branch iterates from the same v)
_RADSIMP: dict = {}


def _radsimp(x):
    """``sp.radsimp(x)``, remembered by the expression: radsimp is a function of the expression
    (its ``nsimplify`` of a numeric denominator sets its own precision), and its ``nsimplify``
    step costs a PSLQ search per numeric denominator (``pi, E`` masses: most of the path)."""
    from sympy.core.parameters import global_parameters as gp

    key = (x, gp.evaluate, gp.distribute)  # (SymPy's evaluation switches: radsimp builds under them)
    hit = _RADSIMP.get(key)
    if hit is None:
        hit = sp.radsimp(x)
        if len(_RADSIMP) >= 4096:
            _RADSIMP.pop(next(iter(_RADSIMP)))
        _RADSIMP[key] = hit
    return hit


class _Data:
    """``s_A, s_B, g, c_A, c_B, Δ`` of one ordering of the two rows (exact), and ``W``, ``Γ``."""

    def __init__(self, sa, sb, g, ca, cb):
        self.sa, self.sb, self.g, self.ca, self.cb = sa, sb, g, ca, cb
        self.D = sa * sb - g * g
        if not isinstance(self.D, fmpq):
            self.D = _radsimp(sp.expand(self.D))

    def swapped(self) -> "_Data":
        return _Data(self.sb, self.sa, self.g, self.cb, self.ca)

    def balls(self, prec: int):
        """The Arb balls at ``prec`` bits, made once per precision (the bound, the A-first count
        and the exit each ask for them; the same enclosures of the same exact data)."""
        memo = self.__dict__.setdefault("_balls", {})
        hit = memo.get(prec)
        if hit is None:
            hit = memo[prec] = self._balls_at(prec)
        return hit

    def _balls_at(self, prec: int):
        with ctx.workprec(prec):
            sa, sb, g, ca, cb, D = (enclose(x, prec) for x in (self.sa, self.sb, self.g, self.ca, self.cb, self.D))
            rD = D.sqrt()
            psi = arb.atan2(-ca * rD, sa * cb - g * ca)
            beta = arb.atan2(rD, -g)
        return sa, sb, g, ca, cb, D, rD, psi, beta

    def rational(self) -> bool:
        return isinstance(self.D, fmpq)


def _field_power_exit(d: _Data, m: int):
    """Exact ``(c_A', c_B')`` after ``m`` reflections starting with A, for rational data.

    The closed form ``α_f = α ρ^k`` (or its conjugate) of :mod:`derivations.two_surface`, in
    integer arithmetic: with ``Δ = P/Q`` and ``r = √(−PQ)`` (so ``√−Δ = r/Q``), elements of
    ``Q(√−Δ)`` are ``(X + Y r)/den`` with integers ``X, Y``; the power ``(a + b r)^k`` is taken by
    squaring on integer pairs (no gcd until the end).
    """
    P, Q = fmpz(d.D.p), fmpz(d.D.q)
    Dint = P * Q

    def mul(u, v):
        return (u[0] * v[0] - Dint * u[1] * v[1], u[0] * v[1] + u[1] * v[0])

    # rho = ((g^2 - Δ) + (-2g/Q) r) / (s_A s_B): integer numerators over a common denominator
    re, im = (d.g * d.g - d.D) / (d.sa * d.sb), (-2 * d.g / Q) / (d.sa * d.sb)
    den_rho = re.q.lcm(im.q)
    a, b = re.p * (den_rho // re.q), im.p * (den_rho // im.q)
    # alpha = (s_A c_B - g c_A) + (c_A/Q) r
    are, aim = d.sa * d.cb - d.g * d.ca, d.ca / Q
    den_alpha = are.q.lcm(aim.q)
    alpha = (are.p * (den_alpha // are.q), aim.p * (den_alpha // aim.q))
    k, acc, base = m // 2, (fmpz(1), fmpz(0)), (a, b)
    while k:
        if k & 1:
            acc = mul(acc, base)
        k >>= 1
        if k:
            base = mul(base, base)
    X, Y = mul(alpha, acc)
    if m % 2:
        Y = -Y
    den = den_alpha * den_rho ** (m // 2)
    ca = fmpq(Y * Q, den)  # the coefficient of √−Δ = r/Q
    x = fmpq(X, den)
    return ca, (x + d.g * ca) / d.sa


def _exact_feasible(d: _Data, m: int, budget: int) -> bool:
    size = max(bits(d.sa * d.sb), bits(d.g * d.g), bits(d.D)) + 2
    return m * size <= budget


# --------------------------------------------------------------------------- the law
def _checked(mass_matrix, gradients, velocity):
    exact = is_exact(mass_matrix, gradients, velocity)
    M = check_mass_matrix(mass_matrix, exact=exact)
    n = M.shape[0]
    H = check_gradients(gradients, n, exact=exact)
    rows = H.rows if exact else H.shape[0]
    if rows != 2:
        raise ImpactInputError("gradients", f"must have exactly 2 rows (two closed contacts), got {rows}")
    v = check_velocity(velocity, n, exact=exact)
    return exact, M, H, v, n


def _invariants(exact, M, H, v, n):
    """``W = M⁻¹Hᵀ``, ``Γ``, ``c`` exactly; rational data as fmpq, irrational as SymPy."""
    if exact and not (all_rational(M) and all_rational(H) and all_rational(v)):
        W = M.LUsolve(H.T).applyfunc(_radsimp)
        gram = (H * W).applyfunc(_radsimp)
        c = (H * v).applyfunc(_radsimp)
        return W, gram, c, False
    # exact rational, or float at its binary value
    Mq, Hq, vq = rational_matrix(M), rational_matrix(H), rational_matrix(v)
    W = Mq.solve(Hq.transpose())
    gram = Hq * W
    c = Hq * vq
    return (W, gram, c, True), vq, (Mq, Hq)


def _certified_ceil_ratio(d: _Data, tie_check, decisions: dict) -> int:
    """``⌈ψ/β⌉`` of the A-first branch, certified (Arb at rising precision, exact tie test).

    The working precision starts above the bit size of ``π/β`` (the count can be as large as
    that) and doubles until the ball of ``ψ/β`` excludes every integer; every read of the ball
    is exact (:func:`impactsym.arithmetic.certified_ceiling`)."""
    def ball_at(prec):
        *_, psi, beta = d.balls(prec)
        with ctx.workprec(prec):
            return psi / beta

    found = certified_ceiling(ball_at, lambda j: tie_check(d, j), max_bits=MAX_PRECISION_BITS)
    if found is None:
        raise UndecidableSign(
            f"the reflection count ceil(psi/beta) could not be certified: psi/beta is within 2^-{MAX_PRECISION_BITS} "
            "of an integer and an exact check of that tie (an iterate exactly on an edge) was not feasible")
    m, how, prec = found
    if how == "arb":
        decisions["arb"] = decisions.get("arb", 0) + 1
        decisions["max_bits"] = max(decisions.get("max_bits", 0), prec)
    else:
        decisions["exact_tie"] = decisions.get("exact_tie", 0) + 1
    return m


def _tie_check_rational(d: _Data, j: int):
    """Whether the j-th iterate of the A-first branch lies exactly on an edge (``ψ = jβ``)."""
    if not _exact_feasible(d, j, TIE_CHECK_BITS):
        return None
    ca, cb = _field_power_exit(d, j)
    return (cb if j % 2 else ca) == 0


def _make_tie_check_algebraic(M, HA, HB, v):
    def check(d: _Data, j: int):
        if j > MAX_EXACT_ALGEBRAIC_REFLECTIONS:
            return None
        it = _iterate_exact(M, HA, HB, v, j)
        last = it[-1]
        row = HB if j % 2 else HA
        return certified_sign(_matmul(row, last)[0, 0]) == 0
    return check


def _iterate_exact(M, HA, HB, v, m):
    """Explicit alternating SymPy iteration (irrational inputs, small counts), starting with A."""
    out, cur = [], v
    for k in range(m):
        h = HA if k % 2 == 0 else HB
        w, s = _r.sympy_parts(M, h)
        cur = _r.reflect_along(cur, w, _matmul(h, cur)[0, 0], _r.gain(s))[0].applyfunc(_expanded)
        out.append(cur)
    return out


def _expanded(x):
    """An iterate's entry with its denominator rationalized (:func:`_radsimp`), and then, when it is
    built of rationals and radicals alone (no ``π``, ``e`` or function), expanded: a sum of terms,
    ``a + b·√3`` for an entry of ``Q(√3)``. Unexpanded, each reflection nested the one before (the
    4th iterate of ``H = ((1, 0), (−√3, 1))`` was a 300-character tree ``1 + (1024·√3·(−2·√3 − 1) +
    …)/2048``, now ``1``, and the products of such trees that verify the exit took 0.3 s). An entry
    with transcendental numbers is left as radsimp gives it (expanded, its sums over a common
    denominator only grow)."""
    x = _radsimp(x)
    if x.atoms(sp.NumberSymbol, sp.Function):
        return x
    return sp.expand(x)


def _matmul(A, B) -> sp.Matrix:
    """``A * B`` of SymPy matrices of finite exact numbers, the same matrix: each entry
    ``Add(*[A[i,k]*B[k,j] ...])`` over the pairs of non-zero entries, as SymPy's product builds it
    (``Add`` of the products), without its products ``0 * B[k,j]`` (SymPy's test for an infinite
    entry, whose ``is_finite`` on a nested iterate asks the assumption system for signs by
    ``evalf``: a tenth of a second per product)."""
    rows = []
    for i in range(A.rows):
        row = []
        for j in range(B.cols):
            terms = [A[i, k] * B[k, j] for k in range(A.cols) if A[i, k] != 0 and B[k, j] != 0]
            row.append(sp.Add(*terms) if terms else sp.S.Zero)
        rows.append(row)
    return sp.Matrix(rows)


def _w_after(balls, m: int):
    """Balls of ``(H_A v_m, H_B v_m)`` after ``m ≥ 1`` reflections starting with A (the angle form
    of the closed form); call inside the ``ctx.workprec`` block that made ``balls``."""
    sa, sb, g, ca, cb, D, rD, psi, beta = balls
    sigma = 1 if m % 2 == 0 else -1
    th = sigma * (m * beta - psi) + (beta if sigma == -1 else 0)
    pn = ((sb * ca * ca - 2 * g * ca * cb + sa * cb * cb) / D).sqrt()
    return sa.sqrt() * pn * th.sin(), sb.sqrt() * pn * (beta - th).sin()


def _certified_exit(d: _Data, m: int, digits: int, W, gram, vec, swap: bool):
    """Certified ``v⁺`` (Arb): every component to ``digits`` significant digits (radius below
    ``10^-digits·|v⁺_i|``), except components below ``10^-digits·max|v⁺|``, which are certified to
    the absolute ``10^-2digits·max|v⁺|``.

    ``W`` (n×2), ``gram`` (2×2) and ``vec`` (n) hold exact numbers (fmpq or SymPy); they are
    enclosed at each working precision. Returns the velocity and impulse balls, the largest
    radius and the working precision they were made at (read them only inside a block of it)."""
    extra = max(m, 1).bit_length()
    prec = int(digits * 3.33) + extra + 64
    while prec <= MAX_PRECISION_BITS:
        balls = d.balls(prec)
        with ctx.workprec(prec):
            sa, sb, g, ca, cb = balls[:5]
            Wb = [[enclose(W[i][0], prec), enclose(W[i][1], prec)] for i in range(len(W))]
            gram_b = [[enclose(gram[i][j], prec) for j in range(2)] for i in range(2)]
            v_arb = [enclose(x, prec) for x in vec]
            ca2, cb2 = _w_after(balls, m)
            if swap:
                ca, cb, ca2, cb2 = cb, ca, cb2, ca2
            dA, dB = ca2 - ca, cb2 - cb
            (g00, g01), (g10, g11) = gram_b
            det = g00 * g11 - g01 * g10
            pA = (g11 * dA - g01 * dB) / det
            pB = (g00 * dB - g10 * dA) / det
            vel = [v_arb[i] + Wb[i][0] * pA + Wb[i][1] * pB for i in range(len(v_arb))]
            scale = max((abs(x.mid()) for x in vel), default=arb(0))
            rad = max((x.rad() for x in vel), default=arb(0))
            tol, floor = arb(10) ** (-digits), arb(10) ** (-2 * digits) * scale
            ok = all(x.is_finite() and (x.rad() <= tol * abs(x.mid()) or x.rad() <= floor) for x in vel)
        if ok:
            return vel, (pA, pB), rad, prec
        prec *= 2
    raise UndecidableSign(f"the exit velocity could not be certified to {digits} digits within {MAX_PRECISION_BITS} bits")


def _verify_count_balls(d: _Data, m: int, prec: int) -> None:
    """The count is consistent with the order: the first surface is approached, and after
    ``m − 1`` reflections the surface of the ``m``-th one is approached (not certainly leaving)."""
    if sign_of(d.ca) >= 0:
        raise VerificationError("two-surface", "the branch starts with a surface that is not approached")
    if m < 2:
        return
    balls = d.balls(prec)
    with ctx.workprec(prec):
        wa, wb = _w_after(balls, m - 1)
        nxt = wa if (m - 1) % 2 == 0 else wb
        bad = nxt >= 0 and not nxt.contains(0)
        shown = nxt.str(10, radius=True)
    if bad:
        raise VerificationError(
            "two-surface", f"count {m}: after {m - 1} reflections the next surface has H v = {shown} >= 0 "
            "(the branch would have ended earlier)")


def _verify_count_rational(d: _Data, m: int) -> None:
    """Exact form of :func:`_verify_count_balls` (rational data)."""
    if d.ca >= 0:
        raise VerificationError("two-surface", "the branch starts with a surface that is not approached")
    if m < 2:
        return
    wa, wb = _field_power_exit(d, m - 1)
    nxt = wa if (m - 1) % 2 == 0 else wb
    if nxt >= 0:
        raise VerificationError(
            "two-surface", f"count {m}: after {m - 1} reflections the next surface has H v = {nxt} >= 0 "
            "(the branch would have ended earlier)")


def _mid_scale(vel) -> mpmath.mpf:
    return max(abs(vel[i]) for i in range(vel.rows))


def _certified_outcome(first, order, m, vel_b, imp_b, rad, digits, prec) -> "TwoSurfaceOutcome":
    """An outcome certified to ``digits`` significant digits, from the Arb balls of
    :func:`_certified_exit` (made at ``prec`` bits): mpmath midpoints and an error bound covering
    the ball's radius and the rounding of the midpoints."""
    with ctx.workprec(prec), mpmath.workdps(digits + 5):
        vel = mpmath.matrix([arb_to_mpf(x) for x in vel_b])
        imp = mpmath.matrix([arb_to_mpf(x) for x in imp_b])
        err = arb_to_mpf(rad) * 2 + _mid_scale(vel) * mpmath.mpf(10) ** -(digits + 4)
    return TwoSurfaceOutcome(first, order, m, vel, _floats(vel), imp, False, digits=digits, error_bound=err,
                             _balls=tuple(vel_b), _prec=prec)


def resolve_two_surfaces(mass_matrix, gradients, velocity, *, digits: int = DEFAULT_DIGITS,
                         max_exact_digits: int = DEFAULT_MAX_EXACT_DIGITS) -> TwoSurfaceResolution:
    """Resolve an impact against exactly two surfaces, every first-surface choice, in O(1).

    Parameters
    ----------
    mass_matrix : matrix-like (n×n), symmetric positive definite
    gradients : matrix-like (2×n), the gradient rows ``H_1``, ``H_2`` of the two closed contacts,
        linearly independent
    velocity : vector-like (n,), the pre-impact velocity ``v``
    digits : int
        Significant digits of an exit velocity that is not exact (certified per component).
    max_exact_digits : int
        Rational input gets an exact exit velocity when its numbers have at most about this many
        digits (``0``: always certified digits; small counts of small data are exact by default).

    Returns
    -------
    TwoSurfaceResolution
        ``outcomes`` (one per approached surface, or one with no reflection if ``v`` is valid),
        the certified bound ``N = ⌈π/β⌉``, ``cos φ`` and ``β``.

    Raises
    ------
    ImpactInputError
        Bad shapes, NaN/inf, a mass matrix that is not SPD, zero rows, not exactly two rows, or
        parallel rows (a degenerate wedge: ``Δ = 0``).
    UndecidableSign
        A count or digit that could not be certified (never guessed).

    Examples
    --------
    >>> r = resolve_two_surfaces("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
    >>> [(list(o.order), o.reflections, list(o.velocity)) for o in r.outcomes]
    [([0, 1], 2, [0, 0, 1])]
    >>> resolve_two_surfaces([[1.1, 0.0], [0.0, 1.0]], [[1.0, 0.0], [-1.0, 1.0]], [-1.0, -2.0]).outcomes[1].velocity
    array([0.81405896, 2.09070295])
    """
    if not isinstance(digits, int) or digits < 1:
        raise ImpactInputError("digits", f"must be a positive integer, got {digits!r}")
    # exact rational input: read once into checked sparse fmpq data (the sequential law's reader,
    # the checks and messages of impactsym.mechanics); anything else, or two rows not given, is
    # read and worded by the general checks
    from .sequential.sparse import read_rational, two_surface_data

    data = read_rational(mass_matrix, gradients, velocity)
    if data is not None and data.k == 2:
        return _resolve(True, None, None, None, data.n, digits, max_exact_digits, prepared=two_surface_data(data))
    exact, M, H, v, n = _checked(mass_matrix, gradients, velocity)
    return _resolve(exact, M, H, v, n, digits, max_exact_digits)


def _resolve(exact, M, H, v, n, digits=DEFAULT_DIGITS, max_exact_digits=DEFAULT_MAX_EXACT_DIGITS, *,
             prepared=None) -> TwoSurfaceResolution:
    """:func:`resolve_two_surfaces` on checked input. ``prepared`` (exact rational data already
    checked by the caller, e.g. the sequential law, which reads its input once): the
    ``fmpq_mat`` tuple ``(W, gram, c, vq, Mq, Hq)`` with ``W = M⁻¹Hᵀ`` (n×2), ``gram = H W``,
    ``c = H v``; then ``M``, ``H``, ``v`` are not read (pass ``None``)."""
    decisions: dict = {}
    rational_path = prepared is not None or not exact or (all_rational(M) and all_rational(H) and all_rational(v))
    if prepared is not None:
        W, gram, c, vq, Mq, Hq = prepared
        v = None  # (read only where no surface is approached: v+ = v)
        d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], c[0, 0], c[1, 0])
        tie_check = _tie_check_rational
    elif rational_path:
        (W, gram, c, _), vq, (Mq, Hq) = _invariants(exact, M, H, v, n)
        d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], c[0, 0], c[1, 0])
        tie_check = _tie_check_rational
    else:
        W, gram, c, _ = _invariants(exact, M, H, v, n)
        d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], c[0], c[1])
        HA, HB = H[0, :], H[1, :]
        tie_check = None  # built per branch below
    if sign_of(d.D) == 0:
        raise ImpactInputError(
            "gradients", "the two rows are parallel (Δ = s_1 s_2 − g² = 0): the wedge is degenerate (opening 0 or π)")
    signs = (sign_of(d.ca), sign_of(d.cb))
    # bound N = ceil(pi/beta), certified; pi/beta is an integer only for beta = pi/K with
    # cos^2(pi/K) = g^2/(s_A s_B); decided exactly with SymPy for the candidate K.
    bound = _certified_bound(d, decisions)

    def wedge_angle():
        with mpmath.workdps(digits):
            *_, beta = d.balls(int(digits * 3.33) + 32)
            return arb_to_mpf(beta)

    wedge = wedge_angle() if exact else wedge_angle  # float input: made (with mpmath) on first access

    by_first: dict = {0: None, 1: None}
    outcomes = []
    if signs[0] >= 0 and signs[1] >= 0:
        if v is None:
            v = _rational_column([vq[i, 0] for i in range(n)])
        vel = _as_output(exact, v, vq if rational_path else None)
        zero = sp.zeros(2, 1) if exact else np.zeros(2)
        # no surface is approached: no impact, no first surface (``first`` is None), v+ = v
        o = TwoSurfaceOutcome(first=None, order=AlternatingOrder(0, 0), reflections=0, velocity=vel,
                              velocity_float=_floats(vel), impulse=zero, exact=exact)
        return TwoSurfaceResolution([o], by_first, bound, wedge, exact, decisions, d)

    # exact entries for the certified path (enclosed at each precision tried)
    W_ex = [[W[i, 0], W[i, 1]] for i in range(n)]
    gram_ex = [[gram[0, 0], gram[0, 1]], [gram[1, 0], gram[1, 1]]]
    v_ex = [vq[i, 0] for i in range(n)] if rational_path else list(v)
    # the exact data every outcome is verified against before it is returned
    data_ex = (Mq, Hq, vq) if rational_path else (M, H, v)
    for first in (0, 1):
        if signs[first] >= 0:
            continue
        df = d if first == 0 else d.swapped()
        if rational_path:
            m = _certified_ceil_ratio(df, tie_check, decisions)
        else:
            rows = (HA, HB) if first == 0 else (HB, HA)
            m = _certified_ceil_ratio(df, _make_tie_check_algebraic(M, rows[0], rows[1], v), decisions)
        order = AlternatingOrder(first, m)
        if rational_path and exact and _exact_feasible(df, m, int(3.33 * max_exact_digits)):
            ca2, cb2 = _field_power_exit(df, m)
            if first == 1:
                ca2, cb2 = cb2, ca2
            jump = gram.solve(fmpq_mat(2, 1, [ca2 - c[0, 0], cb2 - c[1, 0]]))
            vplus = vq + W * jump
            from .sequential.sparse import verify_matrices  # verify_exact's checks, in flint

            verify_matrices("two-surface", Mq, Hq, vq, vplus, jump)
            _verify_count_rational(df, m)
            qs = [vplus[i, 0] for i in range(n)]
            vel = _rational_column(qs)
            imp = _rational_column([jump[i, 0] for i in range(2)])
            outcomes.append(TwoSurfaceOutcome(first, order, m, vel, _nearest_floats(qs), imp, True))
        elif rational_path:
            want = digits if exact else 20
            vel_b, imp_b, rad, prec = _certified_exit(df, m, want, W_ex, gram_ex, v_ex, first == 1)
            verify_balls("two-surface", *data_ex, vel_b, imp_b, prec)
            _verify_count_balls(df, m, prec)
            if exact:
                outcomes.append(_certified_outcome(first, order, m, vel_b, imp_b, rad, digits, prec))
            else:
                with ctx.workprec(prec):
                    vel = np.array([arb_mid_float(x) for x in vel_b])
                    imp = np.array([arb_mid_float(x) for x in imp_b])
                outcomes.append(TwoSurfaceOutcome(first, order, m, vel, vel.copy(), imp, False,
                                                  _balls=tuple(vel_b), _prec=prec))
        else:  # irrational exact input
            rows = (HA, HB) if first == 0 else (HB, HA)
            if m <= MAX_EXACT_ALGEBRAIC_REFLECTIONS:
                vel = _iterate_exact(M, rows[0], rows[1], v, m)[-1]
                imp = (gram.LUsolve(_matmul(H, vel) - c)).applyfunc(_expanded)
                verify_exact("two-surface", M, H, v, vel, imp)
                outcomes.append(TwoSurfaceOutcome(first, order, m, vel, _floats(vel), imp, True))
            else:
                vel_b, imp_b, rad, prec = _certified_exit(df, m, digits, W_ex, gram_ex, v_ex, first == 1)
                verify_balls("two-surface", *data_ex, vel_b, imp_b, prec)
                _verify_count_balls(df, m, prec)
                outcomes.append(_certified_outcome(first, order, m, vel_b, imp_b, rad, digits, prec))
        by_first[first] = outcomes[-1]
    return TwoSurfaceResolution(outcomes, by_first, bound, wedge, exact, decisions, d)


_COS2_LOWER: dict = {}


def _cos2_lower(K: int) -> fmpq:
    """A rational ``c < cos²(π/K)`` (an Arb enclosure's lower end, minus ``2⁻¹⁰⁰``)."""
    c = _COS2_LOWER.get(K)
    if c is None:
        with ctx.workprec(160):
            man, exp = ((arb.pi() / K).cos() ** 2).lower().mid().man_exp()
        c = fmpq(int(man), 1 << int(-exp)) if exp < 0 else fmpq(int(man) << int(exp))
        c = _COS2_LOWER[K] = c - fmpq(1, 1 << 100)
    return c


def bound_at_most(s_a, s_b, g, K: int) -> bool:
    """Whether the paper's bound ``N = ⌈π/β⌉`` (the largest count of any branch, any velocity)
    is certainly at most ``K ≥ 3``, decided in rational arithmetic from the Gram entries
    ``s_a = H_A M⁻¹H_Aᵀ``, ``s_b``, ``g = H_A M⁻¹H_Bᵀ`` (no Arb evaluation of ``β``).

    ``cos β = −g/√(s_a s_b)``. If ``g ≥ 0`` then ``β ≥ π/2`` and ``N ≤ 2``. Otherwise
    ``β ∈ (0, π/2)`` and ``N ≤ K ⇔ β ≥ π/K ⇔ g² ≤ cos²(π/K) s_a s_b``; the test uses a rational
    ``c < cos²(π/K)``, so ``True`` is certain (``False`` may be returned in a window of width
    about ``2⁻¹⁰⁰`` below the threshold, where the caller only takes its other, equally exact path).

    Three balls (``β = π/3``, ``N = 3``) and a wedge of about ``10⁻³`` rad (``N = 3142``):

    >>> bound_at_most(fmpq(2), fmpq(2), fmpq(-1), 4), bound_at_most(fmpq(1), fmpq(10**6 + 1), fmpq(-10**3), 64)
    (True, False)
    """
    if K < 3:
        raise ValueError("K: must be at least 3")
    if g >= 0:
        return True
    return g * g <= _cos2_lower(K) * s_a * s_b


def branch_counts(mass_matrix, gradients, velocity) -> dict:
    """The certified reflection count of every branch, without the exit velocities.

    Cheap (no exact power, no exit enclosure): what a caller needs to refuse an iteration up
    front (:func:`impactsym.laws.sequential.resolve_sequential` with ``two_surface="iterate"``).

    Returns
    -------
    dict
        ``{first surface: count}`` for each approached surface (empty when none is approached).

    Examples
    --------
    >>> branch_counts("1,0;0,1", "1,0;-1000000,1", "-1,0")
    {0: 1570797}
    >>> branch_counts("11/10,0;0,1", "1,0;-1,1", "-1,-2")
    {0: 4, 1: 4}
    """
    from .sequential.sparse import read_rational, two_surface_data

    data = read_rational(mass_matrix, gradients, velocity)
    if data is not None and data.k == 2:
        return _branch_counts_prepared(two_surface_data(data))
    exact, M, H, v, n = _checked(mass_matrix, gradients, velocity)
    rational_path = not exact or (all_rational(M) and all_rational(H) and all_rational(v))
    if rational_path:
        (W, gram, c, _), vq, _ = _invariants(exact, M, H, v, n)
        d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], c[0, 0], c[1, 0])
    else:
        W, gram, c, _ = _invariants(exact, M, H, v, n)
        d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], c[0], c[1])
    if rational_path:
        return _counts_of(d, lambda first: _tie_check_rational)
    return _counts_of(d, lambda first: _make_tie_check_algebraic(M, *((H[0, :], H[1, :]) if first == 0
                                                                      else (H[1, :], H[0, :])), v))


def _counts_of(d, check_for) -> dict:
    """The certified count ``⌈ψ/β⌉`` of each branch whose first contact approaches (``c < 0``),
    ``check_for(first)`` giving the exact tie check of that branch."""
    if sign_of(d.D) == 0:
        raise ImpactInputError(
            "gradients", "the two rows are parallel (Δ = s_1 s_2 − g² = 0): the wedge is degenerate (opening 0 or π)")
    out = {}
    for first in (0, 1):
        df = d if first == 0 else d.swapped()
        if sign_of(df.ca) < 0:
            out[first] = _certified_ceil_ratio(df, check_for(first), {})
    return out


def _branch_counts_prepared(prepared) -> dict:
    """:func:`branch_counts` of checked rational data (the ``fmpq_mat`` tuple of
    :func:`_resolve`'s ``prepared``)."""
    W, gram, c, vq, Mq, Hq = prepared
    d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], c[0, 0], c[1, 0])
    return _counts_of(d, lambda first: _tie_check_rational)


def _rational_column(qs) -> sp.Matrix:
    """``sp.Matrix([to_sympy_rational(q) for q in qs])`` (a column of the exact ``fmpq`` entries ``qs``),
    built as that constructor builds it: a sparse domain matrix over ``ZZ`` when every entry is an
    integer, else ``QQ`` (the same matrix, without a SymPy ``Rational`` per entry and its sympify)."""
    from sympy.polys.domains import QQ, ZZ
    from sympy.polys.matrices import DomainMatrix

    if all(q.q == 1 for q in qs):
        dod = {i: {0: ZZ(int(q.p))} for i, q in enumerate(qs) if q != 0}
        return sp.Matrix._fromrep(DomainMatrix(dod, (len(qs), 1), ZZ))
    dod = {i: {0: QQ(int(q.p), int(q.q))} for i, q in enumerate(qs) if q != 0}
    return sp.Matrix._fromrep(DomainMatrix(dod, (len(qs), 1), QQ))


def _nearest_floats(qs) -> np.ndarray:
    """``float_vector`` of the column of the exact ``fmpq`` entries ``qs``: each the correctly
    rounded ``p / q`` (Python's integer division, what ``float(Fraction(p, q))`` computes)."""
    return np.array([int(q.p) / int(q.q) for q in qs])


def _as_output(exact, v, vq):
    if exact:
        return sp.Matrix(v)
    return np.asarray(v, dtype=float).copy()


def _kinetic_cos(d: _Data, exact: bool):
    if d.rational():
        ss = d.sa * d.sb
        val = sp.Rational(int(d.g.p), int(d.g.q)) / sp.sqrt(sp.Rational(int(ss.p), int(ss.q)))
        return val if exact else float(sp.N(val, 17))
    return _radsimp(d.g / sp.sqrt(d.sa * d.sb))


#: ``cos²(π/K)`` for the ``K ≥ 2`` where it is rational (Niven's theorem; see :func:`rational_tie`)
RATIONAL_COS2 = {2: fmpq(0), 3: fmpq(1, 4), 4: fmpq(1, 2), 6: fmpq(3, 4)}


def rational_tie(s_a, s_b, g, K: int) -> bool:
    """Whether the wedge of rational data has ``β = π/K`` exactly, ``K ≥ 2`` (a tie of the bound
    ``⌈π/β⌉``): ``cos β = −g/√(s_A s_B)`` with ``s_A, s_B > 0`` and ``β ∈ (0, π)``, decided in
    ``fmpq`` without SymPy.

    Proof. If ``β = π/K`` then ``cos²(π/K) = g²/(s_A s_B)`` is rational, so ``cos(2π/K) = 2cos²(π/K)
    − 1`` is rational. By Niven's theorem a rational multiple ``θ`` of ``π`` has a rational cosine
    only when ``cos θ ∈ {0, ±1/2, ±1}``; with ``θ = 2π/K ∈ (0, π]`` that is ``K ∈ {2, 3, 4, 6}``
    (``cos θ = −1, −1/2, 0, 1/2``), where ``cos²(π/K) = 0, 1/4, 1/2, 3/4``
    (:data:`RATIONAL_COS2`). For every other ``K`` there is no tie. For those four, ``β = π/K``
    holds iff ``cos β = cos(π/K)``, i.e. ``g² = cos²(π/K)·s_A s_B`` and ``−g`` has the sign of
    ``cos(π/K)`` (zero for ``K = 2``, positive otherwise): both exact rational tests.

    Examples
    --------
    Two balls and a wall (``M = I``, rows ``(1, 0)`` and ``(−1, 1)``): ``β = π/4``; orthogonal
    contacts: ``β = π/2``.

    >>> rational_tie(fmpq(1), fmpq(2), fmpq(-1), 4), rational_tie(fmpq(1), fmpq(2), fmpq(-1), 5)
    (True, False)
    >>> rational_tie(fmpq(1), fmpq(1), fmpq(0), 2), rational_tie(fmpq(1), fmpq(4), fmpq(1), 3)
    (True, False)
    """
    c2 = RATIONAL_COS2.get(int(K))
    if c2 is None:
        return False
    if g * g != c2 * s_a * s_b:
        return False
    return g == 0 if K == 2 else g < 0


def _certified_bound(d: _Data, decisions: dict) -> int:
    """``⌈π/β⌉`` (sec. III-C), certified; a tie ``β = π/K`` is decided exactly
    (``−g/√(s_A s_B) = cos(π/K)``: in ``fmpq`` for rational data, :func:`rational_tie`; a
    certified sign otherwise)."""
    def ball_at(prec):
        *_, beta = d.balls(prec)
        with ctx.workprec(prec):
            return arb.pi() / beta

    def tie(K):
        if d.rational():
            return rational_tie(d.sa, d.sb, d.g, K)
        to_sp = (lambda x: sp.Rational(int(x.p), int(x.q))) if d.rational() else (lambda x: x)
        expr = -to_sp(d.g) / sp.sqrt(to_sp(d.sa) * to_sp(d.sb)) - sp.cos(sp.pi / K)
        try:
            return certified_sign(expr, max_digits=200) == 0
        except UndecidableSign:
            return None

    found = certified_ceiling(ball_at, tie, min_tie=2, max_bits=MAX_PRECISION_BITS)
    if found is None:
        raise UndecidableSign("the bound ceil(pi/beta) could not be certified")
    if found[1] == "exact_tie":
        decisions["exact_tie"] = decisions.get("exact_tie", 0) + 1
    return found[0]
