"""The classical impact laws Acary & Taha measure the impulse-ratio law against (secs. 2.2, 3.2).

All laws share eq. 7: ``Δv = W p`` with the Delassus operator ``W = H M⁻¹ Hᵀ`` on the closed
contacts, ``M Δq̇ = Hᵀp``, ``p ≥ 0``; and they are checked against eq. 8 (``H v⁺ ≥ 0``) and
against the energy (``T⁺ ≤ T⁻``), each decided exactly.

* :func:`newton_moreau` — eqs. 9–10, Moreau's form ``0 ≤ H v⁺ + e H v⁻ ⊥ p ≥ 0``, a linear
  complementarity problem ``0 ≤ W p + (1+e) H v⁻ ⊥ p ≥ 0``. Solved exactly by enumerating
  active sets for ``k ≤`` :data:`MAX_ENUMERATED_CONTACTS`; beyond, as the equivalent
  non-negative least-squares problem ``min_{p ≥ 0} ‖R⁻¹Hᵀp + (1+e)Rᵀv⁻‖`` (``M = RRᵀ``; the LCP
  is its optimality condition), whose active set is then re-solved and checked exactly.
  ``W`` is positive semi-definite, so ``v⁺`` is unique; ``p`` is unique unless rows of ``H``
  are dependent on the contacts that stay closed, and several solutions are reported.
* :func:`poisson` — eq. 11. Compression: the LCP with ``e = 0`` (``0 ≤ H v_c ⊥ p_c ≥ 0``).
  Restitution as the paper states it (sec. 3.2): ``p = (1 + e_p) p_c`` contact-wise
  (``variant="paper"``); or Glocker–Pfeiffer's expansion LCP ``p = (1 + e_p) p_c + λ``,
  ``0 ≤ H v⁺ ⊥ λ ≥ 0`` (``variant="glocker-pfeiffer"``), which restores ``H v⁺ ≥ 0``.
* :func:`energetic` — eq. 12 alone, ``T⁺ = e T⁻``: one equation for ``k`` unknown impulses.
  For one contact it fixes the impulse. For ``k ≥ 2`` it is under-determined (a ``k−1``
  parameter family: the impulse ratios). **Choice made here:** without ratios, the impulse
  *direction* is that of the elastic Newton/Moreau solution (``e = 1``; it conserves energy, see
  below), and eq. 12 fixes its magnitude; with ratios, this *is* the impulse-ratio law. If the
  elastic Newton impulse is not unique or vanishes, the direction is undefined and a
  ``DomainError`` says so.
* :func:`han_gilmore` — sequential impacts in the manner of Han & Gilmore (eqs. 15–16): at each
  stage, a hypothesis is a set ``J`` of closed contacts that are approaching or grazing
  (``H_i v ≤ 0``), with at least one approaching, that impact together with Newton's law as an
  equality, ``H_J v' = −e H_J v``; a hypothesis that needs a pulling impulse (some ``p_i < 0``)
  is rejected; stages repeat until no contact approaches. Every feasible sequence is followed;
  the distinct end states are the outcomes.

Energy of Newton/Moreau (proved in :func:`derivations.impulse_ratio.moreau_energy_proof`):
``T⁺ − T⁻ = ½ pᵀ(H v⁺ + H v⁻)``, and complementarity gives ``p_i(H_i v⁺ + e H_i v⁻) = 0``, so
``T⁺ − T⁻ = ½(1 − e) pᵀ H v⁻``: **for e = 1 Newton/Moreau conserves kinetic energy exactly**
(whatever the number of contacts), and for ``e < 1`` it dissipates when the contacts with
``p_i > 0`` approach. So the sec. 3.2 state ``[−1/3, 2/3, 2/3]`` conserves energy; the paper's
"not acceptable" is qualitative, not energetic, and eq. 12's "advantage ... ensures the
energetic balance contrary to both aforementioned cases" does not hold against Newton at e = 1.
Likewise Poisson with one coefficient: ``T⁺ − T⁻ = −½(1 − e²) p_cᵀ W p_c ≤ 0``
(:func:`derivations.impulse_ratio.poisson_energy_proof`).

Examples
--------
Sec. 3.2, the 3-ball chain (unit masses, ``q̇⁻ = (1, 0, 0)``, ``e = 1``):

>>> chain = ("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
>>> r = newton_moreau(*chain, 1)
>>> r.velocity.T, r.impulses.T, r.energy_after - r.energy_before
(Matrix([[-1/3, 2/3, 2/3]]), Matrix([[4/3, 2/3]]), 0)
>>> poisson(*chain, 1).velocity.T
Matrix([[-1/3, 2/3, 2/3]])
>>> [o.velocity.T for o in han_gilmore(*chain, 1).outcomes]
[Matrix([[-1/3, 2/3, 2/3]]), Matrix([[0, 0, 1]])]

References
----------
Acary & Taha, eqs. 7–12, 15–16 and sec. 3.2; Moreau's complementarity form (eq. 10);
Glocker & Pfeiffer (1995) for the expansion phase; Han & Gilmore (1993).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy as sp

from ..errors import DomainError, ImpactInputError, NonTermination
from ..mechanics import check_gradients, check_mass_matrix, check_velocity
from ..numbers import is_exact, to_exact
from .delassus import ExactLinearAlgebra, exact_data, sign_of, tidy
from .impulse_ratio import Violation, energy_balance_along
from .reflection import check_restitution

__all__ = [
    "MAX_ENUMERATED_CONTACTS",
    "ClassicalResult",
    "solve_lcp",
    "newton_moreau",
    "poisson",
    "energetic",
    "HanGilmoreOutcome",
    "HanGilmoreResult",
    "han_gilmore",
]

#: largest number of contacts whose LCP is solved by enumerating all 2^k active sets
MAX_ENUMERATED_CONTACTS = 10


@dataclass
class ClassicalResult:
    """The answer of one classical law.

    Attributes
    ----------
    law : the law's CLI name
    impulses, velocity : ``p`` (k) and ``v⁺`` (n); exact SymPy for exact input, floats otherwise
    exact : whether the numbers are exact
    valid : no violated condition
    violations : list of :class:`~impactsym.laws.impulse_ratio.Violation`
    energy_before, energy_after : ``T⁻``, ``T⁺``
    unique_impulse : whether ``p`` is unique (``v⁺`` always is for the LCP laws)
    other_impulses : further solutions ``p`` when not unique
    notes : what the law did (method, phases, choices)
    details : law-specific data (compression impulse, direction, ...)
    """

    law: str
    impulses: Any
    velocity: Any
    exact: bool
    valid: bool
    violations: list = field(default_factory=list)
    energy_before: Any = None
    energy_after: Any = None
    unique_impulse: bool = True
    other_impulses: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    details: dict = field(default_factory=dict)


# --------------------------------------------------------------------------------------- input


def _checked(M, H, v, e, *, vector_e=False):
    exact = is_exact(M, H, v) and (is_exact(list(e)) if isinstance(e, (list, tuple)) else is_exact(e))
    Mx = check_mass_matrix(M, exact=exact)
    n = Mx.shape[0]
    Hx = check_gradients(H, n, exact=exact)
    vx = check_velocity(v, n, exact=exact)
    k = Hx.shape[0]
    if isinstance(e, str) and "," in e:
        e = [x for x in e.split(",")]
    if isinstance(e, (list, tuple, np.ndarray)) and not isinstance(e, str):
        if not vector_e:
            raise ImpactInputError("restitution", "this law takes one coefficient, got a list")
        e = list(e)
        if len(e) != k:
            raise ImpactInputError("restitution", f"expected 1 or {k} coefficients (one per closed contact), got {len(e)}")
        ex = [check_restitution(x, exact=exact) for x in e]
    else:
        ex = check_restitution(e, exact=exact)
        ex = [ex] * k if vector_e else ex
    return exact, Mx, Hx, vx, ex


class _Scene:
    """Exact data of a checked scene: W, w = H v, M⁻¹Hᵀ, T⁻, in one arithmetic."""

    def __init__(self, Mx, Hx, vx, restitution=()):
        # an irrational restitution (sqrt(2)/2) takes the SymPy arithmetic, as irrational M, H, v do
        es = list(restitution) if isinstance(restitution, (list, tuple)) else [restitution]
        es = [x for x in es if isinstance(x, sp.Basic)]
        self.kind, mats = exact_data(Mx, Hx, vx, *([sp.Matrix(es)] if es else []))
        self.M, self.H, self.v = mats[:3]
        self.la = ExactLinearAlgebra(self.kind)
        Ht = self.H.T if self.kind == "sympy" else self.H.transpose()
        self.MinvHt = self.M.LUsolve(Ht) if self.kind == "sympy" else self.M.solve(Ht)
        self.W = self.H * self.MinvHt
        if self.kind == "sympy":
            self.W = self.W.applyfunc(lambda x: tidy(x))
        self.k = Hx.shape[0]
        self.n = Mx.shape[0]
        self.w = self.H * self.v
        vt = self.v.T if self.kind == "sympy" else self.v.transpose()
        self.T = (vt * self.M * self.v)[0, 0] / 2

    def scalar(self, x):
        if self.kind == "sympy":
            return sp.sympify(x)
        return self.la.column([x])[0, 0]

    def velocity_after(self, p):
        return self.v + self.MinvHt * p

    def energy(self, v):
        vt = v.T if self.kind == "sympy" else v.transpose()
        return (vt * self.M * v)[0, 0] / 2


# ------------------------------------------------------------------------------------------ LCP


def _lcp_enumerate(sc: _Scene, q):
    """All basic solutions of ``0 ≤ W p + q ⊥ p ≥ 0`` (``q`` a column in ``sc``'s arithmetic)."""
    la, W, k = sc.la, sc.W, sc.k
    sols = []
    for size in range(k + 1):
        for J in itertools.combinations(range(k), size):
            J = list(J)
            WJJ = la.extract(W, J, J)
            qJ = la.extract(q, J, [0])
            pJ = la.solve(WJJ, -qJ) if J else la.zeros(0, 1)
            if pJ is None:
                continue
            if any(sign_of(pJ[i, 0]) < 0 for i in range(len(J))):
                continue
            p = la.zeros(k, 1)
            for i, j in enumerate(J):
                p[j, 0] = pJ[i, 0]
            y = W * p + q
            if sc.kind == "sympy":
                y = y.applyfunc(lambda x: tidy(x))
            if any(sign_of(y[i, 0]) < 0 for i in range(k) if i not in J):
                continue
            if not any(_equal(p, s, k) for s in sols):
                sols.append(p)
    return sols


def _equal(p, s, k):
    return all(sign_of(p[i, 0] - s[i, 0]) == 0 for i in range(k))


def _lcp_nnls(sc: _Scene, Mx, Hx, vx, q_factor, q):
    """k > MAX_ENUMERATED_CONTACTS: NNLS in floats, then the active set re-solved exactly."""
    Mf, Hf = (np.array(x.tolist(), dtype=float) for x in (Mx, Hx))
    vf = np.array(vx.tolist(), dtype=float).reshape(-1)
    R = np.linalg.cholesky(Mf)
    G = np.linalg.solve(R, Hf.T)
    c = q_factor * (R.T @ vf)
    from scipy.optimize import nnls  # imported here: scipy.optimize costs 0.3-0.5 s and only the float LCP path needs it

    pf, _ = nnls(G, -c, maxiter=50 * max(sc.k, 10))
    support = [i for i in range(sc.k) if pf[i] > 0]
    la = sc.la
    WJJ = la.extract(sc.W, support, support)
    pJ = la.solve(WJJ, -la.extract(q, support, [0])) if support else la.zeros(0, 1)
    if pJ is not None:
        p = la.zeros(sc.k, 1)
        for i, j in enumerate(support):
            p[j, 0] = pJ[i, 0]
        y = sc.W * p + q
        if all(sign_of(p[i, 0]) >= 0 for i in range(sc.k)) and all(sign_of(y[i, 0]) >= 0 for i in range(sc.k)):
            return [p]
    raise NonTermination("LCP: the active set found by non-negative least squares could not be certified "
                         f"exactly (k = {sc.k} > MAX_ENUMERATED_CONTACTS = {MAX_ENUMERATED_CONTACTS})")


def solve_lcp(W, q):
    """Every basic solution ``p`` of ``0 ≤ W p + q ⊥ p ≥ 0`` by active-set enumeration (exact).

    Parameters
    ----------
    W : square matrix (exact entries), q : vector (exact entries)

    Returns
    -------
    list of sympy.Matrix (columns), each a solution; several when the solution is not unique.

    >>> solve_lcp(sp.Matrix([[2, -1], [-1, 2]]), sp.Matrix([-2, 0]))
    [Matrix([
    [4/3],
    [2/3]])]
    >>> solve_lcp(sp.Matrix([[1, 1], [1, 1]]), sp.Matrix([-1, -1]))
    [Matrix([
    [1],
    [0]]), Matrix([
    [0],
    [1]])]
    """
    kind, (Wq, qq) = exact_data(sp.Matrix(W), sp.Matrix(q))
    sc = _Scene.__new__(_Scene)
    sc.kind, sc.la, sc.W, sc.k = kind, ExactLinearAlgebra(kind), Wq, Wq.rows if kind == "sympy" else Wq.nrows()
    return [sc.la.to_sympy(p) for p in _lcp_enumerate(sc, qq)]


def _lcp(sc, Mx, Hx, vx, factor):
    """Solutions of ``0 ≤ W p + factor·H v ⊥ p ≥ 0``, with a note on the method."""
    q = sc.w * sc.scalar(factor)
    if sc.k <= MAX_ENUMERATED_CONTACTS:
        return _lcp_enumerate(sc, q), f"exact active-set enumeration (k = {sc.k} <= {MAX_ENUMERATED_CONTACTS})"
    return (_lcp_nnls(sc, Mx, Hx, vx, float(sp.N(sp.sympify(factor), 17)), q),
            "non-negative least squares, active set re-solved and certified exactly")


def _uniqueness(sc, sols, y_of):
    """(unique, reason). Several basic solutions: not unique. One: unique iff the rows of H on the
    contacts with zero post-impact complementarity slack are independent or no feasible move exists."""
    if len(sols) > 1:
        return False, f"{len(sols)} basic solutions (rows of H dependent on the active contacts); v+ is unique"
    p = sols[0]
    y = y_of(p)
    T = [i for i in range(sc.k) if sign_of(y[i, 0]) == 0]
    if not T:
        return True, "unique"
    HT = sc.la.extract(sc.H, T, list(range(sc.n)))
    if sc.la.rank(HT) == len(T):
        return True, "unique (rows of H on the active contacts are independent)"
    return False, ("rows of H on the contacts with zero slack are dependent: impulses may be shifted along "
                   "the null space of H^T without changing v+ (non-unique unless p >= 0 pins them)")


def _finish(law, exact, sc, p, extra_violations=(), notes=(), details=None, unique=True, others=()):
    vplus = sc.velocity_after(p)
    Tplus = sc.energy(vplus)
    violations = list(extra_violations)
    Hv = sc.H * vplus
    for j in range(sc.k):
        if sign_of(p[j, 0]) < 0:
            violations.append(Violation("negative-impulse", f"negative-impulse: p_{j + 1} < 0", j + 1))
    for j in range(sc.k):
        if sign_of(Hv[j, 0]) < 0:
            violations.append(Violation("penetration", f"penetration: contact {j + 1} has H_{j + 1} v+ = "
                                        f"{_str(sc, Hv[j, 0])} < 0", j + 1))
    if sign_of(Tplus - sc.T) > 0:
        violations.append(Violation("energy-increase", f"energy-increase: T+ = {_str(sc, Tplus)} > T- = {_str(sc, sc.T)}"))
    if exact:
        _verify(law, sc, vplus, p, valid=not violations)
    conv = _values(sc, exact)
    return ClassicalResult(law, conv(p), conv(vplus), exact, not violations, violations, conv(sc.T), conv(Tplus),
                           unique, [conv(o) for o in others], list(notes),
                           {k_: conv(v_) for k_, v_ in (details or {}).items()})


def _verify(law, sc, vplus, p, *, valid):
    """Verify an exact outcome before it is returned (:func:`impactsym.verify.verify_exact`):
    the momentum balance ``M(v⁺ − v) = Hᵀp`` always; when the law labels it valid also
    ``H v⁺ ≥ 0``, ``p ≥ 0`` and ``T⁺ ≤ T⁻`` (the classical laws dissipate)."""
    from ..verify import verify_exact

    verify_exact(law, sc.M, sc.H, sc.v, vplus, p, energy_ratio=None, closed=None if valid else [],
                 impulse_nonnegative=valid, energy_at_most=1 if valid else None)


def _str(sc, x) -> str:
    return str(sc.la.to_sympy(x)) if sc.kind == "rational" else str(tidy(x))


def _values(sc, exact):
    def conv(x):
        if x is None or isinstance(x, (str, list, dict, bool)):
            return x
        s = sc.la.to_sympy(x)
        if sc.kind == "sympy":
            s = s.applyfunc(lambda t: tidy(t)) if isinstance(s, sp.MatrixBase) else tidy(s)
        if exact:
            return s
        if isinstance(s, sp.MatrixBase):
            return np.array([float(t) for t in s], dtype=float)
        return float(s)

    return conv


def _raise_if_invalid(res: ClassicalResult, allow_invalid: bool, law: str):
    if res.violations and not allow_invalid:
        raise DomainError(f"{law} outside its domain: " + "; ".join(v.message for v in res.violations))
    return res


# ------------------------------------------------------------------------------------------ laws


def newton_moreau(mass_matrix, gradients, velocity, restitution=1, *, allow_invalid: bool = False) -> ClassicalResult:
    """Newton's law in Moreau's form (eqs. 9–10): ``0 ≤ H v⁺ + e H v⁻ ⊥ p ≥ 0``.

    Parameters
    ----------
    mass_matrix, gradients, velocity : the scene (``M`` SPD, closed-contact rows ``H``, ``v⁻``)
    restitution : Newton's coefficient ``e ∈ [0, 1]``
    allow_invalid : return a result that violates eq. 8 (possible when a closed contact is
        leaving fast: the LCP only asks ``H v⁺ ≥ −e H v⁻``) instead of raising

    Returns
    -------
    ClassicalResult (``unique_impulse`` False and ``other_impulses`` listed when ``p`` is not unique)

    Examples
    --------
    >>> r = newton_moreau("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1/2")
    >>> r.velocity.T, r.impulses.T
    (Matrix([[0, 1/2, 1/2]]), Matrix([[1, 1/2]]))

    Two identical rows (the same contact given twice): ``p`` is not unique, ``v⁺`` is.

    >>> r = newton_moreau("1,0;0,1", "1,0;1,0", "-1,0", 1)
    >>> r.unique_impulse, r.velocity.T, [list(p) for p in [r.impulses] + r.other_impulses]
    (False, Matrix([[1, 0]]), [[2, 0], [0, 2]])
    """
    exact, Mx, Hx, vx, ex = _checked(mass_matrix, gradients, velocity, restitution)
    sc = _Scene(Mx, Hx, vx, ex)
    factor = 1 + (ex if exact else to_exact(ex))
    sols, method = _lcp(sc, Mx, Hx, vx, factor)
    q = sc.w * sc.scalar(factor)
    unique, why = _uniqueness(sc, sols, lambda p: sc.W * p + q)
    notes = [f"LCP 0 <= W p + (1+e) H v- _|_ p >= 0 solved by {method}", f"impulse: {why}"]
    res = _finish("newton", exact, sc, sols[0], notes=notes, unique=unique, others=sols[1:])
    return _raise_if_invalid(res, allow_invalid, "Newton/Moreau law")


def poisson(mass_matrix, gradients, velocity, restitution=1, *, variant: str = "paper",
            allow_invalid: bool = False) -> ClassicalResult:
    """Poisson's law (eq. 11): compression, then restitution ``p = (1 + e_p) p_c``.

    Parameters
    ----------
    restitution : ``e_p`` in [0, 1], one for all contacts or one per contact (list or ``"a,b"``)
    variant : ``"paper"`` (sec. 3.2: ``p_α = (1 + e_pα) p_cα``) or ``"glocker-pfeiffer"``
        (expansion LCP ``p = (1 + e_p) p_c + λ``, ``0 ≤ H v⁺ ⊥ λ ≥ 0``)

    Examples
    --------
    >>> r = poisson("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1")
    >>> r.details["compression_impulses"].T, r.details["compression_velocity"].T, r.impulses.T
    (Matrix([[2/3, 1/3]]), Matrix([[1/3, 1/3, 1/3]]), Matrix([[4/3, 2/3]]))
    """
    if variant not in ("paper", "glocker-pfeiffer"):
        raise ImpactInputError("variant", f"must be 'paper' or 'glocker-pfeiffer', got {variant!r}")
    exact, Mx, Hx, vx, ex = _checked(mass_matrix, gradients, velocity, restitution, vector_e=True)
    sc = _Scene(Mx, Hx, vx, ex)
    sols, method = _lcp(sc, Mx, Hx, vx, 1)  # compression: 0 <= H v_c _|_ p_c >= 0
    pc = sols[0]
    la = sc.la
    eq = [sc.scalar(x if exact else to_exact(x)) for x in ex]
    p = la.zeros(sc.k, 1)
    for i in range(sc.k):
        p[i, 0] = (1 + eq[i]) * pc[i, 0]
    notes = [f"compression LCP 0 <= H v_c _|_ p_c >= 0 solved by {method}", "restitution p = (1 + e_p) p_c (eq. 11)"]
    if variant == "glocker-pfeiffer":
        q2 = sc.H * sc.velocity_after(p)
        sub = _Scene.__new__(_Scene)
        sub.__dict__.update(sc.__dict__)
        lam = _lcp_enumerate(sub, q2)[0] if sc.k <= MAX_ENUMERATED_CONTACTS else None
        if lam is None:
            raise NonTermination(f"Glocker-Pfeiffer expansion LCP: k = {sc.k} > {MAX_ENUMERATED_CONTACTS}")
        p = p + lam
        notes.append("expansion LCP 0 <= H v+ _|_ lambda >= 0 added (Glocker-Pfeiffer)")
    details = {"compression_impulses": pc, "compression_velocity": sc.velocity_after(pc)}
    res = _finish("poisson", exact, sc, p, notes=notes, details=details, unique=len(sols) == 1, others=[])
    return _raise_if_invalid(res, allow_invalid, "Poisson law")


def energetic(mass_matrix, gradients, velocity, restitution=1, ratios=None, *, allow_invalid: bool = False):
    """The global energetic coefficient alone (eq. 12, ``T⁺ = e T⁻``), with the choice of direction
    stated in the module docstring (elastic Newton/Moreau direction unless ``ratios`` are given).

    Returns a :class:`ClassicalResult` whose ``details`` hold ``direction`` (the impulse direction
    used) and ``delta`` (the discriminant of the quadratic, :mod:`impactsym.laws.impulse_ratio`).

    Examples
    --------
    >>> r = energetic("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1/2")
    >>> r.details["direction"].T, r.impulses.T
    (Matrix([[2, 1]]), Matrix([[1, 1/2]]))
    >>> r.energy_after
    1/4
    """
    exact, Mx, Hx, vx, ex = _checked(mass_matrix, gradients, velocity, restitution)
    k = Hx.shape[0]
    notes = []
    if ratios is not None and len(list(ratios)) > 0 or k == 1:
        from .impulse_ratio import _ratio_vector

        a = _ratio_vector(ratios if ratios is not None else [], k, exact)
        notes.append("direction (1, alpha_12, ...) from the given ratios: this is the impulse-ratio law" if k > 1
                     else "one contact: eq. 12 fixes the impulse")
    else:
        sc = _Scene(Mx, Hx, vx, ex)
        sols, _ = _lcp(sc, Mx, Hx, vx, 2)
        q = sc.w * sc.scalar(2)
        unique, why = _uniqueness(sc, sols, lambda p: sc.W * p + q)
        if not unique:
            raise DomainError("energetic law: eq. 12 is one equation for k impulses and the elastic Newton/Moreau "
                              f"direction used to close it is not unique ({why}); give --ratios")
        d = sols[0]
        if all(sign_of(d[i, 0]) == 0 for i in range(k)):
            raise DomainError("energetic law: the elastic Newton/Moreau impulse vanishes (no contact approaches); "
                              "eq. 12 with no impulse direction is undetermined")
        ds = sc.la.to_sympy(d)
        g = sp.gcd(list(ds)) if sc.kind == "rational" else 1
        ds = (ds / g) if g else ds
        a = list(ds) if exact else [float(x) for x in ds]
        notes.append("eq. 12 alone is under-determined for k >= 2: direction taken from the elastic (e = 1) "
                     "Newton/Moreau impulse, magnitude from T+ = e T-")
    r = energy_balance_along(Mx, Hx, vx, ex, a, exact=exact, allow_invalid=True, law="energetic law")
    sc = _Scene(Mx, Hx, vx, ex)
    conv = _values(sc, exact)
    Tplus = None
    if r.velocity is not None:
        if exact:
            Tplus = tidy((r.velocity.T * sp.Matrix(Mx) * r.velocity)[0, 0] / 2)
        else:
            Tplus = 0.5 * float(r.velocity @ np.asarray(Mx, dtype=float) @ r.velocity)
    res = ClassicalResult("energetic", r.impulses, r.velocity, exact, r.valid, r.violations, conv(sc.T), Tplus,
                          True, [], notes, {"direction": sp.Matrix(a) if exact else np.array(a, dtype=float),
                                            "delta": r.delta})
    return _raise_if_invalid(res, allow_invalid, "energetic law")


# ----------------------------------------------------------------------------------- Han-Gilmore


@dataclass
class HanGilmoreOutcome:
    """One end state of the sequential method: ``velocity``, accumulated ``impulses``, and every
    ``sequence`` of impact stages (each a tuple of 1-based contacts impacting together) reaching it."""

    velocity: Any
    impulses: Any
    sequences: list
    energy_after: Any = None


@dataclass
class HanGilmoreResult:
    """All outcomes of :func:`han_gilmore`; ``unique`` when there is exactly one."""

    outcomes: list
    exact: bool
    energy_before: Any = None
    notes: list = field(default_factory=list)
    unterminated: list = field(default_factory=list)  # stage sequences cut at max_stages

    @property
    def unique(self) -> bool:
        return len(self.outcomes) == 1


def han_gilmore(mass_matrix, gradients, velocity, restitution=1, *, max_stages: int = 50,
                max_outcomes: int = 64, max_nodes: int = 20000) -> HanGilmoreResult:
    """Sequential impacts in the manner of Han & Gilmore (eqs. 15–16), every hypothesis followed.

    At each stage, for every set ``J`` of closed contacts with ``H_i v ≤ 0`` containing an
    approaching one, Newton's law is applied on ``J`` as an equality (``H_J v' = −e H_J v``;
    ``W_JJ`` must be invertible and ``p_J ≥ 0``, else the hypothesis is rejected). A branch ends
    when no contact approaches. With ``e = 1`` (Han & Gilmore's "conservation of kinetic
    energy") every stage conserves ``T`` exactly.

    For the 3-ball chain: ``J = {1, 2}`` (contact 2–3 is grazing, ``H_2 v⁻ = 0``, and joins the
    impact) gives eq. 15, which is the Newton/Moreau solution (its LCP's active set is {1, 2});
    ``J = {1}`` then ``{2}`` (1–2 first, then 2–3) gives eq. 16.

    A branch still approaching after ``max_stages`` stages (e.g. plastic impacts one at a time,
    whose velocities only converge) is cut and reported in ``unterminated``, never dropped
    silently.

    Raises
    ------
    NonTermination
        No branch terminates within ``max_stages``, more than ``max_outcomes`` outcomes arise, or
        more than ``max_nodes`` hypotheses are explored.

    Examples
    --------
    >>> r = han_gilmore("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", 1)
    >>> [(o.velocity.T, o.sequences) for o in r.outcomes]
    [(Matrix([[-1/3, 2/3, 2/3]]), [[(1, 2)]]), (Matrix([[0, 0, 1]]), [[(1,), (2,)]])]
    """
    exact, Mx, Hx, vx, ex = _checked(mass_matrix, gradients, velocity, restitution)
    sc = _Scene(Mx, Hx, vx, ex)
    la = sc.la
    e = sc.scalar(ex if exact else to_exact(ex))
    outcomes: list = []  # (v, p, [sequences])
    unterminated: list = []
    nodes = [0]

    def explore(v, p_total, seq, depth):
        nodes[0] += 1
        if nodes[0] > max_nodes:
            raise NonTermination(f"Han-Gilmore: more than max_nodes = {max_nodes} hypotheses explored")
        w = sc.H * v
        signs = [sign_of(w[i, 0]) for i in range(sc.k)]
        if all(s >= 0 for s in signs):
            for o in outcomes:
                if all(sign_of(o[0][i, 0] - v[i, 0]) == 0 for i in range(sc.n)):
                    o[2].append(list(seq))
                    return
            if len(outcomes) >= max_outcomes:
                raise NonTermination(f"Han-Gilmore: more than max_outcomes = {max_outcomes} outcomes")
            outcomes.append((v, p_total, [list(seq)]))
            return
        if depth >= max_stages:
            unterminated.append(list(seq))
            return
        candidates = [i for i in range(sc.k) if signs[i] <= 0]
        for size in range(len(candidates), 0, -1):  # the simultaneous hypothesis first
            for J in itertools.combinations(candidates, size):
                if not any(signs[i] < 0 for i in J):
                    continue
                J = list(J)
                WJJ = la.extract(sc.W, J, J)
                rhs = la.extract(w, J, [0]) * (-(1 + e))
                pJ = la.solve(WJJ, rhs)
                if pJ is None or any(sign_of(pJ[i, 0]) < 0 for i in range(len(J))):
                    continue
                p = la.zeros(sc.k, 1)
                for i, j in enumerate(J):
                    p[j, 0] = pJ[i, 0]
                v2 = v + sc.MinvHt * p
                if sc.kind == "sympy":
                    v2 = v2.applyfunc(lambda x: tidy(x))
                explore(v2, p_total + p, seq + [tuple(j + 1 for j in J)], depth + 1)

    explore(sc.v, la.zeros(sc.k, 1), [], 0)
    if not outcomes:
        raise NonTermination(f"Han-Gilmore: no sequence of impacts ends within max_stages = {max_stages} stages")
    if exact:
        for v, p, _ in outcomes:
            _verify("han-gilmore", sc, v, p, valid=True)
    conv = _values(sc, exact)
    outs = [HanGilmoreOutcome(conv(v), conv(p), seqs, conv(sc.energy(v))) for v, p, seqs in outcomes]
    notes = ["stages: Newton's law as an equality on every set J of closed contacts with H_i v <= 0 containing "
             "an approaching one; hypotheses needing p_J < 0 or singular W_JJ rejected"]
    if unterminated:
        notes.append(f"{len(unterminated)} sequence(s) still approaching after max_stages = {max_stages} stages "
                     "(cut; see unterminated)")
    return HanGilmoreResult(outs, exact, conv(sc.T), notes, unterminated)
