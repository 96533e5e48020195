"""The physical root of the impulse-ratio quadratic (Acary & Taha eq. 38), as a float kernel,
in a cancellation-free form proved equal to the textbook one.

:func:`derivations.impulse_ratio.general_quadratic` reduces the impulse-ratio law of any scene to
``A p₁² + B p₁ + C = 0`` with ``A > 0`` (a kinetic norm), ``B = aᵀH v⁻`` (``< 0`` when the impact
is approaching along ``a``) and ``C = (1 − e) T⁻ ≥ 0``. SymPy solves this quadratic here; the root
kept is the ``+`` branch ``(−B + √D)/(2A)`` (proved to be the physical one in
:func:`derivations.impulse_ratio.physical_root_proof`), the other is returned too.

Naive forms (the quadratic formula, as SymPy's ``solve`` gives it) lose digits:

* the partner root ``(−B − √D)/(2A)`` when ``4AC ≪ B²`` and ``B < 0`` (``|B| − √D`` cancels,
  e.g. ``e → 1``); the physical root when ``B > 0``;

The stable forms (the product-of-roots trick, ``p₁ p₂ = C/A``): with ``q = (−B + σ√D)/2``, ``σ = 1``
for ``B < 0`` and ``−1`` otherwise,
whose two terms never cancel, the roots are ``q/A`` and ``C/q``. The equivalence is proved by
eliminating ``C`` in favour of ``r = √D`` (``C = (B² − r²)/(4A)``), after which both sides are
rational in ``A, B, r`` and their difference cancels to 0, branch by branch.

What stays ill-conditioned by nature: ``D = B² − 4AC`` itself as ``Δ → 0⁺`` (the root's condition
number w.r.t. ``B`` and ``C`` grows like ``B²/D``); the reference module reports it.

Examples
--------
>>> [p["proven"] for p in stable_form_proofs()]
[True, True]
>>> ks = kernels(); [k.name for k in ks]
['impulse_ratio_root', 'impulse_ratio_root_naive']
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import sympy as sp

from .memo import simplify
from .rational_zero import is_zero, is_zero_algebraic

from .codegen import ScalarKernel, render_family

from impactsym.errors import DerivationError

__all__ = ["coefficients", "naive_roots", "stable_roots", "stable_form_proofs", "kernels", "generate"]


def coefficients():
    """The symbols ``A, B, C`` of ``A p₁² + B p₁ + C = 0`` (as real symbols; no sign assumed)."""
    return sp.symbols("A B C", real=True)


@lru_cache(maxsize=None)
def naive_roots():
    """``(physical, partner)`` roots as SymPy's ``solve`` gives them, identified by the sign of √D
    (derived once per process: the proofs and the naive kernel both use them)."""
    A, B, C = coefficients()
    p = sp.Symbol("p_1")
    roots = sp.solve(A * p**2 + B * p + C, p)
    D = B**2 - 4 * A * C
    plus = [r for r in roots if is_zero(r - (-B + sp.sqrt(D)) / (2 * A))]
    minus = [r for r in roots if is_zero(r - (-B - sp.sqrt(D)) / (2 * A))]
    if not (len(plus) == 1 and len(minus) == 1):
        raise DerivationError(roots)
    return plus[0], minus[0]


def stable_roots():
    """``(physical, partner)`` by the product-of-roots trick, branch on the sign of ``B``.

    ``q = (−B + σ√D)/2`` with ``σ = 1`` for ``B < 0`` and ``σ = −1`` otherwise: the two terms of
    ``q`` have the same sign, and ``q ≠ 0`` unless ``B = C = 0``. The roots are ``q/A`` and
    ``C/q``; both are finite on every branch, so a vectorized evaluation of both branches
    (``numpy.select``) divides by zero nowhere.
    """
    A, B, C = coefficients()
    sigma = sp.Piecewise((1, B < 0), (-1, True))
    q = (-B + sigma * sp.sqrt(B**2 - 4 * A * C)) / 2
    physical = sp.Piecewise((q / A, B < 0), (C / q, True))
    partner = sp.Piecewise((C / q, B < 0), (q / A, True))
    return physical, partner


def stable_form_proofs() -> list[dict]:
    """Prove stable == naive for both roots on both branches (``r = √D > 0`` eliminates ``C``)."""
    A, B, C = coefficients()
    r = sp.Symbol("r", positive=True)
    elim = {C: (B**2 - r**2) / (4 * A)}
    naive = naive_roots()
    out = []
    for label, nv, st in zip(("physical root", "partner root"), naive, stable_roots()):
        ok = True
        steps = []
        for cond, sigma, expr in ((B < 0, 1, st.args[0][0]), (B >= 0, -1, st.args[1][0])):
            expr = expr.replace(lambda x: isinstance(x, sp.Piecewise), lambda x: sp.Integer(sigma))
            diff = (expr - nv).subs(elim)
            diff = diff.subs(sp.sqrt(B**2 - 4 * A * (B**2 - r**2) / (4 * A)), r)
            # 0 at once when the exact zero test proves it (what cancel(expand(simplify(.))) gives then)
            diff = sp.Integer(0) if is_zero_algebraic(diff) else sp.cancel(sp.expand(simplify(diff)))
            ok &= diff == 0
            steps.append(f"branch {cond}: stable - naive with C = (B^2 - r^2)/(4A), sqrt(D) = r cancels to {diff}")
        out.append({"kernel": "impulse_ratio_root", "output": label, "proven": bool(ok),
                    "method": "elimination of C by r = sqrt(D), then cancel (rational in A, B, r)",
                    "steps": steps})
    return out


_DOC = """Roots of A p^2 + B p + C = 0 for the impulse-ratio law (Acary & Taha eq. 38): the physical
p1 = (-B + sqrt(D))/(2A) and its partner (-B - sqrt(D))/(2A), D = B^2 - 4AC.
"""


def kernels() -> list:
    A, B, C = coefficients()
    for p in stable_form_proofs():
        if not (p["proven"]):
            raise DerivationError(p)
    stable = ScalarKernel(
        "impulse_ratio_root", [A, B, C], list(stable_roots()), ["p1", "p1_partner"],
        _DOC + "Stable form: q = (-B + s sqrt(D))/2, s = 1 if B < 0 else -1; roots q/A and C/q (no cancellation).",
    )
    naive = ScalarKernel(
        "impulse_ratio_root_naive", [A, B, C], list(naive_roots()), ["p1", "p1_partner"],
        _DOC + "Naive form (the quadratic formula), kept for comparison with impulse_ratio_root.",
    )
    return [stable, naive]


MODULE_DOC = """The physical root of the impulse-ratio quadratic A p1^2 + B p1 + C = 0 (Acary & Taha eq. 38),
stable (product-of-roots) and naive (quadratic formula) forms.
"""


def generate(outdir) -> list[Path]:
    """Write ``impulse_ratio_root.py`` into ``outdir``."""
    path = Path(outdir) / "impulse_ratio_root.py"
    path.write_text(render_family("impulse_ratio_root", "impulse_ratio_root", MODULE_DOC, kernels()))
    return [path]
