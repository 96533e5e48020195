"""Inelastic collapse of two contacts: an alternation ``X, Y, X, Y, ...`` that never ends
(restitution < 1), decided exactly, and its limit in closed form.

The two-contact reduction
-------------------------
Let ``W_i = M⁻¹H_iᵀ``, ``s_i = H_i W_i``, ``g = H_X W_Y`` (the Gram entries of the pair). A single
impact on ``X`` changes ``v`` only along ``W_X``, so ``G_X(e_X)`` and ``G_Y(e_Y)`` act on the plane
``span(W_X, W_Y)`` and are the identity on its M-orthogonal complement ``{H_X v = H_Y v = 0}``.
In the plane a state is ``(a, b) = (H_X v, H_Y v)``:

    G_X:  a ↦ −e_X a,           b ↦ b − (1+e_X) (g/s_X) a
    G_Y:  b ↦ −e_Y b,           a ↦ a − (1+e_Y) (g/s_Y) b

Before an impact on ``X`` write ``u = −a > 0`` (approach speed) and ``ρ = b/u`` (``b ≥ 0`` after
the first impact: ``Y`` was just left). With ``κ_X = −(1+e_X) g/s_X`` and ``κ_Y = −(1+e_Y) g/s_Y``
the alternation continues past ``X`` iff ``ρ < κ_X`` (then ``Y`` is approached), the ratio before
``Y`` is ``f_X(ρ) = e_X/(κ_X − ρ)``, and after a full ``X, Y`` step ``ρ' = φ(ρ) = f_Y(f_X(ρ))``.
If ``g ≥ 0`` the alternation stops after at most two impacts (``κ ≤ 0``). Otherwise ``φ`` is an
increasing Möbius map on its domain ``D = (−∞, ρ_max)``, ``ρ_max = κ_X − e_X/κ_Y`` (where
``φ → +∞``), so the ratios are monotone:

* ``φ(ρ₀) ≤ ρ₀``: they decrease to a fixed point in ``[0, ρ₀]`` (``φ ≥ 0``): **never ends**;
* ``φ(ρ₀) > ρ₀``: they increase, and stay in ``D`` forever iff a fixed point lies in
  ``(ρ₀, ρ_max)``, i.e. iff the smaller root ``ρ₋`` of ``κ_Y ρ² − Bρ + e_Y κ_X = 0``
  (``B = κ_Xκ_Y − e_X + e_Y``, discriminant ``Δ = B² − 4κ_Xκ_Y e_Y``) is real and
  ``ρ₀ < ρ₋ < ρ_max``. Both comparisons are decided without square roots.

Fixed points of ``φ`` are the eigen-directions of the composite map, whose eigenvalues satisfy
``λ² − (κ_Xκ_Y − e_X − e_Y)λ + e_X e_Y = 0`` (the same discriminant ``Δ``): a collapse needs real
eigenvalues. For equal restitution ``e`` on both contacts and kinetic angle cosine
``c = g/√(s_X s_Y) < 0``, ``Δ ≥ 0`` iff ``(1+e)|c| ≥ 2√e`` iff ``e ≤ e_c = (1 − sin θ)/(1 + sin θ)``
with ``sin θ = √(1 − c²)`` (:func:`critical_restitution`); three equal balls on a line have
``c = −1/2`` and ``e_c = 7 − 4√3``.

The limit
---------
A full step dissipates energy along its eigen-direction unless ``e_X = e_Y = 1`` (and then
``Δ < 0``: no collapse), so the eigenvalue of the limit direction is ``< 1``: ``(a, b) → 0``
geometrically. The accumulated pair impulse ``p`` then converges, ``v_n = v + W_X p_X + W_Y p_Y``,
and the limit satisfies ``H_X v∞ = H_Y v∞ = 0``: ``p = −Γ⁻¹(a, b)`` with ``Γ`` the 2×2 Gram
matrix, i.e. ``v∞`` is the M-orthogonal projection of ``v`` onto ``{H_X v = 0, H_Y v = 0}``, the
perfectly plastic impact of the pair (``tests/test_sequential_restitution.py`` sums the series
symbolically and checks this identity with SymPy).

Other contacts ``C`` must stay unapproached along the whole infinite tail. Every single impact
is non-expansive in the kinetic norm (``‖G_u(e)‖_M = 1`` for ``0 ≤ e ≤ 1``) and fixes ``v∞``, so
``|H_C v_n − H_C v∞| ≤ √s_C ‖v − v∞‖_M`` for every later state: ``H_C v∞ > 0`` and
``(H_C v∞)² > s_C ‖v − v∞‖²_M`` certify ``C`` (exact, no root). A contact with ``H_C v∞ < 0``
would be approached infinitely often (infinitely many orderings branch off the collapse),
``H_C v∞ = 0`` cannot be certified: both are refused (``NonTermination``).
"""

