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

__all__ = ["QuadraticLaw", "general_quadratic", "physical_root_proof"]


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


def general_quadratic(M, H, v, e, alphas) -> QuadraticLaw:
    """Derive the quadratic in ``p₁`` for given (numeric or symbolic) ``M``, ``H``, ``v⁻``, ``e``, ratios.

    Parameters
    ----------
    M : sympy.Matrix (n×n), H : sympy.Matrix (k×n), v : sympy.Matrix (n×1)
    e : energetic coefficient (symbol or number)
    alphas : sequence of k−1 ratios ``α₁ⱼ = p_j / p_1``
    """
    M, H, v = sp.Matrix(M), sp.Matrix(H), sp.Matrix(v)
    if len(alphas) != H.rows - 1:
        raise ValueError(f"alphas: expected {H.rows - 1} ratios for {H.rows} contacts, got {len(alphas)}")
    a = sp.Matrix([1, *alphas])
    p1 = sp.Symbol("p_1")
    r = H.T * a
    w = M.LUsolve(r)
    vplus_of_p1 = v + p1 * w
    T_minus = (v.T * M * v)[0, 0] / 2
    balance = sp.expand((vplus_of_p1.T * M * vplus_of_p1)[0, 0] / 2 - e * T_minus)
    poly = sp.Poly(balance, p1)
    A, B, C = (sp.simplify(poly.coeff_monomial(p1**k)) for k in (2, 1, 0))
    # identification with the closed forms stated in the docstring (checked, not assumed)
    assert sp.simplify(A - (r.T * w)[0, 0] / 2) == 0
    assert sp.simplify(B - (a.T * H * v)[0, 0]) == 0
    assert sp.simplify(C - (1 - e) * T_minus) == 0
    D = sp.expand(B**2 - 4 * A * C)
    root = (-B + sp.sqrt(D)) / (2 * A)
    other = (-B - sp.sqrt(D)) / (2 * A)
    return QuadraticLaw(A, B, C, D, a, root, other, root * a, v + root * w)


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
    at_elastic_plus = sp.simplify(plus.subs(C, 0))
    at_elastic_minus = sp.simplify(minus.subs(C, 0))
    q = (-B + sp.sqrt(D)) / 2
    pair_ok = sp.simplify(q / A - plus) == 0 and sp.simplify(C / q - minus) == 0
    proven = at_elastic_minus == 0 and sp.simplify(at_elastic_plus - Bn / A) == 0 and pair_ok
    return {"plus_at_e1": at_elastic_plus, "minus_at_e1": at_elastic_minus, "stable_pair": pair_ok,
            "proven": bool(proven)}
