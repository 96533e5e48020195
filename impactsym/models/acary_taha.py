"""The example systems of Acary & Taha, built from their constraint functions by SymPy.

Every builder accepts exact numbers *or SymPy symbols* for its parameters (θ, τ, masses,
velocities), so the same function feeds the exact law, the symbolic closed-form derivations and
the float path. Gradient rows are ``∂h_α/∂q`` of the constraint functions at the contact
configuration, computed by SymPy, never typed in.

Geometry of the pool (sec. 4), reconstructed from eqs. 27, 35, 36 and 42
--------------------------------------------------------------------------
Unit masses and radii ``a = 1``. Ball 2 at the origin, ball 3 at ``(2, 0)``, ball 1 at
``−2(cos θ, sin θ)``: the line 1→2 makes the angle θ with the line 2→3, so θ = 0 is the
chain and θ = 2π/3 closes the third contact (1–3). Eq. 42 (``n₁·n₂ = −½ cos θ``) and the
components of eq. 27 (``ẋ₂⁺ ∝ cos θ − α₁₂``, ``ẋ₃⁺ ∝ α₁₂``, ``ẏ₃⁺ = 0``) fix this layout.

Constraint functions (eq. 24). The paper prints ``h = (Δx)² + (Δy)² − 2``; with radius 1 the
contact distance is 2, so the squared form should read ``… − 4`` (misprint). Here the contacts
are ``h_α = ‖G_j − G_i‖ − 2a`` (``constraint="distance"``, default), whose gradients are the unit
normals that eq. 27's impulses refer to; ``constraint="squared"`` uses ``‖G_j − G_i‖² − 4a²``,
whose gradient rows are ``4a`` times longer (impulses ``1/(4a)`` times, ratios unchanged).

Incidence. The text (sec. 4.1) gives ``q̇⁻ = [−cos(θ+τ), −sin(θ+τ), 0, 0, 0, 0]``, but eqs. 27,
35 and 36 are reproduced only by ``q̇⁻ = (cos(θ−τ), sin(θ−τ))`` for ball 1 (``incidence=
"theta-minus-tau"``, default); ``"theta-plus-tau"`` gives ``(cos(θ+τ), sin(θ+τ))`` and
``"printed"`` the text's form. The paper checks record which reading each equation supports.

Examples
--------
>>> sc = chain3()
>>> sc.H, sc.v.T
(Matrix([
[-1,  1, 0],
[ 0, -1, 1]]), Matrix([[1, 0, 0]]))
>>> import sympy as sp
>>> pool(sp.pi / 4).H.shape, pool(2 * sp.pi / 3).contacts
((2, 6), ['1-2', '2-3', '1-3'])
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

from ..arithmetic import LazyModule
from ..errors import ImpactInputError
from ..exact import certified_sign
from ..scenes import Scene

# SymPy is imported on first use: ``chain3(..., rational=True)`` builds the chain without it (issue 15)
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["chain3", "pool", "bernoulli", "pool_positions", "INCIDENCES"]

INCIDENCES = ("theta-minus-tau", "theta-plus-tau", "printed")


def _coord_names(n_balls: int, planar: bool) -> list[str]:
    if planar:
        return [f"{c}{i}" for i in range(1, n_balls + 1) for c in ("x", "y")]
    return [f"q{i}" for i in range(1, n_balls + 1)]


def _coords(n_balls: int, planar: bool):
    names = _coord_names(n_balls, planar)
    return list(sp.symbols(" ".join(names), real=True)), names


def _approaching(H, v):
    out = []
    for w in H * v:
        try:
            out.append(certified_sign(w) < 0)
        except Exception:  # symbolic parameters: undecided
            out.append(None)
    return out


def _chain3_constraints(r):
    """The chain's constraints (eq. 14), ``h₁ = q₂ − q₁ − 2r``, ``h₂ = q₃ − q₂ − 2r``, each as
    ``({index of q: coefficient}, constant)``: linear in ``q``, so their gradient rows are the
    coefficients (the rational build reads them so; the SymPy one differentiates ``h``)."""
    return [({1: 1, 0: -1}, -2 * r), ({2: 1, 1: -1}, -2 * r)]


def chain3(masses=(1, 1, 1), velocities=(1, 0, 0), radius=1, *, rational=False):
    """The 3-ball chain of sec. 3.2: balls on a line touching, contacts 1–2 and 2–3 closed.

    Constraints ``h₁ = q₂ − q₁ − 2r ≥ 0``, ``h₂ = q₃ − q₂ − 2r ≥ 0`` (eq. 14); ``M = diag(m)``.
    Eq. 13 is ``M(q̇⁺ − q̇⁻) = Hᵀp`` with these rows.

    Parameters
    ----------
    masses, velocities : three numbers or symbols each (defaults: unit masses, ``q̇⁻ = (1, 0, 0)``).
    rational : every number an ``int`` or a ``Fraction`` (masses positive), and ``M``, ``H``, ``v``
        :class:`~impactsym.resolution.RationalMatrix`, built without SymPy (the command line's
        float path, issue 15); the same entries as the SymPy build.

    >>> from fractions import Fraction
    >>> chain3((1, Fraction(1, 2), 4), rational=True).M
    RationalMatrix([['1', '0', '0'], ['0', '1/2', '0'], ['0', '0', '4']])
    """
    if len(masses) != 3 or len(velocities) != 3:
        raise ImpactInputError("masses/velocities", "chain3 needs exactly three of each")
    if rational:
        return _chain3_rational(masses, velocities, radius)
    q, names = _coords(3, planar=False)
    r = sp.sympify(radius)
    h = [sum((c * q[j] for j, c in coef.items()), const) for coef, const in _chain3_constraints(r)]
    H = sp.Matrix([[sp.diff(hi, qj) for qj in q] for hi in h])
    M = sp.diag(*[sp.sympify(m) for m in masses])
    v = sp.Matrix([sp.sympify(x) for x in velocities])
    return Scene(M, H, v, names, ["1-2", "2-3"], _approaching(H, v),
                 {"paper": "acary-taha", "ref": "sec. 3.2, eqs. 13-14", "scene": "chain3"})


def _chain3_rational(masses, velocities, radius):
    from ..resolution import RationalMatrix

    values = [*masses, *velocities, radius]
    if any(isinstance(x, bool) or not isinstance(x, (int, Fraction)) for x in values):
        raise ImpactInputError("masses/velocities", "rational=True takes ints and Fractions")
    for m in masses:
        if m <= 0:
            raise ImpactInputError("masses", f"must be positive, got {m}")
    H = RationalMatrix.from_entries((2, 3), {(i, j): c for i, (coef, _) in enumerate(_chain3_constraints(Fraction(radius)))
                                             for j, c in coef.items()})
    M = RationalMatrix.from_entries((3, 3), {(i, i): m for i, m in enumerate(masses)})
    v = RationalMatrix.column(velocities)
    approaching = [sum((H[i, j] * v[j, 0] for j in range(3)), Fraction(0)) < 0 for i in range(2)]
    return Scene(M, H, v, _coord_names(3, planar=False), ["1-2", "2-3"], approaching,
                 {"paper": "acary-taha", "ref": "sec. 3.2, eqs. 13-14", "scene": "chain3"})


def pool_positions(theta, a=1):
    """Centres of balls 1, 2, 3 (see the module docstring): ``G₁ = −2a(cos θ, sin θ)``, ``G₂ = 0``, ``G₃ = (2a, 0)``."""
    a = sp.sympify(a)
    return (-2 * a * sp.Matrix([sp.cos(theta), sp.sin(theta)]), sp.zeros(2, 1), sp.Matrix([2 * a, 0]))


def _incidence_velocity(theta, tau, incidence):
    if incidence == "theta-minus-tau":
        ang, sign = theta - tau, 1
    elif incidence == "theta-plus-tau":
        ang, sign = theta + tau, 1
    elif incidence == "printed":
        ang, sign = theta + tau, -1
    else:
        raise ImpactInputError("incidence", f"must be one of {INCIDENCES}, got {incidence!r}")
    return sign * sp.cos(ang), sign * sp.sin(ang)


def pool(theta, tau=0, *, incidence="theta-minus-tau", constraint="distance", third_contact=None, a=1):
    """The planar pool of sec. 4: ball 1 strikes balls 2 and 3 (unit masses, radius ``a``).

    Parameters
    ----------
    theta : angle between the lines 1→2 and 2→3 (number or symbol), θ ∈ [0, 2π/3]
    tau : incidence angle of ball 1 relative to the line 1→2 (number or symbol)
    incidence : ``"theta-minus-tau"`` (default), ``"theta-plus-tau"`` or ``"printed"``
    constraint : ``"distance"`` (unit-normal rows, default) or ``"squared"`` (eq. 24's form, corrected)
    third_contact : include contact 1–3. Default: decided exactly (closed iff θ = 2π/3);
        required when θ is symbolic.
    """
    theta, tau = sp.sympify(theta), sp.sympify(tau)
    if third_contact is None:
        if theta.free_symbols:
            third_contact = False
        else:
            third_contact = certified_sign(theta - 2 * sp.pi / 3) == 0
            if not theta.free_symbols and (certified_sign(theta) < 0 or certified_sign(theta - 2 * sp.pi / 3) > 0):
                raise ImpactInputError("theta", f"must lie in [0, 2*pi/3] (balls 1 and 3 would overlap), got {theta}")
    q, names = _coords(3, planar=True)
    pairs = [(0, 1), (1, 2)] + ([(0, 2)] if third_contact else [])
    if constraint not in ("distance", "squared"):
        raise ImpactInputError("constraint", f"must be 'distance' or 'squared', got {constraint!r}")
    H = sp.Matrix(_pool_gradients(theta, bool(third_contact), constraint, sp.sympify(a)))
    vx, vy = _incidence_velocity(theta, tau, incidence)
    v = sp.Matrix([vx, vy, 0, 0, 0, 0])
    contacts = [f"{i + 1}-{j + 1}" for i, j in pairs]
    return Scene(sp.eye(6), H, v, names, contacts, _approaching(H, v),
                 {"paper": "acary-taha", "ref": "sec. 4, eqs. 24-27", "scene": "pool",
                  "theta": theta, "tau": tau, "incidence": incidence, "constraint": constraint})


#: ``(cos, sin)`` of ``k·π/2`` for ``k mod 4``: the only angles in ``π·Q`` whose cosine and sine are
#: both rational (Niven's theorem)
_QUARTER_TURNS = ((1, 0), (0, 1), (-1, 0), (0, -1))


def pool_rational(theta_turns, tau_turns=0):
    """The pool of :func:`pool` (default incidence and constraint, ``a = 1``) at ``θ = theta_turns·π``
    and ``τ = tau_turns·π`` with ``M``, ``H``, ``v`` :class:`~impactsym.resolution.RationalMatrix`,
    built without SymPy, or ``None`` when its data are not rational.

    Its data are rational exactly when ``cos θ``, ``sin θ``, ``cos(θ − τ)``, ``sin(θ − τ)`` are
    (Niven: ``θ`` and ``θ − τ`` multiples of ``π/2``), so for ``θ ∈ [0, 2π/3]`` only ``θ = 0`` and
    ``θ = π/2``; every other pool (``sqrt(3)/2`` at ``θ = π/3``, Bernoulli's ``θ = 2π/3``) gives
    ``None``. The gradient of ``h = ‖G_j − G_i‖ − 2`` at contact is ``∓(G_j − G_i)/2`` on balls
    ``i``, ``j`` (the unit normal that :func:`pool` obtains by differentiating ``h``).

    >>> sc = pool_rational(Fraction(1, 2))
    >>> sc.H, sc.v.tolist()[:2], sc.contacts
    (RationalMatrix([['0', '-1', '0', '1', '0', '0'], ['0', '0', '-1', '0', '1', '0']]), [[Fraction(0, 1)], [Fraction(1, 1)]], ['1-2', '2-3'])
    >>> pool_rational(Fraction(1, 3)) is None
    True
    """
    from ..resolution import RationalMatrix

    theta, tau = Fraction(theta_turns), Fraction(tau_turns)
    if theta not in (0, Fraction(1, 2)) or (2 * (theta - tau)).denominator != 1:
        return None
    c, s = _QUARTER_TURNS[int(2 * theta) % 4]
    vx, vy = _QUARTER_TURNS[int(2 * (theta - tau)) % 4]
    G = [(-2 * c, -2 * s), (0, 0), (2, 0)]  # pool_positions at a = 1
    pairs = [(0, 1), (1, 2)]  # the third contact closes only at θ = 2π/3
    H = {}
    for r, (i, j) in enumerate(pairs):
        for d in range(2):
            n = Fraction(G[j][d] - G[i][d], 2)
            if n:
                H[r, 2 * i + d], H[r, 2 * j + d] = -n, n
    H = RationalMatrix.from_entries((2, 6), H)
    v = RationalMatrix.column([vx, vy, 0, 0, 0, 0])
    approaching = [sum((H[r, k] * v[k, 0] for k in range(6)), Fraction(0)) < 0 for r in range(2)]
    return Scene(RationalMatrix.from_entries((6, 6), {(k, k): 1 for k in range(6)}), H, v, _coord_names(3, planar=True),
                 [f"{i + 1}-{j + 1}" for i, j in pairs], approaching,
                 {"paper": "acary-taha", "ref": "sec. 4, eqs. 24-27", "scene": "pool", "theta": theta, "tau": tau,
                  "incidence": "theta-minus-tau", "constraint": "distance"})


@lru_cache(maxsize=256)  # bounded: a sweep over θ must not grow it without end
def _pool_gradients(theta, third_contact: bool, constraint: str, a) -> sp.ImmutableMatrix:
    """The gradient rows of the pool's contacts at the balls' positions (simplified entries):
    the slow part of :func:`pool` (one ``simplify`` per entry), computed once per geometry."""
    from ..arithmetic.remembered import simplify_remembered

    q, _ = _coords(3, planar=True)
    G = [sp.Matrix(q[0:2]), sp.Matrix(q[2:4]), sp.Matrix(q[4:6])]
    pairs = [(0, 1), (1, 2)] + ([(0, 2)] if third_contact else [])
    hs = []
    for i, j in pairs:
        d2 = (G[j] - G[i]).dot(G[j] - G[i])
        hs.append(sp.sqrt(d2) - 2 * a if constraint == "distance" else d2 - 4 * a**2)
    P = pool_positions(theta, a)
    at = dict(zip(q, [*P[0], *P[1], *P[2]]))
    rows = []
    for (i, j), h in zip(pairs, hs):
        # a contact's gradient wrt ball j is minus its gradient wrt ball i (h depends on the
        # difference of the two positions only): each such pair is simplified once
        # the positions are put in by xreplace (one simultaneous replacement of the six symbols,
        # each entry rebuilt once; subs replaced them one after another, half again the time): the
        # same entries (checked on every pool of the test suite)
        raw = [sp.diff(h, qj).xreplace(at) for qj in q]
        if constraint == "distance" and isinstance(theta, sp.Symbol):
            # the distance at contact, ‖G_j − G_i‖² at the positions, is a polynomial in cos θ, sin θ:
            # sin²θ = 1 − cos²θ writes it as a number when it is one (4a² for 1–2), and the
            # entries' √ of it is that number's root: the same entries, which simplify then need
            # not find through trigsimp (0.2 s for the symbolic pool's first row)
            d2 = (G[j] - G[i]).dot(G[j] - G[i]).subs(at)
            d2_number = sp.expand(sp.expand(d2).subs(sp.sin(theta) ** 2, 1 - sp.cos(theta) ** 2))
            if d2_number.is_number and d2_number != d2:
                raw = [x.xreplace({d2: d2_number}) for x in raw]
        done: dict = {}
        row = []
        for x in raw:
            if x in done:
                row.append(done[x])
            elif -x in done:
                row.append(-done[-x])
            else:
                # simplify, remembered per entry (the entries of one geometry recur whenever this
                # cache is cleared and rebuilt; impactsym.arithmetic.remembered)
                done[x] = simplify_remembered(x)
                row.append(done[x])
        rows.append(row)
    return sp.ImmutableMatrix(rows)


def bernoulli(tau=None, **kw):
    """Bernoulli's problem (sec. 4.2, case 3, eq. 37): the pool at θ = 2π/3, three closed contacts
    (``tau`` default ``−π/6``)."""
    return pool(2 * sp.pi / 3, -sp.pi / 6 if tau is None else tau, third_contact=True, **kw)