from __future__ import annotations


from ...errors import DomainError, ImpactInputError, NonTermination, VerificationError

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["critical_restitution", "alternation_limit"]


def _pair(system, X, Y):
    """``(s_X, s_Y, g)`` of the pair, exact."""
    return system.s[X], system.s[Y], system.w(system.W[Y], X)


def _possible(F, sX, sY, g, eX, eY) -> bool:
    """Can the alternation of this pair ever be infinite (for some state)? ``g < 0``, the rows
    independent and real eigenvalues (``Δ ≥ 0``)."""
    if F.sign(g) >= 0:
        return False
    if F.sign(F.norm(sX * sY - g * g)) == 0:
        return True  # opposite parallel rows: handled (refused) by the decision
    kX = F.norm(-(1 + eX) * g / sX)
    kY = F.norm(-(1 + eY) * g / sY)
    B = F.norm(kX * kY - eX + eY)
    return F.sign(F.norm(B * B - 4 * kX * kY * eY)) >= 0


def _never_ends(F, sX, sY, g, eX, eY, a, b, names) -> bool:
    """Exactly: does the pure alternation ``X, Y, X, ...`` from the state ``(a, b) = (H_X v,
    H_Y v)``, ``a < 0``, never end? (See the module docstring.)"""
    if F.sign(g) >= 0:
        return False
    if F.sign(F.norm(sX * sY - g * g)) == 0:
        # opposite parallel rows (g < 0): Y is approached after X unless e_X = 0; each double step
        # multiplies the approach speed by e_X e_Y
        if F.sign(eX) == 0 or F.sign(eY) == 0:
            return False
        raise NonTermination(
            f"restitution: contacts {names[0]} and {names[1]} are opposite and parallel (H_{names[1]} is a "
            f"negative multiple of H_{names[0]}); with restitutions e_{names[0]} e_{names[1]} > 0 they alternate "
            "forever (a bounce between parallel walls), a limit the sequential law does not sum")
    kX = F.norm(-(1 + eX) * g / sX)
    kY = F.norm(-(1 + eY) * g / sY)
    u = F.norm(-a)
    rho0 = F.norm(b / u)
    if F.sign(F.norm(kX - rho0)) <= 0:  # Y is not approached after X
        return False
    sigma = F.norm(eX / (kX - rho0))
    if F.sign(F.norm(kY - sigma)) <= 0:  # X is not approached after Y
        return False
    rho1 = F.norm(eY / (kY - sigma))
    if F.sign(F.norm(rho1 - rho0)) <= 0:
        return True
    B = F.norm(kX * kY - eX + eY)
    delta = F.norm(B * B - 4 * kX * kY * eY)
    if F.sign(delta) < 0:
        return False
    # Here phi(rho0) > rho0, so rho0 is not between the roots; with the parity of the roots in
    # (rho0, rho_max) the second halves of the two tests below are implied by the first halves.
    # They are kept as the literal conditions (rho0 < rho_-, rho_- < rho_max).
    d0 = F.norm(B - 2 * kY * rho0)  # rho0 < rho_-  <=>  d0 > sqrt(delta)
    if not (F.sign(d0) > 0 and F.sign(F.norm(d0 * d0 - delta)) > 0):
        return False
    rho_max = F.norm(kX - eX / kY)
    dm = F.norm(B - 2 * kY * rho_max)  # rho_- < rho_max  <=>  dm < sqrt(delta)
    return F.sign(dm) < 0 or F.sign(F.norm(dm * dm - delta)) < 0


