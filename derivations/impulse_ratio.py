"""The impulse-ratio law of Acary & Taha (eq. 38), derived in general.

For ``M Δv = Hᵀp`` with ``p = p₁ a``, ``a = (1, α₁₂, α₁₃, ...)`` (ratios against the primary
contact, row 1 of ``H``; ``CONVENTIONS.md``) and the energy balance ``T⁺ = e T⁻`` (eq. 12 read
with ½ on both sides), the post-impact velocity is ``v⁺ = v⁻ + p₁ M⁻¹Hᵀa`` and the balance is a
quadratic in ``p₁``:

    A p₁² + B p₁ + C = 0,   A = ½ aᵀ H M⁻¹ Hᵀ a,   B = aᵀ H v⁻,   C = (1 − e) T⁻,

with discriminant ``D = B² − 4AC``. The physical root is ``p₁ = (−B + √D)/(2A)``: at ``e = 1``
the roots are ``0`` (no impact, discarded) and ``−B/A``, and the ``+`` branch is the continuation
of the non-trivial root (proved in :func:`physical_root_proof`). For ``B < 0`` (approaching along
``a``) it is evaluated without cancellation as ``q/A`` with ``q = (−B + √D)/2``; its partner root
is ``C/q``.

The paper's ``Δ`` is ``D`` normalized by the pre-impact data (for the unit-speed chain, ``B = −1``).

Examples
--------
>>> import sympy as sp
>>> al, e = sp.symbols("alpha e", positive=True)
>>> law = general_quadratic(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([1, 0, 0]), e, [al])
>>> sp.factor(law.A), law.B, sp.factor(law.C)
(alpha**2 - alpha + 1, -1, -(e - 1)/2)
>>> sp.expand(law.D)
2*alpha**2*e - 2*alpha**2 - 2*alpha*e + 2*alpha + 2*e - 1
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .memo import simplify
from .rational_zero import is_zero

from impactsym.errors import DerivationError

__all__ = ["QuadraticLaw", "general_quadratic", "on_energy_line", "physical_root_proof", "general_coefficients_proof", "moreau_energy_proof", "poisson_energy_proof"]


@dataclass
class QuadraticLaw:
    """The impulse-ratio law for one scene, symbolically: coefficients, discriminant and solution."""

    A: sp.Expr
    B: sp.Expr
    C: sp.Expr
    D: sp.Expr  # discriminant B^2 - 4AC
    ratios: sp.Matrix  # a = (1, alpha_12, ...)
    p1: sp.Expr  # the physical root (-B + sqrt(D)) / (2A)
    p1_other: sp.Expr  # the discarded root (-B - sqrt(D)) / (2A)
    p: sp.Matrix  # p1 * a
    vplus: sp.Matrix  # v + M^-1 H^T p


def general_quadratic(M, H, v, e, alphas, *, simplified: bool = True) -> QuadraticLaw:
    """Derive the quadratic in ``p₁`` for given (numeric or symbolic) ``M``, ``H``, ``v⁻``, ``e``, ratios.

    Parameters
    ----------
    M : sympy.Matrix (n×n), H : sympy.Matrix (k×n), v : sympy.Matrix (n×1)
    e : energetic coefficient (symbol or number)
    alphas : sequence of k−1 ratios ``α₁ⱼ = p_j / p_1``
    simplified : ``A``, ``B``, ``C`` simplified (default); ``False`` leaves them as the expanded
        balance's coefficients (the same values, checked the same way), for a caller that only
        decides identities of the state (an exact zero test or a certified point needs no form)
    """
    M, H, v = sp.Matrix(M), sp.Matrix(H), sp.Matrix(v)
    if len(alphas) != H.rows - 1:
        raise ValueError(f"alphas: expected {H.rows - 1} ratios for {H.rows} contacts, got {len(alphas)}")
    a = sp.Matrix([1, *alphas])
    e = sp.sympify(e)
    if all(x.is_Rational for x in (*M, *H, *v, *a, e)):
        return _rational_quadratic(M, H, v, e, a)
    p1 = sp.Symbol("p_1")
    r = H.T * a
    w = M.LUsolve(r)
    vplus_of_p1 = v + p1 * w
    T_minus = (v.T * M * v)[0, 0] / 2
    balance = sp.expand((vplus_of_p1.T * M * vplus_of_p1)[0, 0] / 2 - e * T_minus)
    A, B, C = ((simplify if simplified else sp.sympify)(x) for x in _p1_coefficients(balance, p1))
    # identification with the closed forms stated in the docstring (checked, not assumed)
    if not (is_zero(A - (r.T * w)[0, 0] / 2)):
        raise DerivationError('derivation check failed: sp.simplify(A - (r.T * w)[0, 0] / 2) == 0')
    if not (is_zero(B - (a.T * H * v)[0, 0])):
        raise DerivationError('derivation check failed: sp.simplify(B - (a.T * H * v)[0, 0]) == 0')
    if not (is_zero(C - (1 - e) * T_minus)):
        raise DerivationError('derivation check failed: sp.simplify(C - (1 - e) * T_minus) == 0')
    return _solved(A, B, C, sp.expand(B**2 - 4 * A * C), a, v, w)


def _solved(A, B, C, D, a, v, w) -> QuadraticLaw:
    """The law from its coefficients and discriminant: both roots, ``p = p₁a``, ``v⁺ = v⁻ + p₁w``."""
    root = (-B + sp.sqrt(D)) / (2 * A)
    other = (-B - sp.sqrt(D)) / (2 * A)
    return QuadraticLaw(A, B, C, D, a, root, other, root * a, v + root * w)


def _rational_quadratic(M, H, v, e, a) -> QuadraticLaw:
    """:func:`general_quadratic` for rational data: the same derivation in ``QQ[p₁]``.

    ``v⁺(p₁) = v⁻ + p₁ M⁻¹Hᵀa`` (``M⁻¹Hᵀa`` by exact elimination over ``QQ``) and the balance
    ``T(v⁺(p₁)) − e T⁻`` are built as polynomials of the ring ``QQ[p₁]`` (python-flint's rationals
    underneath), whose product is expanded as it is made: the same coefficients ``A``, ``B``, ``C``
    as the expanded SymPy balance (exact rationals have one form), without building and expanding
    products of SymPy ``Rational``s and ``p₁`` (3-ball chains at float-converted data, whose
    denominators are powers of 2 up to 2¹⁰⁷⁴: 37 -> 27 ms each, most of the rest SymPy's ``√D``).
    The same identifications are checked.

    >>> law = general_quadratic(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([1, 0, 0]), 1,
    ...                         [sp.Rational(19, 20)])
    >>> law.A, law.B, law.C, law.p.T
    (381/400, -1, 0, Matrix([[400/381, 380/381]]))
    """
    from sympy.matrices.exceptions import NonInvertibleMatrixError
    from sympy.polys.matrices import DomainMatrix
    from sympy.polys.matrices.exceptions import DMNonInvertibleMatrixError

    QQ = sp.QQ
    dm = lambda X: DomainMatrix.from_list_sympy(X.rows, X.cols, X.tolist()).convert_to(QQ)  # noqa: E731
    Mq, Hq, vq, aq = dm(M), dm(H), dm(v), dm(a)
    eq = QQ.from_sympy(e)
    rq = Hq.transpose() * aq
    try:
        wq = Mq.lu_solve(rq)
    except DMNonInvertibleMatrixError as exc:  # the error the SymPy route's M.LUsolve raises
        raise NonInvertibleMatrixError(str(exc)) from None
    R, P = sp.ring("p_1", QQ)
    n = M.rows
    Mr, vr, wr = Mq.to_list(), [x[0] for x in vq.to_list()], [x[0] for x in wq.to_list()]
    vp = [vr[i] + P * wr[i] for i in range(n)]
    T_minus = sum((Mr[i][j] * vr[i] * vr[j] for i in range(n) for j in range(n)), QQ(0)) / 2
    balance = sum((vp[i] * Mr[i][j] * vp[j] for i in range(n) for j in range(n) if Mr[i][j]), R(0)) / 2 - eq * T_minus
    A, B, C = (balance.coeff(P**k) if k else balance.coeff(1) for k in (2, 1, 0))
    if A != sum((rr[0] * ww[0] for rr, ww in zip(rq.to_list(), wq.to_list())), QQ(0)) / 2:
        raise DerivationError('derivation check failed: sp.simplify(A - (r.T * w)[0, 0] / 2) == 0')
    if B != (aq.transpose() * Hq * vq).to_list()[0][0]:
        raise DerivationError('derivation check failed: sp.simplify(B - (a.T * H * v)[0, 0]) == 0')
    if C != (1 - eq) * T_minus:
        raise DerivationError('derivation check failed: sp.simplify(C - (1 - e) * T_minus) == 0')
    return _solved(*(QQ.to_sympy(x) for x in (A, B, C, B**2 - 4 * A * C)), a, v, wq.to_Matrix())


def _p1_coefficients(balance, p1):
    """The coefficients of ``p₁²``, ``p₁``, ``1`` in the expanded ``balance``, as
    ``sympy.Poly(balance, p1).coeff_monomial`` gives them.

    Read off the expanded sum term by term (each term is ``c·p₁ᵏ``, ``c`` free of ``p₁``), which
    spares ``Poly``'s construction of a coefficient domain (about 10 ms a scene, half of the
    derivation's time). ``Poly`` writes a coefficient as the polynomial of its domain, i.e. as the
    expanded sum of its terms, exactly this sum, unless the domain is a fraction field (a symbol in
    a denominator: ``(α² − α + 1)/m`` for symbolic masses, which it puts over one denominator) or
    a term is not a monomial in ``p₁`` of degree ≤ 2, or a Float occurs (domain ``RR``): then
    ``Poly`` itself is asked.

    >>> p, a, m = sp.symbols("p_1 alpha m")
    >>> _p1_coefficients(sp.expand(a * p**2 / 2 + p * (a - 1) + 3), p)
    (alpha/2, alpha - 1, 3)
    >>> _p1_coefficients(sp.expand((a**2 - a + 1) * p**2 / m - p), p)
    ((alpha**2 - alpha + 1)/m, -1, 0)
    """
    # a Float makes Poly's domain RR (its own precision): Poly decides then
    parts: dict | None = None if balance.has(sp.Float) else {0: [], 1: [], 2: []}
    for term in sp.Add.make_args(balance) if parts is not None else ():
        c, mono = term.as_independent(p1, as_Add=False)
        k = 0 if mono == 1 else 1 if mono == p1 else 2 if mono == p1**2 else None
        if k is None or c.has(p1) or any(d.free_symbols for d in (sp.fraction(f)[1] for f in sp.Mul.make_args(c))):
            parts = None
            break
        parts[k].append(c)
    if parts is None:
        poly = sp.Poly(balance, p1)
        return tuple(poly.coeff_monomial(p1**k) for k in (2, 1, 0))
    return tuple(sp.Add(*parts[k]) for k in (2, 1, 0))


def on_energy_line(law: QuadraticLaw, M, v, e) -> QuadraticLaw:
    """Check that ``law`` (from :func:`general_quadratic`) solves the energy line ``T⁺ = e T⁻`` of
    the scene ``M``, ``v⁻`` for the coefficient ``e`` the caller asked for, and return it; raise
    :class:`~impactsym.errors.DerivationError` otherwise.

    Structural, not a re-derivation: :func:`general_quadratic` proves that its ``A``, ``B`` are the
    ``p₁²`` and ``p₁`` coefficients of ``T(v⁻ + p₁M⁻¹Hᵀa)``, so its root lies on the line
    ``T⁺ = e T⁻`` exactly when its constant term is ``C = (1 − e)T⁻`` (with ``T⁻`` computed here
    from ``M`` and ``v⁻``) and its discriminant is ``D = B² − 4AC``; both are decided by the exact
    zero test. A caller runs it before simplifying any closed form of the law, so a law derived
    for another ``e`` is rejected before any printed form is built.

    >>> law = general_quadratic(sp.eye(2), sp.Matrix([[-1, 1]]), sp.Matrix([1, 0]), 1, [])
    >>> on_energy_line(law, sp.eye(2), sp.Matrix([1, 0]), 1).p1
    1
    >>> on_energy_line(law, sp.eye(2), sp.Matrix([1, 0]), sp.Rational(1, 2))
    Traceback (most recent call last):
    ...
    impactsym.errors.DerivationError: the law's constant term C = 0 is not (1 - e)T- = 1/4 for e = 1/2: its root is off the energy line T+ = e T-
    """
    M, v = sp.Matrix(M), sp.Matrix(v)
    T_minus = (v.T * M * v)[0, 0] / 2
    want = (1 - sp.sympify(e)) * T_minus
    if not is_zero(law.C - want):
        raise DerivationError(f"the law's constant term C = {law.C} is not (1 - e)T- = {want} for e = {e}: its root "
                              "is off the energy line T+ = e T-")
    if not is_zero(law.D - (law.B**2 - 4 * law.A * law.C)):
        raise DerivationError(f"the law's discriminant {law.D} is not B^2 - 4AC")
    return law


def physical_root_proof():
    """Prove, for symbolic ``A > 0``, ``B < 0``, that at ``e = 1`` (``C = 0``) the ``+`` root is the
    non-trivial one and the ``−`` root is ``p = 0``; and that ``q/A`` and ``C/q`` with
    ``q = (−B + √D)/2`` are the two roots (the cancellation-free pair).

    >>> physical_root_proof()["proven"]
    True
    """
    A = sp.Symbol("A", positive=True)
    Bn = sp.Symbol("b", positive=True)  # B = -b < 0
    C = sp.Symbol("C", nonnegative=True)
    B = -Bn
    D = B**2 - 4 * A * C
    plus, minus = (-B + sp.sqrt(D)) / (2 * A), (-B - sp.sqrt(D)) / (2 * A)
    at_elastic_plus = simplify(plus.subs(C, 0))
    at_elastic_minus = simplify(minus.subs(C, 0))
    q = (-B + sp.sqrt(D)) / 2
    pair_ok = is_zero(q / A - plus) and is_zero(C / q - minus)
    proven = at_elastic_minus == 0 and is_zero(at_elastic_plus - Bn / A) and pair_ok
    return {"plus_at_e1": at_elastic_plus, "minus_at_e1": at_elastic_minus, "stable_pair": pair_ok,
            "proven": bool(proven)}


def general_coefficients_proof():
    """Prove the coefficients of the quadratic for **every** dimension ``n`` and contact count ``k``.

    Matrices are non-commutative symbols (:mod:`derivations.algebra`): ``M``, ``Mi = M⁻¹``,
    ``H`` (k×n), ``Ht = Hᵀ``, ``v`` (n×1), ``vt = vᵀ``, ``a`` (k×1), ``at = aᵀ``; ``p₁`` and ``e``
    commute. With ``v⁺ = v + p₁ M⁻¹Hᵀa`` (so ``v⁺ᵀ = vᵀ + p₁ aᵀ H M⁻¹``, using ``(M⁻¹)ᵀ = M⁻¹``),
    the rewriting rules are the defining relations ``M M⁻¹ = M⁻¹ M = I`` and the transpose of a
    scalar, ``vᵀHᵀa = aᵀHv``. The claim:

        ½ v⁺ᵀ M v⁺ − e·½ vᵀ M v = A p₁² + B p₁ + C,
        A = ½ aᵀHM⁻¹Hᵀa,  B = aᵀHv,  C = (1 − e)·½ vᵀMv.

    >>> general_coefficients_proof()["proven"]
    True
    """
    from .algebra import nc_symbols, rewrite

    M, Mi, H, Ht, v, vt, a, at = nc_symbols("M Mi H Ht v vt a at")
    p1, e = sp.symbols("p_1 e")
    vplus, vplus_t = v + p1 * Mi * Ht * a, vt + p1 * at * H * Mi
    balance = vplus_t * M * vplus / 2 - e * vt * M * v / 2
    A = at * H * Mi * Ht * a / 2
    B = at * H * v
    C = (1 - e) * vt * M * v / 2
    rules = {M * Mi: 1, Mi * M: 1, vt * Ht * a: at * H * v}
    residual = rewrite(balance - (A * p1**2 + B * p1 + C), rules)
    return {"A": A, "B": B, "C": C, "residual": residual, "proven": residual == 0}


def moreau_energy_proof():
    """Energy of Newton/Moreau's law (eq. 10), for every ``n`` and ``k``.

    1. ``T⁺ − T⁻ = ½ pᵀ H (v⁺ + v⁻)`` for ``v⁺ = v⁻ + M⁻¹Hᵀp`` (non-commutative rewriting, as in
       :func:`general_coefficients_proof`).
    2. Contact by contact, complementarity ``p_i (w⁺_i + e w⁻_i) = 0`` gives
       ``p_i (w⁺_i + w⁻_i) = (1 − e) p_i w⁻_i``; summing, ``T⁺ − T⁻ = ½ (1 − e) pᵀ H v⁻``.

    Hence at ``e = 1`` Newton/Moreau conserves kinetic energy exactly, for any number of contacts,
    and for ``e < 1`` it dissipates as long as the contacts carrying impulse approach.

    >>> r = moreau_energy_proof()
    >>> r["proven"], r["energy_change"]
    (True, '(1 - e)/2 * p^T H v-')
    """
    from .algebra import nc_symbols, rewrite

    M, Mi, H, Ht, v, vt, p, pt = nc_symbols("M Mi H Ht v vt p pt")
    vplus, vplus_t = v + Mi * Ht * p, vt + pt * H * Mi
    change = vplus_t * M * vplus / 2 - vt * M * v / 2
    claim = pt * H * (vplus + v) / 2
    rules = {M * Mi: 1, Mi * M: 1, vt * Ht * p: pt * H * v}
    step1 = rewrite(change - claim, rules) == 0
    # step 2, one contact: w+ = -e w- wherever p_i > 0 (complementarity); where p_i = 0 both sides vanish
    pi, wm, e = sp.symbols("p_i w_minus e")
    wp = -e * wm
    step2 = sp.expand(pi * (wp + wm) - (1 - e) * pi * wm) == 0 and sp.expand((0 * (wp + wm)) - (1 - e) * 0 * wm) == 0
    return {"step1": step1, "step2": step2, "proven": bool(step1 and step2),
            "energy_change": "(1 - e)/2 * p^T H v-"}


def poisson_energy_proof():
    """Energy of Poisson's law with one coefficient ``e`` for all contacts (eq. 11, ``p = (1+e) p_c``),
    for every ``n`` and ``k``.

    The compression impulse ``p_c`` solves ``0 ≤ H v_c ⊥ p_c ≥ 0`` with ``v_c = v⁻ + M⁻¹Hᵀp_c``, so
    ``p_cᵀ H v_c = 0``, i.e. ``p_cᵀHv⁻ = −p_cᵀHM⁻¹Hᵀp_c`` (the rewriting rule). With
    ``v⁺ = v⁻ + (1+e) M⁻¹Hᵀp_c``:

        T⁺ − T⁻ = −½ (1 − e²) p_cᵀ H M⁻¹ Hᵀ p_c  ≤ 0,

    with equality at ``e = 1``. Like Newton/Moreau, this Poisson law never creates energy.

    >>> poisson_energy_proof()["proven"]
    True
    """
    from .algebra import nc_symbols, rewrite

    M, Mi, H, Ht, v, vt, p, pt = nc_symbols("M Mi H Ht v vt p pt")
    e = sp.Symbol("e")
    vplus, vplus_t = v + (1 + e) * Mi * Ht * p, vt + (1 + e) * pt * H * Mi
    change = vplus_t * M * vplus / 2 - vt * M * v / 2
    claim = -(1 - e**2) * pt * H * Mi * Ht * p / 2
    rules = {M * Mi: 1, Mi * M: 1, vt * Ht * p: pt * H * v}
    residual = rewrite(change - claim, rules)
    # complementarity of the compression phase: p_c^T H v = -p_c^T H M^-1 H^T p_c
    residual = rewrite(residual, {pt * H * v: -pt * H * Mi * Ht * p})
    return {"residual": residual, "proven": residual == 0}