def _limit(system, v, X, Y):
    """The plastic limit of the pair from ``v``: ``(v∞, p_X, p_Y, ‖v − v∞‖²_M)``, exact."""
    F = system.F
    sX, sY, g = _pair(system, X, Y)
    a, b = system.w(v, X), system.w(v, Y)
    det = F.norm(sX * sY - g * g)
    pX = F.norm(-(sY * a - g * b) / det)
    pY = F.norm(-(sX * b - g * a) / det)
    out = list(v)
    for j, wj in system.wcols[X]:
        out[j] = F.norm(out[j] + pX * wj)
    for j, wj in system.wcols[Y]:
        out[j] = F.norm(out[j] + pY * wj)
    dist2 = F.norm(pX * pX * sX + 2 * pX * pY * g + pY * pY * sY)
    return tuple(out), pX, pY, dist2


def _tail_certified(system, vinf, dist2, X, Y):
    """``True`` when every other contact is certified never approached along the tail, ``False``
    when some contact is not yet certified (``H_C v∞ > 0``: step further); raises when a contact
    would be approached at the limit (``H_C v∞ ≤ 0``)."""
    F = system.F
    ok = True
    for C in range(system.k):
        if C in (X, Y):
            continue
        hc = system.w(vinf, C)
        sg = F.sign(hc)
        if sg <= 0:
            what = "approaches" if sg < 0 else "grazes"
            raise NonTermination(
                f"restitution: contacts {X + 1} and {Y + 1} collapse (they alternate forever), and their "
                f"plastic limit {what} contact {C + 1} (H_{C + 1} v∞ = {F.to_sympy(hc)}): "
                + ("infinitely many orderings branch off the collapse, " if sg < 0 else
                   "whether contact {} is approached along the tail cannot be certified, ".format(C + 1))
                + "a collapse involving more than two contacts, which has no closed form here")
        if F.sign(F.norm(hc * hc - system.s[C] * dist2)) <= 0:
            ok = False
    return ok


class _CollapseDetector:
    """The ``collapse`` hook of :func:`~impactsym.laws.sequential.search._explore`.

    ``exact_v(node)`` returns the exact velocity of a node (the state itself in exact mode, a
    replay in float mode); ``as_state(v)`` turns an exact limit into a leaf state of the search;
    ``key_of(v)`` gives its exact outcome key. Only pairs whose restitution admits a collapse
    (:func:`_possible`, decided once per ordered pair) look at the state at all."""

    def __init__(self, system, exact_v, as_state, key_of):
        self.system = system
        self.exact_v = exact_v
        self.as_state = as_state
        self.key_of = key_of
        F, e, k = system.F, system.e, system.k
        self.partners = []
        for X in range(k):
            ys = []
            for Y in range(k):
                if Y != X:
                    sX, sY, g = _pair(system, X, Y)
                    if _possible(F, sX, sY, g, e[X], e[Y]):
                        ys.append(Y)
            self.partners.append(ys)
        self.checks = 0

    def __call__(self, node, X):
        ys = self.partners[X]
        if not ys:
            return None
        system = self.system
        F, e = system.F, system.e
        v = self.exact_v(node)
        a = system.w(v, X)
        for Y in ys:
            sX, sY, g = _pair(system, X, Y)
            self.checks += 1
            if not _never_ends(F, sX, sY, g, e[X], e[Y], a, system.w(v, Y), (X + 1, Y + 1)):
                continue
            vinf, _, _, dist2 = _limit(system, v, X, Y)
            if _tail_certified(system, vinf, dist2, X, Y):
                return self.as_state(vinf), (X, Y), self.key_of(vinf)
            return None  # a collapse, but another contact is not yet certified: step further
        return None


def _verified_collapse(system, prefix, cycle):
    """The exact outcome of ``prefix`` followed by the infinite alternation ``cycle``, verified
    before it is used: every prefix impact acts on an approached contact, the alternation is
    decided infinite again, the limit lies on both contacts (``H_X v∞ = H_Y v∞ = 0``), and
    :func:`impactsym.verify.verify_exact` (valid, momentum ``M(v∞ − v0) = Hᵀp`` with ``p ≥ 0``,
    energy not gained)."""
    from ...verify import verify_exact

    F = system.F
    X, Y = cycle
    v = system.v0
    p = [F.zero] * system.k
    for step, i in enumerate(prefix):
        wi = system.w(v, i)
        if F.sign(wi) >= 0:
            raise VerificationError("sequential", f"ordering {tuple(prefix)[:20]}: reflection {step + 1} acts on "
                                                  f"surface {i}, which is not approached (H_{i + 1} v = {wi})")
        v, pi = system.reflect(v, i, wi)
        p[i] = F.norm(p[i] + pi)
    sX, sY, g = _pair(system, X, Y)
    a = system.w(v, X)
    if F.sign(a) >= 0 or not _never_ends(F, sX, sY, g, system.e[X], system.e[Y], a, system.w(v, Y), (X + 1, Y + 1)):
        raise VerificationError("sequential", f"collapse of contacts {X + 1}, {Y + 1} after {tuple(prefix)[:20]} "
                                              "was not confirmed on replay")
    vinf, pX, pY, _ = _limit(system, v, X, Y)
    if F.sign(system.w(vinf, X)) != 0 or F.sign(system.w(vinf, Y)) != 0:
        raise VerificationError("sequential", "collapse limit is not on both contacts")
    p[X] = F.norm(p[X] + pX)
    p[Y] = F.norm(p[Y] + pY)
    verify_exact("sequential (collapse)", system.M, system.H, list(system.v0), list(vinf), p,
                 energy_ratio=None, energy_at_most=1)
    return vinf, p


def critical_restitution(mass_matrix, gradients, first: int = 0, second: int = 1):
    """The critical restitution ``e_c`` of a pair of contacts, exact: with one restitution ``e``
    on both, an alternation ``first, second, first, ...`` can be infinite (inelastic collapse)
    iff ``e < e_c`` — or ``e = e_c`` for the states on the double eigen-direction — and always
    ends when ``e > e_c``.

    ``e_c = (1 − sin θ)/(1 + sin θ)`` with ``cos θ = H_i M⁻¹H_jᵀ/√(s_i s_j)`` the kinetic angle
    cosine, when ``cos θ < 0``; ``0`` when ``cos θ ≥ 0`` (no collapse for any ``e``).
    Per-contact restitutions ``e_i``, ``e_j`` admit a collapse iff ``cos θ < 0`` and
    ``(1+e_i)(1+e_j) cos²θ ≥ (√e_i + √e_j)²`` (see :mod:`impactsym.laws.sequential.collapse`).

    Parameters
    ----------
    mass_matrix : matrix-like (n×n), SPD, exact
    gradients : matrix-like (k×n), exact
    first, second : int
        Rows of ``gradients`` (0-based), distinct.

    Returns
    -------
    sympy.Expr
        Exact, in ``[0, 1)``.

    Examples
    --------
    Three equal balls on a line:

    >>> critical_restitution("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1")
    7 - 4*sqrt(3)

    A unit ball between a wall and a ball of mass 3 (``cos²θ = 3/4``), and two perpendicular walls:

    >>> critical_restitution("1,0;0,3", "1,0;-1,1"), critical_restitution("1,0;0,1", "1,0;0,1")
    (1/3, 0)

    References
    ----------
    McNamara & Young (1994), three-particle inelastic collapse below ``e = 7 − 4√3`` (the value
    of the three-ball case; derived here for any pair from the composite map).
    """
    from ...mechanics import check_gradients, check_mass_matrix

    M = check_mass_matrix(mass_matrix, exact=True)
    H = check_gradients(gradients, M.shape[0], exact=True)
    for name, idx in (("first", first), ("second", second)):
        if isinstance(idx, bool) or not isinstance(idx, int) or not 0 <= idx < H.rows:
            raise ImpactInputError(name, f"must be a row index of gradients in [0, {H.rows - 1}], got {idx!r}")
    if first == second:
        raise ImpactInputError("second", f"must differ from first (both are {first})")
    hi, hj = H[first, :], H[second, :]
    Wi, Wj = M.LUsolve(hi.T), M.LUsolve(hj.T)
    si, sj, g = sp.radsimp((hi * Wi)[0, 0]), sp.radsimp((hj * Wj)[0, 0]), sp.radsimp((hi * Wj)[0, 0])
    from ...arithmetic import certified_sign

    if certified_sign(g) >= 0:
        return sp.Integer(0)
    cos2 = sp.radsimp(g * g / (si * sj))
    if certified_sign(1 - cos2) == 0:
        raise DomainError("gradients: the two rows are opposite and parallel (kinetic angle pi): any "
                          "restitution e > 0 bounces forever; no critical value")
    sin = sp.sqrt(1 - cos2)
    ec = sp.radsimp((1 - sin) / (1 + sin))
    return sp.expand(ec)


def alternation_limit(mass_matrix, gradients, velocity, restitution, first: int = 0, second: int = 1):
    """Decide exactly whether the pure alternation ``first, second, first, ...`` from ``velocity``
    never ends (inelastic collapse); return its limit, or ``None`` when it ends.

    Only the two contacts ``first`` and ``second`` are considered (the other rows of
    ``gradients`` are ignored); ``first`` must be approached (``H_first v < 0``).

    Parameters
    ----------
    mass_matrix, gradients, velocity : exact matrix-like data, as for :func:`resolve_sequential`
    restitution : exact number or one per row of ``gradients``, in ``[0, 1]``
    first, second : int
        Rows of ``gradients`` (0-based), distinct.

    Returns
    -------
    None, or (sympy.Matrix, sympy.Matrix)
        The limit velocity (the M-orthogonal projection of ``velocity`` onto
        ``{H_first v = H_second v = 0}``) and the pair's impulses ``(p_first, p_second)``.

    Examples
    --------
    >>> v, p = alternation_limit("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1/20")
    >>> list(v), list(p)
    ([1/3, 1/3, 1/3], [2/3, 1/3])
    >>> alternation_limit("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1/10") is None
    True
    """
    from ...mechanics import check_gradients, check_mass_matrix, check_velocity
    from .resolve import check_restitutions
    from .search import _ExactSystem

    M = check_mass_matrix(mass_matrix, exact=True)
    H = check_gradients(gradients, M.shape[0], exact=True)
    v = check_velocity(velocity, M.shape[0], exact=True)
    for name, idx in (("first", first), ("second", second)):
        if isinstance(idx, bool) or not isinstance(idx, int) or not 0 <= idx < H.rows:
            raise ImpactInputError(name, f"must be a row index of gradients in [0, {H.rows - 1}], got {idx!r}")
    if first == second:
        raise ImpactInputError("second", f"must differ from first (both are {first})")
    E = check_restitutions(restitution, H.rows, exact=True)
    system = _ExactSystem(M, H, v, E)
    F = system.F
    a = system.w(system.v0, first)
    if F.sign(a) >= 0:
        raise DomainError(f"velocity: contact {first + 1} is not approached (H_{first + 1} v = {F.to_sympy(a)} >= 0)")
    sX, sY, g = _pair(system, first, second)
    if not _never_ends(F, sX, sY, g, system.e[first], system.e[second], a, system.w(system.v0, second),
                       (first + 1, second + 1)):
        return None
    vinf, pX, pY, _ = _limit(system, system.v0, first, second)
    if F.sign(system.w(vinf, first)) != 0 or F.sign(system.w(vinf, second)) != 0 or F.sign(pX) < 0 or F.sign(pY) < 0:
        raise VerificationError("sequential (collapse)", "the pair's limit failed its exact check")
    return sp.Matrix([F.to_sympy(x) for x in vinf]), sp.Matrix([F.to_sympy(pX), F.to_sympy(pY)])
