"""Two constraint surfaces: the reduction to a 2-plane, the exact reflection count, the bound.

Seghete & Murphey, sec. III-B (sequential single impacts) and sec. III-C (proof of termination).
Everything below is derived by SymPy from the single-impact map ``G_u = I − 2 w u/(u w)``,
``w = M⁻¹uᵀ`` (sec. II-A, derived in :mod:`derivations.reflection`); nothing is retyped.

Notation (impactsym conventions): gradient rows ``H_A``, ``H_B``; ``w_i = M⁻¹H_iᵀ``;
``s_i = H_i M⁻¹ H_iᵀ > 0``; ``g = H_A M⁻¹ H_Bᵀ``; ``Δ = s_A s_B − g² ≥ 0`` (zero exactly when the
rows are parallel); ``c_i = H_i v`` (approaching when ``c_i < 0``).

Results
-------
1. **Plane reduction** (:func:`plane_reduction`, any dimension, by non-commutative rewriting):
   both reflections fix ``ker H_A ∩ ker H_B`` pointwise, and that subspace is the M-orthogonal
   complement of ``P = span(w_A, w_B)``; both map ``P`` to itself. Validity (``H v ≥ 0``) depends
   only on the ``P``-part of ``v``. So the two-surface problem *in any dimension* is a problem in
   the Euclidean plane ``P`` (with the M inner product).
2. **Frame** (:func:`plane_frame`): in the M-orthonormal frame ``E1 = e_A/|e_A|``, ``E2 = n_A``
   (``e_A`` the edge of the admissible wedge lying in surface A, ``n_A`` the M-normal of A), the
   admissible wedge is ``{0 ≤ θ ≤ β}``, ``G_A`` is the Euclidean reflection ``θ ↦ −θ``, ``G_B`` the
   reflection ``θ ↦ 2β − θ`` and ``G_B G_A`` the rotation by ``2β`` (≡ ``−2φ``), where
   ``cos β = −g/√(s_A s_B) = −cos φ``, ``sin β = √Δ/√(s_A s_B)``: the wedge opening is
   ``β = π − φ`` with ``φ`` the kinetic angle (``impactsym.mechanics.kinetic_angle``). The pre-impact
   velocity has angle ``θ₀ = atan2(c_A √Δ, s_A c_B − g c_A)``.
3. **Exact count** (:func:`reflection_count_derivation`): the sequence that starts with A (only
   possible when ``c_A < 0``) is forced to alternate, and it stops after exactly
   ``m_A = ⌈ψ_A/β⌉`` reflections, ``ψ_A = −θ₀ = atan2(−c_A √Δ, s_A c_B − g c_A) ∈ (0, π)`` (the
   M-angle between ``v`` and the edge ``e_A``). Symmetrically ``m_B = ⌈ψ_B/β⌉`` with A and B swapped.
   A velocity that is already valid needs 0 reflections. Grazing at any step (an iterate exactly on
   an edge, ``ψ/β`` an integer) is valid and stops the sequence; the ceiling handles it exactly.
4. **Exit velocity** (:func:`exit_angle`, :func:`exit_relative_velocity`): after ``m`` reflections
   the angle is ``θ_f = σ(mβ − ψ) + (1 − σ)β/2``, ``σ = (−1)^m``; exactly, with
   ``α = (s_A c_B − g c_A) + c_A√−Δ`` and ``ρ = (−g + √−Δ)²/(s_A s_B) = e^{2iβ}``, the exit is
   ``α_f = α ρ^k`` (m = 2k) or ``conj(α ρ^k)`` (m = 2k+1), read back as ``c_A' = Im α_f/√Δ``,
   ``c_B' = (Re α_f + g c_A')/s_A``, and ``v⁺ = v + W Γ⁻¹ (c' − c)`` (``Γ`` the Gram matrix).
   For rational data ``ρ`` and ``α`` have rational coordinates in ``Q(√−Δ)``: the exit is rational.
5. **The paper's bound** (:func:`paper_bound`): the admissible part of the kinetic-energy sphere is a
   lune of dihedral angle β; its area fraction is ``β/(2π)`` in every dimension (derived for
   n = 2, 3 by integration and for every n by the Gaussian measure), so
   ``N = ⌈S_total/(2S₀)⌉ = ⌈π/β⌉``. It equals the exact maximum of the count over all velocities
   (:func:`bound_versus_count`): never exceeded, attained on an open set of velocities, for every β.

Examples
--------
>>> r = plane_reduction()
>>> r["proven"]
True
>>> f = plane_frame()
>>> f["proven"]
True
>>> c = reflection_count_derivation()
>>> c["proven"], c["count"]
(True, ceiling(psi/beta))
>>> paper_bound()["N"]
ceiling(pi/beta)
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from pathlib import Path

import sympy as sp

from .algebra import nc_symbols, rewrite
from .codegen import ArrayKernel, ScalarKernel, numpy_code, render_family
from .rational_zero import is_zero
from .reflection import G_matrix

from impactsym.errors import DerivationError
from impactsym.exact import certified_sign

__all__ = [
    "plane_reduction",
    "plane_frame",
    "reflection_count_derivation",
    "exit_angle",
    "exit_relative_velocity",
    "exact_exit_relative_velocity",
    "lune_fraction",
    "paper_bound",
    "bound_versus_count",
    "area_step_counterexample",
    "reachable_arc_lengths",
    "paper_example_counts",
    "exit_frame_branches",
    "frame_exit_velocity",
    "frame_exit_steps",
    "kernels",
    "generate",
]

# --------------------------------------------------------------------------- symbols
s_A, s_B, Delta = sp.symbols("s_A s_B Delta", positive=True)
g = sp.Symbol("g", real=True)
c_A, c_B = sp.symbols("c_A c_B", real=True)
beta, psi, theta, phi = sp.symbols("beta psi theta phi", real=True)
m_ = sp.Symbol("m", integer=True, positive=True)

#: s_B eliminated through Δ = s_A s_B − g² (so that radicals simplify): s_B = (Δ + g²)/s_A
S_B_OF_DELTA = (Delta + g**2) / s_A

WA, WB, UA, UB, MM, X, Xt, UAt, UBt = nc_symbols("WA WB UA UB M X Xt UAt UBt")
#: defining relations of the two-surface algebra (each an identity of the actual matrices)
RULES = {UA * WA: s_A, UB * WB: s_B, UA * WB: g, UB * WA: g, MM * WA: UAt, MM * WB: UBt}
RULE_REASONS = {
    "UA*WA -> s_A, UB*WB -> s_B": "definitions s_i = H_i M^-1 H_i^T",
    "UA*WB -> g, UB*WA -> g": "g = H_A M^-1 H_B^T = H_B M^-1 H_A^T (M^-1 symmetric)",
    "M*WA -> UAt, M*WB -> UBt": "definition w_i = M^-1 H_i^T",
    "UA*X -> 0, UB*X -> 0": "X is any vector of ker H_A ∩ ker H_B",
    "Xt*UAt -> 0, Xt*UBt -> 0": "transposes of the previous rule",
}
G_A = G_matrix(WA, UA, s_A, identity=1)
G_B = G_matrix(WB, UB, s_B, identity=1)


def _fresh(obj):
    """``obj`` with its containers and mutable matrices copied (SymPy expressions are immutable)."""
    if isinstance(obj, dict):
        return {k: _fresh(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(_fresh(v) for v in obj)
    if isinstance(obj, (sp.MutableDenseMatrix, sp.MutableSparseMatrix)):
        return obj.copy()
    return obj


def _derived_once(fn):
    """``fn()`` (a derivation from SymPy and this module alone, no argument) derived once per process:
    the module's doctests, the tests, the paper checks and ``kernels()`` ask for the same proofs
    (``plane_frame`` about 0.3 s each time). Each call returns a fresh copy; ``cache_clear``
    (found by ``paper_checks.mutations.clear_caches``) forgets it."""
    cached = lru_cache(maxsize=None)(fn)

    def derived():
        return _fresh(cached())

    derived.__name__, derived.__qualname__, derived.__doc__ = fn.__name__, fn.__qualname__, fn.__doc__
    derived.__module__, derived.__wrapped__ = fn.__module__, fn
    derived.cache_clear = cached.cache_clear
    return derived


def _all_zero(mat) -> bool:
    """``simplify(mat) == zeros``: every entry decided by :func:`derivations.rational_zero.is_zero`
    (the exact tests first, ``simplify`` only where they leave it open)."""
    return all(is_zero(x) for x in mat)


def _coeffs(expr) -> tuple:
    """Coordinates of an element of span(WA, WB) (checked to have no other part)."""
    a, b = expr.coeff(WA), expr.coeff(WB)
    if not (sp.expand(expr - a * WA - b * WB) == 0):
        raise DerivationError(expr)
    return sp.simplify(a), sp.simplify(b)


@_derived_once
def plane_reduction() -> dict:
    """Prove, for every dimension, that the two-surface problem lives in ``P = span(w_A, w_B)``.

    Steps (non-commutative rewriting, :mod:`derivations.algebra`):

    * ``G_A x = x``, ``G_B x = x`` for ``x ∈ ker H_A ∩ ker H_B`` (so every product of them fixes x);
    * ``ker H_A ∩ ker H_B`` is M-orthogonal to ``w_A`` and ``w_B`` (``xᵀ M w_i = (H_i x)ᵀ = 0``), and
      it has dimension n − 2 when ``Δ ≠ 0`` (the rows are independent), so it *is* the
      M-orthogonal complement of ``P``;
    * ``G_i w_j ∈ P``: the 2×2 matrices of ``G_A``, ``G_B`` on ``P`` in the basis ``(w_A, w_B)``;
    * ``H_i (x + a w_A + b w_B) = a H_i w_A + b H_i w_B``: validity depends only on the P-part.

    Returns a dict with ``proven``, the 2×2 matrices ``G_A_P``, ``G_B_P``, the Gram matrix and the
    steps.

    >>> r = plane_reduction()
    >>> r["G_A_P"]
    Matrix([
    [-1, -2*g/s_A],
    [ 0,         1]])
    """
    ker_rules = {**RULES, UA * X: 0, UB * X: 0}
    fixA = rewrite(G_A * X - X, ker_rules)
    fixB = rewrite(G_B * X - X, ker_rules)
    orthA = rewrite(Xt * MM * WA, {MM * WA: UAt, Xt * UAt: 0})
    orthB = rewrite(Xt * MM * WB, {MM * WB: UBt, Xt * UBt: 0})
    a, b = sp.symbols("a b", real=True)
    validity = [rewrite(U * (X + a * WA + b * WB), ker_rules) for U in (UA, UB)]
    imgs = {(i, j): _coeffs(rewrite(G * W, RULES)) for i, G in (("A", G_A), ("B", G_B))
            for j, W in (("A", WA), ("B", WB))}
    GAP = sp.Matrix([[imgs["A", "A"][0], imgs["A", "B"][0]], [imgs["A", "A"][1], imgs["A", "B"][1]]])
    GBP = sp.Matrix([[imgs["B", "A"][0], imgs["B", "B"][0]], [imgs["B", "A"][1], imgs["B", "B"][1]]])
    gram = sp.Matrix([[s_A, g], [g, s_B]])
    # the restricted maps are M-isometries of P and involutions: G^T Γ G = Γ, G^2 = I
    iso = all(sp.simplify(Gp.T * gram * Gp - gram) == sp.zeros(2, 2) for Gp in (GAP, GBP))
    invol = all(sp.simplify(Gp * Gp - sp.eye(2)) == sp.zeros(2, 2) for Gp in (GAP, GBP))
    ok = fixA == 0 and fixB == 0 and orthA == 0 and orthB == 0 and iso and invol and \
        validity == [a * s_A + b * g, a * g + b * s_B]
    steps = [
        f"G_A x - x rewrites (H_A x = H_B x = 0) to {fixA}; G_B x - x to {fixB}",
        f"x^T M w_A rewrites to {orthA}, x^T M w_B to {orthB}: ker H_A ∩ ker H_B ⟂_M P",
        "dim(ker H_A ∩ ker H_B) = n − 2 = dim P^⟂ when the rows are independent (Δ ≠ 0)",
        f"G_A on P in the basis (w_A, w_B): {GAP.tolist()}; G_B: {GBP.tolist()}",
        f"H_A (x + a w_A + b w_B) = {validity[0]}, H_B (...) = {validity[1]}: only the P-part matters",
        f"G^T Γ G = Γ on P (Γ = Gram matrix [[s_A, g], [g, s_B]]): {iso}; G^2 = I on P: {invol}",
    ]
    return {"proven": bool(ok), "G_A_P": GAP, "G_B_P": GBP, "gram": gram, "steps": steps,
            "rules": RULE_REASONS}


def _reflection_across(angle):
    """The Euclidean reflection across the line at ``angle``, as a matrix."""
    return sp.Matrix([[sp.cos(2 * angle), sp.sin(2 * angle)], [sp.sin(2 * angle), -sp.cos(2 * angle)]])


def _rotation(angle):
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


@_derived_once
def plane_frame() -> dict:
    """The M-orthonormal frame of ``P`` in which the wedge is ``{0 ≤ θ ≤ β}``.

    ``E2 = n_A = w_A/√s_A`` (the M-normal of surface A), ``E1 = e_A/|e_A|_M`` with
    ``e_A = w_B − (g/s_A) w_A`` (``H_A e_A = 0``, ``H_B e_A = Δ/s_A > 0``: the edge of the admissible
    wedge on surface A). SymPy checks, with ``s_B = (Δ + g²)/s_A``:

    * the frame is M-orthonormal (``FᵀΓF = I``);
    * ``F⁻¹ G_A F = diag(1, −1)`` (reflection across ``θ = 0``),
      ``F⁻¹ G_B F`` = reflection across ``θ = β``, ``F⁻¹ G_B G_A F`` = rotation by ``2β``,
      with ``cos β = −g/√(s_A s_B)``, ``sin β = √Δ/√(s_A s_B)``;
    * the kinetic angle satisfies ``cos φ = g/√(s_A s_B) = −cos β`` and ``sin φ = sin β``: ``β = π − φ``;
    * on ``x = r(cos θ E1 + sin θ E2)``: ``H_A x = √s_A r sin θ``, ``H_B x = √s_B r sin(β − θ)``,
      so the admissible wedge is ``0 ≤ θ ≤ β`` (0 < β < π);
    * a velocity with ``H v = (c_A, c_B)`` has frame coordinates
      ``(x1, x2) = ((s_A c_B − g c_A)/√(s_A Δ), c_A/√s_A)``, so its angle is
      ``θ₀ = atan2(c_A √Δ, s_A c_B − g c_A)`` (both coordinates scaled by ``√(s_A Δ) > 0``).

    >>> f = plane_frame()
    >>> f["cos_beta"], f["sin_beta"]
    (-g/sqrt(Delta + g**2), sqrt(Delta)/sqrt(Delta + g**2))
    """
    sB = S_B_OF_DELTA
    gram = sp.Matrix([[s_A, g], [g, sB]])
    red = plane_reduction()
    GA, GB = red["G_A_P"].subs(s_B, sB), red["G_B_P"].subs(s_B, sB)
    eA = sp.Matrix([-g / s_A, 1])
    nA = sp.Matrix([1 / sp.sqrt(s_A), 0])
    norm_eA2 = sp.simplify((eA.T * gram * eA)[0, 0])
    F = sp.Matrix.hstack(eA / sp.sqrt(norm_eA2), nA)
    # each identity decided by rational_zero.is_zero (simplify(d) == 0, by the exact tests first)
    orthonormal = _all_zero(F.T * gram * F - sp.eye(2))
    cosb = -g / sp.sqrt(s_A * sB)
    sinb = sp.sqrt(Delta) / sp.sqrt(s_A * sB)
    cosb, sinb = sp.simplify(cosb), sp.simplify(sinb)
    unit = is_zero(cosb**2 + sinb**2 - 1)
    Fi = F.inv()
    refl_B = sp.Matrix([[cosb**2 - sinb**2, 2 * sinb * cosb], [2 * sinb * cosb, sinb**2 - cosb**2]])
    rot_2b = sp.Matrix([[cosb**2 - sinb**2, -2 * sinb * cosb], [2 * sinb * cosb, cosb**2 - sinb**2]])
    A_ok = _all_zero(Fi * GA * F - sp.diag(1, -1))
    B_ok = _all_zero(Fi * GB * F - refl_B)
    R_ok = _all_zero(Fi * GB * GA * F - rot_2b)
    # refl_B and rot_2b are the reflection across angle beta and the rotation by 2 beta:
    # refl_B / rot_2b are the reflection across the line at beta / the rotation by 2 beta, with
    # beta = atan2(sin_beta, cos_beta): checked at sample data (the forms are double-angle identities)
    trig_ok = True
    bnum = sp.atan2(sinb, cosb)
    for vals in ({s_A: 2, g: -1, Delta: 3}, {s_A: sp.Rational(10, 11), g: sp.Rational(-10, 11), Delta: 1}):
        b = bnum.subs(vals)
        trig_ok &= _all_zero(_reflection_across(b) - refl_B.subs(vals))
        trig_ok &= _all_zero(_rotation(2 * b) - rot_2b.subs(vals))
    # kinetic angle: cos(phi) = g / sqrt(s_A s_B)
    cosphi = g / sp.sqrt(s_A * sB)
    kin_ok = is_zero(cosphi + cosb) and is_zero(sp.sqrt(1 - cosphi**2) - sinb)
    # validity in the frame
    r = sp.Symbol("r", positive=True)
    x = F * sp.Matrix([r * sp.cos(theta), r * sp.sin(theta)])
    HA_x = sp.simplify((sp.Matrix([[s_A, g]]) * x)[0, 0])
    HB_x = sp.simplify((sp.Matrix([[g, sB]]) * x)[0, 0])
    HA_ok = is_zero(HA_x - sp.sqrt(s_A) * r * sp.sin(theta))
    HB_target = sp.sqrt(sB) * r * (sinb * sp.cos(theta) - cosb * sp.sin(theta))  # sqrt(s_B) r sin(beta - theta)
    HB_ok = is_zero(HB_x - HB_target)
    # coordinates of a velocity with H v = (c_A, c_B)
    x1, x2 = sp.symbols("x1 x2", real=True)
    p = F * sp.Matrix([x1, x2])
    sol = sp.solve([(sp.Matrix([[s_A, g]]) * p)[0, 0] - c_A, (sp.Matrix([[g, sB]]) * p)[0, 0] - c_B], [x1, x2], dict=True)[0]
    coords = (sp.simplify(sol[x1]), sp.simplify(sol[x2]))
    coords_ok = (is_zero(coords[0] - (s_A * c_B - g * c_A) / sp.sqrt(s_A * Delta))
                 and is_zero(coords[1] - c_A / sp.sqrt(s_A)))
    ok = all([orthonormal, unit, A_ok, B_ok, R_ok, trig_ok, kin_ok, HA_ok, HB_ok, coords_ok])
    return {
        "proven": bool(ok), "frame": F, "cos_beta": cosb, "sin_beta": sinb,
        "velocity_coordinates": coords,
        "theta0": sp.atan2(c_A * sp.sqrt(Delta), s_A * c_B - g * c_A),
        "checks": {"orthonormal": orthonormal, "G_A=diag(1,-1)": A_ok, "G_B=reflection(beta)": B_ok,
                   "G_B G_A=rotation(2 beta)": R_ok, "trig forms": bool(trig_ok),
                   "beta=pi-phi": kin_ok, "H_A x=sqrt(s_A) r sin(theta)": HA_ok,
                   "H_B x=sqrt(s_B) r sin(beta-theta)": HB_ok, "coordinates": coords_ok},
    }


@_derived_once
def reflection_count_derivation() -> dict:
    """Derive the exact reflection count ``m = ⌈ψ/β⌉`` of the branch that starts with surface A.

    In the frame of :func:`plane_frame`, reflection across the line at angle ``a`` maps the angle
    ``θ`` to ``2a − θ`` (checked on the matrices). Define the *excess* of a state: after a reflection
    in A (last mirror A) the angle ``θ`` lies in ``(0, π)`` and the excess is ``x = θ``; after a
    reflection in B the angle lies in ``(β − π, β)`` and the excess is ``y = β − θ``. Then

    * a state is valid exactly when its excess is ``≤ β`` (A-last: ``θ ≤ β`` is ``H_B ≥ 0``;
      B-last: ``θ ≥ 0`` is ``H_A ≥ 0``), otherwise exactly the other surface is violated, strictly,
      so the next reflection is forced (the paper's "no reasonable choice");
    * the forced reflection lowers the excess by exactly β (checked symbolically below);
    * the first reflection (in A, which ``v`` violates: ``θ₀ ∈ (−π, 0)``) gives the excess
      ``ψ = −θ₀ ∈ (0, π)``.

    So after ``m`` reflections the excess is ``ψ − (m − 1)β`` and the sequence stops at the first
    ``m ≥ 1`` with ``ψ − (m − 1)β ≤ β``: ``m = ⌈ψ/β⌉``. An iterate exactly on an edge (grazing) is
    valid: it is the case ``ψ/β ∈ ℤ`` and the ceiling returns that integer.

    >>> reflection_count_derivation()["steps"][1]
    'A-last excess x, reflect in B: new excess y = -beta + x'
    """
    a = sp.Symbol("a", real=True)
    img = _reflection_across(a) * sp.Matrix([sp.cos(theta), sp.sin(theta)])
    refl_ok = _all_zero(img - sp.Matrix([sp.cos(2 * a - theta), sp.sin(2 * a - theta)]))  # exact (is_zero)
    refl = lambda ang, th: 2 * ang - th  # noqa: E731  (checked just above)
    x = sp.Symbol("x", real=True)
    # A-last, excess x = theta; reflect in B (line at beta):
    theta_after_B = refl(beta, x)
    y_new = sp.simplify(beta - theta_after_B)
    # B-last, excess y = beta - theta; reflect in A (line at 0):
    y = sp.Symbol("y", real=True)
    theta_after_A = refl(0, beta - y)
    x_new = sp.simplify(theta_after_A)
    first = sp.simplify(refl(0, -psi))  # theta0 = -psi, reflect in A
    steps_ok = sp.simplify(y_new - (x - beta)) == 0 and sp.simplify(x_new - (y - beta)) == 0 and first == psi
    # closed form of the excess after m reflections, and the stopping rule
    excess = psi - (m_ - 1) * beta
    count = sp.ceiling(psi / beta)
    # induction: excess(1) = psi, excess(m+1) = excess(m) - beta
    ind_ok = sp.simplify(excess.subs(m_, 1) - psi) == 0 and \
        sp.simplify(excess.subs(m_, m_ + 1) - (excess - beta)) == 0
    steps = [
        f"reflection across the line at angle a maps theta to 2a - theta: {refl_ok}",
        "A-last excess x, reflect in B: new excess y = " + str(y_new),
        "B-last excess y, reflect in A: new excess x = " + str(x_new),
        f"first reflection (in A) maps theta0 = -psi to the A-last excess {first}",
        f"excess after m reflections: {excess} (induction: {ind_ok})",
        "stop at the first m >= 1 with excess <= beta: m >= psi/beta, m = ceiling(psi/beta)",
    ]
    return {"proven": bool(refl_ok and steps_ok and ind_ok), "count": count, "excess": excess,
            "psi_A": sp.atan2(-c_A * sp.sqrt(Delta), s_A * c_B - g * c_A),
            "psi_B": sp.atan2(-c_B * sp.sqrt(Delta), s_B * c_A - g * c_B),
            "beta": sp.atan2(sp.sqrt(Delta), -g), "steps": steps}


def exit_angle(m=m_, psi_=psi, beta_=beta):
    """The frame angle of the exit velocity after ``m`` reflections starting with A.

    ``θ_f = σ(mβ − ψ) + (1 − σ)β/2``, ``σ = (−1)^m``: for ``m = 2k`` the map is the rotation by
    ``2kβ`` (``θ₀ + 2kβ = mβ − ψ``), for ``m = 2k + 1`` it is ``G_A`` after it
    (``−(θ₀ + 2kβ) = ψ − (m − 1)β``).

    Parameters
    ----------
    m : int or Symbol, the number of reflections; psi_, beta_ : the angles ψ and β

    References
    ----------
    Seghete & Murphey, sec. III-B (the alternating sequence), sec. III-C (``G_u`` as a reflection).

    >>> exit_angle(3), exit_angle(4)
    (-2*beta + psi, 4*beta - psi)
    """
    sigma = 1 - 2 * sp.Mod(m, 2) if not isinstance(m, int) else (-1) ** m
    return sp.expand(sigma * (m * beta_ - psi_) + (1 - sigma) * beta_ / 2)


@lru_cache(maxsize=None)
def _kinetic_norm_squared():
    """``|p|² = (s_B c_A² − 2g c_A c_B + s_A c_B²)/Δ``, proved equal to ``cᵀΓ⁻¹c`` (the same for every
    ``m``: proved once per process, for every call of :func:`exit_relative_velocity`)."""
    gram = sp.Matrix([[s_A, g], [g, s_B]])
    c = sp.Matrix([c_A, c_B])
    p2 = (s_B * c_A**2 - 2 * g * c_A * c_B + s_A * c_B**2) / Delta
    if not is_zero((p2 - (c.T * gram.inv() * c)[0, 0]).subs(s_B, S_B_OF_DELTA)):  # exact (rational_zero)
        raise DerivationError('derivation check failed: sp.simplify((p2 - (c.T * gram.inv() * c)[0, 0]).subs(s_B, S_B_OF_DELTA)) == 0')
    return p2


def exit_relative_velocity(m=m_):
    """``(c_A', c_B')``, the exit relative velocities of the branch starting with A, in trigonometric
    closed form: ``c_A' = √s_A |p| sin θ_f``, ``c_B' = √s_B |p| sin(β − θ_f)``, with
    ``|p|² = cᵀΓ⁻¹c = (s_B c_A² − 2g c_A c_B + s_A c_B²)/Δ`` (the kinetic norm of the P-part).

    >>> ca, cb = exit_relative_velocity(1)
    >>> ca
    sqrt(s_A)*sqrt(c_A**2*s_B - 2*c_A*c_B*g + c_B**2*s_A)*sin(psi)/sqrt(Delta)
    """
    p2 = _kinetic_norm_squared()
    th = exit_angle(m)
    pn = sp.sqrt(p2)
    return sp.sqrt(s_A) * pn * sp.sin(th), sp.sqrt(s_B) * pn * sp.sin(beta - th)


def exact_exit_relative_velocity(sA, sB, gg, cA, cB, m: int):
    """Exact ``(c_A', c_B')`` after ``m`` reflections starting with A, for rational data, in the
    field ``Q(√−Δ)``: ``α = (s_A c_B − g c_A) + c_A√−Δ``, ``ρ = (−g + √−Δ)²/(s_A s_B)``,
    ``α_f = α ρ^k`` (m = 2k) or its conjugate (m = 2k + 1). Elements ``x + y√−Δ`` are pairs.

    This is the derivation's reference; ``impactsym.laws.two_surface`` evaluates the same closed
    form (the tests check them against each other and against explicit iteration).

    Parameters
    ----------
    sA, sB, gg, cA, cB : rationals ``s_A, s_B, g, c_A, c_B`` (int, Fraction)
    m : int, the number of reflections (the branch starts with A)

    Returns
    -------
    (Fraction, Fraction): ``(H_A v_m, H_B v_m)``, the relative velocities after m reflections.

    References
    ----------
    Seghete & Murphey, sec. II-A (``G_u``), sec. III-B (the alternating products ``G_v G_u ...``).

    >>> exact_exit_relative_velocity(1, 2, -1, -1, -1, 4)   # equal masses, v0 = (-1, -2)
    (Fraction(1, 1), Fraction(1, 1))
    """
    sA, sB, gg, cA, cB = (Fraction(x) for x in (sA, sB, gg, cA, cB))
    D = sA * sB - gg * gg

    def mul(u, v):
        return (u[0] * v[0] - D * u[1] * v[1], u[0] * v[1] + u[1] * v[0])

    alpha = (sA * cB - gg * cA, cA)
    n = sA * sB
    rho = ((gg * gg - D) / n, -2 * gg / n)
    k, acc, base = m // 2, (Fraction(1), Fraction(0)), rho
    while k:
        if k & 1:
            acc = mul(acc, base)
        base = mul(base, base)
        k >>= 1
    af = mul(alpha, acc)
    if m % 2:
        af = (af[0], -af[1])
    ca = af[1]
    return ca, (af[0] + gg * ca) / sA


# --------------------------------------------------------------------------- the bound
def lune_fraction(n) -> sp.Expr:
    """Area fraction ``S₀/S_total`` of the admissible lune (dihedral angle β) on the unit sphere of
    ``R^n`` (M-orthonormal coordinates, the first two spanning P).

    * ``n = 2``: arc length ``β`` over ``2π``;
    * ``n = 3``: ``∫₀^β∫₀^π sin ϑ dϑ dλ`` over ``4π``;
    * ``n = "n"``: the standard Gaussian measure is rotation invariant and its radial projection is
      the uniform measure on the sphere; the lune's condition involves only the angle of the first
      two coordinates, whose joint density ``e^{−r²/2} r/(2π)`` integrates over ``[0, β] × (0, ∞)`` to
      the fraction (the other coordinates integrate to 1).

    Parameters
    ----------
    n : 2, 3 or ``"n"`` (every dimension)

    References
    ----------
    Seghete & Murphey, sec. III-C (``S₀``, ``S_total``).

    >>> [lune_fraction(k) for k in (2, 3, "n")]
    [beta/(2*pi), beta/(2*pi), beta/(2*pi)]
    """
    lam, vt, r = sp.symbols("lambda vartheta r", positive=True)
    b = sp.Symbol("beta", positive=True)
    if n == 2:
        out = sp.integrate(1, (lam, 0, b)) / sp.integrate(1, (lam, 0, 2 * sp.pi))
    elif n == 3:
        out = sp.integrate(sp.sin(vt), (vt, 0, sp.pi), (lam, 0, b)) / sp.integrate(
            sp.sin(vt), (vt, 0, sp.pi), (lam, 0, 2 * sp.pi))
    elif n == "n":
        dens = sp.exp(-r**2 / 2) * r / (2 * sp.pi)
        total = sp.integrate(dens, (r, 0, sp.oo), (lam, 0, 2 * sp.pi))
        if not (sp.simplify(total - 1) == 0):
            raise DerivationError('derivation check failed: sp.simplify(total - 1) == 0')
        out = sp.integrate(dens, (r, 0, sp.oo), (lam, 0, b))
    else:
        raise ValueError("n must be 2, 3 or 'n'")
    return sp.simplify(out).subs(b, beta)


@_derived_once
def paper_bound() -> dict:
    """The paper's ``N = ⌈S_total/(2S₀)⌉`` (sec. III-C) in closed form: ``⌈π/β⌉``.

    >>> b = paper_bound()
    >>> b["ratio"], b["N"], b["same_in_every_dimension"]
    (pi/beta, ceiling(pi/beta), True)
    """
    fr = [lune_fraction(k) for k in (2, 3, "n")]
    same = all(sp.simplify(f - fr[0]) == 0 for f in fr)
    ratio = sp.simplify(1 / (2 * fr[0]))
    return {"fraction": fr[0], "ratio": ratio, "N": sp.ceiling(ratio), "same_in_every_dimension": same}


def bound_versus_count(beta_over_pi) -> dict:
    """Compare the bound ``N = ⌈π/β⌉`` with the exact counts, for ``β = beta_over_pi · π``.

    * ``max_count``: ``sup_{ψ∈(0,π)} ⌈ψ/β⌉`` (every branch; the supremum of a non-decreasing step
      function on an open interval: its left limit at ``π``). It is attained: on
      ``ψ ∈ ((max−1)β, π)``, a non-empty open interval.
    * ``both_approaching``: the counts possible when the velocity approaches both surfaces
      (``ψ ∈ (π − β, π)``), each first-surface choice.

    Parameters
    ----------
    beta_over_pi : rational in (0, 1)

    References
    ----------
    Seghete & Murphey, sec. III-C (``N = ⌈S_total/(2S₀)⌉``).

    >>> bound_versus_count(sp.Rational(1, 4))
    {'N': 4, 'max_count': 4, 'attained_on': (3*pi/4, pi), 'both_approaching': [4]}
    >>> bound_versus_count(sp.Rational(2, 7))
    {'N': 4, 'max_count': 4, 'attained_on': (6*pi/7, pi), 'both_approaching': [3, 4]}
    """
    bp = sp.Rational(beta_over_pi)
    if not 0 < bp < 1:
        raise ValueError("beta/pi must lie in (0, 1)")
    b = bp * sp.pi
    K = 1 / bp  # pi / beta
    N = int(sp.ceiling(K))
    # left limit of ceiling(t) at t = K (psi < pi is strict)
    max_count = int(K) if K.is_integer else N
    # psi/beta over the open interval (K - 1, K): ceiling takes {K} or {ceil(K) - 1, ceil(K)}
    both = [int(K)] if K.is_integer else [N - 1, N]
    return {"N": N, "max_count": max_count, "attained_on": ((max_count - 1) * b, sp.pi),
            "both_approaching": both}


def reachable_arc_lengths(beta_over_pi, iterations: int) -> list:
    """The paper's reachable set, exactly, on the circle (n = 2; every n is a cylinder over it):
    start with the wedge ``[0, β]`` and alternately join its images under ``G_A``, ``G_B``. Each
    set is an arc ``[lo, hi]`` (checked: the union of an arc and its mirror image is an arc when
    they overlap); returns the lengths, capped at ``2π``. The paper's claims are ``2kβ`` after k
    iterations, ``S_u = 2 max(S_u⁺, S_u⁻)`` and ``S_u^± = S_v ± S₀`` at each step (before the arc
    wraps around) — all checked here.

    Parameters
    ----------
    beta_over_pi : rational in (0, 1), the wedge opening in units of π
    iterations : number of reflections joined

    References
    ----------
    Seghete & Murphey, sec. III-C (the reachable-area argument, fig. 6).

    >>> reachable_arc_lengths(sp.Rational(1, 5), 4)
    [pi/5, 2*pi/5, 4*pi/5, 6*pi/5, 8*pi/5]
    """
    # every endpoint is a rational multiple of π (reflections in the lines at angles 0 and β):
    # the arcs are computed in units of π, with exact rational comparisons (SymPy's Min and Max of
    # multiples of π compare them numerically, 1-2 ms each), and returned as multiples of π
    b = sp.Rational(beta_over_pi)
    lo, hi = sp.Integer(0), b
    out = [hi - lo]
    mirror = [sp.Integer(0), b]  # line angles of A and B
    for k in range(iterations):
        a = mirror[k % 2]
        if hi - lo >= 2:
            out.append(sp.Integer(2))
            continue
        # the reflected arc [2a - hi, 2a - lo]; the arc contains the mirror point a (it always
        # does: it contains [0, beta]), so the union is [min, max]
        if not (lo <= a <= hi):
            raise DerivationError('derivation check failed: lo <= a <= hi')
        nlo, nhi = min(lo, 2 * a - hi), max(hi, 2 * a - lo)
        plus, minus = hi - a, a - lo  # the two sides of the mirror inside the arc
        if not ((nhi - nlo) - 2 * max(plus, minus) == 0):  # S_u = 2 max(S+, S-)
            raise DerivationError('derivation check failed: (nhi - nlo) - 2 * max(plus, minus) == 0')
        if k >= 1:  # the paper's S_u^+ = S_v + S_0, S_u^- = S_v - S_0 (S_v = S/2, S_0 = beta)
            half = (hi - lo) / 2
            big, small = max(plus, minus), min(plus, minus)
            if not (big - (half + b) == 0 and small - (half - b) == 0):
                raise DerivationError('derivation check failed: big - (half + b) == 0 and small - (half - b) == 0')
        lo, hi = nlo, nhi
        out.append(min(hi - lo, sp.Integer(2)))
    return [x * sp.pi for x in out]


def area_step_counterexample() -> dict:
    """A connected set on the 2-sphere for which the paper's ``S_u = 2 max{S_u⁺, S_u⁻}`` fails.

    Mirror: the plane ``z = 0`` (``u = e_z``). ``S`` = the cap of angular radius ``r`` around
    ``a = (1, 0, ½)/|·|`` ∪ the cap around ``b = (−1, 0, −½)/|·|`` ∪ a great-circle arc joining them
    (area 0). The caps are disjoint from each other and from their mirror images (centre distances
    exceed ``2r``), so ``|S ∪ G_u S| = 4·cap`` while ``2 max{S⁺, S⁻} = 2·cap``. On the circle
    (n = 2) and for the lunes the proof actually meets, the step is right
    (:func:`reachable_arc_lengths` checks it).

    >>> area_step_counterexample()["fails"]
    True
    """
    r = sp.Rational(1, 10)
    cap = 2 * sp.pi * (1 - sp.cos(r))
    a = sp.Matrix([1, 0, sp.Rational(1, 2)]).normalized()
    b = sp.Matrix([-1, 0, -sp.Rational(1, 2)]).normalized()
    Gu = sp.diag(1, 1, -1)
    centres = [a, b, Gu * a, Gu * b]
    dists = [sp.acos((centres[i].T * centres[j])[0]) for i in range(4) for j in range(i + 1, 4)]
    # every sign certified (rigorous enclosures, impactsym.exact), never a 30-digit comparison
    disjoint = all(certified_sign(d - 2 * r) > 0 for d in dists)
    # caps are within one hemisphere each: |z| of the centre exceeds sin(r)
    inside = all(certified_sign(abs(c[2]) - sp.sin(r)) > 0 for c in (a, b))
    union = 4 * cap if disjoint else None
    two_max = 2 * cap
    return {"fails": bool(disjoint and inside and certified_sign(union - two_max) > 0),
            "union_area": union, "two_max": two_max}


@_derived_once
def paper_example_counts() -> dict:
    """Sec. III-B.3 (``M = diag(11/10, 1)``, ``u = [1, 0]``, ``v = [−1, 1]``): the counts depend on v0.

    The u-first branch needs 4 reflections exactly when ``H_v G_u G_v G_u v0 < 0`` (the third iterate
    still violates v), else 3; the v-first branch needs 4 exactly when ``H_u G_v G_u G_v v0 < 0``.
    With ``v0 = v1 (1, t)``, ``v1 < 0``, approaching both (``t > 1``): u-first needs 4 iff ``t > 23/19``,
    v-first needs 4 iff ``t < 439/40``.

    >>> e = paper_example_counts()
    >>> e["u_first_four_iff"], e["v_first_four_iff"], e["N"]
    (23/19 < t, t < 439/40, 4)
    """
    M = sp.diag(sp.Rational(11, 10), 1)
    Hu, Hv = sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]])

    def G(h):
        w = M.inv() * h.T
        return G_matrix(w, h, (h * w)[0, 0])

    Gu, Gv = G(Hu), G(Hv)
    lu = Hv * Gu * Gv * Gu
    lv = Hu * Gv * Gu * Gv
    t = sp.Symbol("t", real=True)
    v1 = sp.Symbol("v1", negative=True)
    v0 = sp.Matrix([v1, t * v1])
    cond_u = sp.solve_univariate_inequality((lu * v0)[0, 0] / (-v1) < 0, t, relational=True)
    cond_v = sp.solve_univariate_inequality((lv * v0)[0, 0] / (-v1) < 0, t, relational=True)
    cosphi = (Hu * M.inv() * Hv.T)[0, 0] / sp.sqrt((Hu * M.inv() * Hu.T)[0, 0] * (Hv * M.inv() * Hv.T)[0, 0])
    b = sp.pi - sp.acos(cosphi)
    return {"G_u": Gu, "G_v": Gv, "u_first_four_iff": cond_u, "v_first_four_iff": cond_v,
            "ell_u": lu, "ell_v": lv, "beta": sp.simplify(b), "N": int(sp.ceiling(sp.pi / b)),
            "v4a": Gv * Gu * Gv * Gu, "v4b": Gu * Gv * Gu * Gv}


# --------------------------------------------------------------------------- code generation
_ARGS = sp.symbols("s_a s_b g c_a c_b", real=True)


@lru_cache(maxsize=None)  # both branches of kernels() take the same m: derived and proved once
def _emitted_exit(mm):
    """``(c_A', c_B')`` as the kernels evaluate them (issue 15), proved equal to
    :func:`exit_relative_velocity` for even and odd ``m`` (asserted).

    ``θ_f`` and ``β − θ_f`` are ``a = ψ − (m − 1)β`` and ``b = mβ − ψ`` (``(a, b)`` for odd ``m``,
    ``(b, a)`` for even), the smaller of the two as one difference and the other as ``β`` minus
    it, instead of the expanded
    ``σ(mβ − ψ) + (1 − σ)β/2`` whose terms (``mβ − 2mβ·(m mod 2) + ...``) lose ``eps·mβ`` around
    angles that can be ``1e-12`` (one reflection: ``θ_f = ψ`` exactly, was ``−(β − ψ) + β``).
    """
    odd = sp.Eq(sp.Mod(mm, 2), 1)
    a_d, b_d = psi - (mm - 1) * beta, mm * beta - psi
    if not (sp.expand(beta - b_d - a_d) == 0):
        raise DerivationError('derivation check failed: sp.expand(beta - b_d - a_d) == 0')
    # the smaller one directly (its relative precision), the other as beta minus it (so that
    # a + b = beta to one rounding: independent roundings of both break the exit vector of a thin
    # wedge, whose H^-1 amplifies an inconsistency by 1/beta)
    small_a = 2 * psi <= (2 * mm - 1) * beta  # a_d <= b_d
    sa_, sb_ = sp.sin(a_d), sp.sin(b_d)
    # the same sines through the smaller angle: beta minus it, held unevaluated (SymPy would flatten
    # beta - (m beta - psi) back into psi - (m - 1) beta)
    sa2, sb2 = sp.sin(beta - sp.UnevaluatedExpr(b_d)), sp.sin(beta - sp.UnevaluatedExpr(a_d))
    p2 = (s_B * c_A**2 - 2 * g * c_A * c_B + s_A * c_B**2) / Delta
    pn = sp.sqrt(p2)
    ca = sp.sqrt(s_A) * pn * sp.Piecewise((sa_, sp.And(odd, small_a)), (sa2, odd), (sb2, small_a), (sb_, True))
    cb = sp.sqrt(s_B) * pn * sp.Piecewise((sb2, sp.And(odd, small_a)), (sb_, odd), (sa_, small_a), (sa2, True))
    # one, two and three reflections (every wedge with beta >= pi/3 needs at most three) as the
    # reflections themselves, rational in the data: no angle, no pi (a right-angle wedge put
    # 2 beta - psi ~ 1e-17 next to atan2 values ~ pi, 1e15 eps); equal to the trigonometric form
    # (asserted in _check_few_reflections)
    one, two, three = few_reflections(s_A, s_B, g, c_A, c_B)
    _check_few_reflections(one, two, three)
    ca = sp.Piecewise((one[0], sp.Eq(mm, 1)), (two[0], sp.Eq(mm, 2)), (three[0], sp.Eq(mm, 3)), (ca, True))
    cb = sp.Piecewise((one[1], sp.Eq(mm, 1)), (two[1], sp.Eq(mm, 2)), (three[1], sp.Eq(mm, 3)), (cb, True))
    k = sp.Symbol("k", integer=True)
    ca_t, cb_t = ca.args[-1].expr, cb.args[-1].expr  # the general (trigonometric) branch
    ca, cb = ca_t, cb_t
    for m_val in (2 * k, 2 * k + 1):
        old_a, old_b = exit_relative_velocity(m_val)
        # every branch of m's parity (small or not: the same sine through a_d + b_d = beta)
        for pick in ((0, 1) if m_val == 2 * k + 1 else (2, 3)):
            new_a = (ca / ca.args[-1] * ca.args[-1].args[pick].expr).subs(mm, m_val)
            new_b = (cb / cb.args[-1] * cb.args[-1].args[pick].expr).subs(mm, m_val)
            new_a, new_b = (x.doit() for x in (new_a, new_b))  # UnevaluatedExpr: its value
            if not (sp.simplify(sp.expand_trig(sp.expand(new_a - old_a))) == 0):
                raise DerivationError((m_val, pick))
            if not (sp.simplify(sp.expand_trig(sp.expand(new_b - old_b))) == 0):
                raise DerivationError((m_val, pick))
    # the branch is chosen by the count's own tests (emitted_count), not by comparing a count with
    # 1, 2, 3 (SymPy folds Eq(Piecewise, j) into conditions C cannot print); the trigonometric
    # branch (count >= 4) takes m = ceiling(psi/beta)
    t1, t2, t3 = count_tests(s_A, s_B, g, c_A, c_B)
    return (sp.Piecewise((one[0], t1), (two[0], t2), (three[0], t3), (ca_t, True)),
            sp.Piecewise((one[1], t1), (two[1], t2), (three[1], t3), (cb_t, True)))


def few_reflections(sa, sb, gg, ca, cb):
    """``(c_A, c_B)`` after one, two and three reflections of the branch that starts with A, as
    the reflections themselves (``G_A``: ``c_A ↦ −c_A``, ``c_B ↦ c_B − 2g c_A/s_A``; ``G_B``
    symmetrically), nested so that a float evaluation errs by a few eps of the magnitudes of its
    terms (componentwise backward stable in ``s, g, c``).

    >>> one, two, three = few_reflections(*sp.symbols("s_A s_B g c_A c_B"))
    >>> one
    (-c_A, -2*c_A*g/s_A + c_B)
    """
    one = (-ca, cb - 2 * gg * ca / sa)
    two = (one[0] - 2 * gg * one[1] / sb, -one[1])
    three = (-two[0], two[1] - 2 * gg * two[0] / sa)
    return one, two, three


def count_tests(sa, sb, gg, ca, cb):
    """The conditions ``count = 1``, ``= 2``, ``= 3`` of the A-first branch, each read where the
    previous ones fail: the component the next reflection would act on is ``≥ 0`` (valid)."""
    one, two, three = few_reflections(sa, sb, gg, ca, cb)
    return one[1] >= 0, two[0] >= 0, three[1] >= 0


def emitted_count(sa, sb, gg, ca, cb, ratio):
    """The reflection count ``⌈ψ/β⌉`` of the A-first branch (``c_A < 0``) as the kernels evaluate
    it: the signs of the rational iterates for counts 1, 2, 3, the ceiling of ``ratio = ψ/β`` above.

    ``ψ/β`` near 1, 2 or 3 happens with ``ψ`` or ``β`` near ``π/2`` or ``π``, where a float angle
    carries an absolute error ``eps·π`` that the inputs do not (``ψ/β = 2 + 4e-17`` at a right-angle
    wedge whose iterate after two reflections violates A by ``1e-10``: the float ceiling said 2, the
    exact count is 3 at every input within 1e13 eps). The sign of a rational iterate errs only within
    a few eps (componentwise) of its zero, i.e. of the count boundary itself. Equal to
    ``⌈ψ/β⌉`` (proved in :func:`count_form_steps`).
    """
    t1, t2, t3 = count_tests(sa, sb, gg, ca, cb)
    return sp.Piecewise((1, t1), (2, t2), (3, t3), (sp.ceiling(ratio), True))


@_derived_once
def count_form_steps() -> dict:
    """Prove that :func:`emitted_count` equals ``⌈ψ/β⌉`` on the branch ``c_A < 0``.

    * The j-th iterate's component that the next reflection tests is ``√s |p| sin(jβ − ψ)``
      (``j = 1``: ``c_B' = √s_B|p| sin(β − ψ)``; ``j = 2``: ``c_A'' = √s_A|p| sin(2β − ψ)``; ``j = 3``:
      ``c_B''' = √s_B|p| sin(3β − ψ)``): the trigonometric exit of :func:`exit_relative_velocity`
      with ``θ_f = ψ``, ``2β − ψ``, ``ψ − 2β`` (checked here), and the rational iterates equal it
      (:func:`_check_few_reflections`).
    * ``|p| > 0`` (``c ≠ 0``) and ``√s > 0``: the component has the sign of ``sin(jβ − ψ)``.
    * When the earlier tests failed, ``ψ > (j − 1)β``; with ``0 < ψ < π`` and ``β > 0``,
      ``jβ − ψ ∈ (−π, β) ⊂ (−π, π)`` (``jβ − ψ < β < π`` and ``jβ − ψ > −ψ > −π``), where
      ``sin ≥ 0`` exactly when ``jβ − ψ ≥ 0``: the test says ``ψ ≤ jβ``, i.e. ``⌈ψ/β⌉ = j``.
    * All three failed: ``ψ > 3β``, and the count is the ceiling itself.

    >>> count_form_steps()["proven"]
    True
    """
    pn = sp.sqrt((s_B * c_A**2 - 2 * g * c_A * c_B + s_A * c_B**2) / Delta)
    tests = [(1, 1, sp.sqrt(s_B)), (2, 0, sp.sqrt(s_A)), (3, 1, sp.sqrt(s_B))]
    ok = True
    steps = []
    for j, comp, root in tests:
        got = exit_relative_velocity(j)[comp]
        want = root * pn * sp.sin(j * beta - psi)
        same = is_zero(sp.expand_trig(got - want))  # simplify(d) == 0, by the exact tests first
        ok &= bool(same)
        steps.append(f"after {j} reflection(s) the tested component is {root}|p| sin({j} beta - psi): {same}")
    # the interval argument (linear, stated): j beta - psi < beta < pi since psi > (j-1) beta, and
    # j beta - psi > -psi > -pi since beta > 0 and psi < pi
    steps.append("with psi in (0, pi) and psi > (j-1) beta: j beta - psi in (-pi, beta), where sin >= 0 iff >= 0")
    return {"proven": bool(ok), "steps": steps}


def _check_few_reflections(one, two, three):
    """The trigonometric exit (:func:`exit_relative_velocity`) after one, two and three reflections
    equals the rational ``one``, ``two``, ``three``: with ``cos β = −g/√(s_A s_B)``, ``sin β = √Δ/√(s_A s_B)`` and
    ``cos ψ = x/r``, ``sin ψ = y/r`` (``ψ = atan2(y, x)``, ``y = −c_A √Δ``, ``x = s_A c_B − g c_A``,
    ``r² = x² + y² = s_A (s_B c_A² − 2g c_A c_B + s_A c_B²)``), after ``Δ = s_A s_B − g²``."""
    y, x = -c_A * sp.sqrt(Delta), s_A * c_B - g * c_A
    r = sp.sqrt(s_A * (s_B * c_A**2 - 2 * g * c_A * c_B + s_A * c_B**2))
    sub = {sp.cos(beta): -g / sp.sqrt(s_A * s_B), sp.sin(beta): sp.sqrt(Delta) / sp.sqrt(s_A * s_B),
           sp.cos(psi): x / r, sp.sin(psi): y / r}
    for m_val, want in ((1, one), (2, two), (3, three)):
        got = exit_relative_velocity(m_val)
        for gexpr, w in zip(got, want):
            d = (sp.expand_trig(gexpr).subs(sub) - w).subs(Delta, s_A * s_B - g**2)
            if not is_zero(d):  # simplify(d) == 0, decided first by exact tests (rational_zero)
                raise DerivationError((m_val, sp.simplify(d)))


@lru_cache(maxsize=None)
def _count_angles() -> tuple:
    """``(ψ_A, β)`` of :func:`reflection_count_derivation` (derived once: both branches of
    :func:`_branch_expressions` and :func:`_branch_frames` read them)."""
    der = reflection_count_derivation()
    return der["psi_A"], der["beta"]


def _branch_expressions(first_is_a: bool):
    """Count and exit (c_A', c_B') of one branch in the kernel's arguments (float closed form)."""
    sa, sb, gg, ca, cb = _ARGS
    if not first_is_a:  # swap roles: the branch starting with B is the A-branch of (B, A)
        sa, sb, ca, cb = sb, sa, cb, ca
    D = sa * sb - gg**2
    psi_a, beta_ = _count_angles()
    sub = {s_A: sa, s_B: sb, g: gg, c_A: ca, c_B: cb, Delta: D}
    # symbols by expressions free of every key: one simultaneous replacement (xreplace) gives the
    # chain of subs (psi, beta through fresh names, then the arguments, then m) srepr for srepr
    psi_e = psi_a.xreplace(sub)
    beta_e = beta_.xreplace(sub)
    count = emitted_count(sa, sb, gg, ca, cb, psi_e / beta_e)
    mm = sp.Symbol("m_count", real=True)
    ea, eb = _emitted_exit(mm)
    # the trigonometric branch is the count's last one (above 3): m = ceiling(psi/beta) there
    rep = {**sub, psi: psi_e, beta: beta_e, mm: sp.ceiling(psi_e / beta_e)}
    ea, eb = (e.xreplace(rep) for e in (ea, eb))
    if not first_is_a:
        ea, eb = eb, ea
    return count, ea, eb


def _same_condition(a, b) -> bool:
    """``a`` and ``b`` are the same condition up to SymPy's normal form of a relational (each
    ``x <= y`` of one is ``x' <= y'`` of the other with ``x − y`` a positive multiple of ``x' − y'``)."""
    if a == b:
        return True
    if type(a) is not type(b):
        return False
    if isinstance(a, sp.core.relational.Relational):
        ratio = sp.simplify((a.lhs - a.rhs) / (b.lhs - b.rhs))
        return bool(ratio.is_number and ratio > 0)
    if isinstance(a, (sp.And, sp.Or)) and len(a.args) == len(b.args):
        rest = list(b.args)
        for x in a.args:
            match = next((y for y in rest if _same_condition(x, y)), None)
            if match is None:
                return False
            rest.remove(match)
        return True
    return False


def _branch_frames(first_is_a: bool):
    """:func:`exit_frame_branches` in the kernel's arguments (``m = ⌈ψ/β⌉``), frames as rows of ``H``
    (0 for the row the branch starts with), checked against :func:`_emitted_exit`'s sines."""
    sa, sb, gg, ca, cb = _ARGS
    if not first_is_a:
        sa, sb, ca, cb = sb, sa, cb, ca
    psi_a, beta_ = _count_angles()
    sub = {s_A: sa, s_B: sb, g: gg, c_A: ca, c_B: cb, Delta: sa * sb - gg**2}
    psi_e, beta_e = psi_a.subs(sub), beta_.subs(sub)
    mm = sp.Symbol("m_count", real=True)
    ea, eb = _emitted_exit(mm)
    inner = [e.args[-1].expr.atoms(sp.Piecewise) for e in (ea, eb)]
    if not all(len(x) == 1 for x in inner):
        raise DerivationError("derivation check failed: the trigonometric exit has one Piecewise of sines")
    inner = [x.pop() for x in inner]
    out = []
    for idx, (cond, frame, angle) in enumerate(exit_frame_branches(mm)):
        t_first, t_other = (angle, beta - angle) if frame == 0 else (beta - angle, angle)
        for pw, t in zip(inner, (t_first, t_other)):
            got = pw.args[idx]
            if not (_same_condition(got.cond, cond) and is_zero(sp.expand_trig(got.expr.doit() - sp.sin(t)))):
                raise DerivationError(f"derivation check failed: frame branch {idx} is not _emitted_exit's")
        rep = {psi: psi_e, beta: beta_e}
        cond_e, angle_e = (x.subs(rep).subs(mm, sp.ceiling(psi_e / beta_e)) for x in (cond, angle))
        row = frame if first_is_a else 1 - frame
        out.append((cond_e, row, angle_e))
    return out


def exit_frame_branches(mm=m_):
    """The trigonometric exit (count ``m ≥ 4``) as an angle from the nearer edge: a list of
    ``(condition, frame, angle)``, ``frame`` 0 for the edge in the first surface (A), 1 for B, in the
    order of :func:`_emitted_exit`'s branches (``a = ψ − (m − 1)β``, ``b = mβ − ψ``, ``a + b = β``).

    The exit's angle from A's edge is ``θ_f``, from B's ``β − θ_f``; the branch picks the smaller one
    of ``a``, ``b`` (the one :func:`_emitted_exit` evaluates directly) and the edge it is measured from.

    >>> [f for _, f, _ in exit_frame_branches()]
    [0, 1, 1, 0]
    """
    odd = sp.Eq(sp.Mod(mm, 2), 1)
    a_d, b_d = psi - (mm - 1) * beta, mm * beta - psi
    small_a = 2 * psi <= (2 * mm - 1) * beta
    return [(sp.And(odd, small_a), 0, a_d), (odd, 1, b_d), (small_a, 1, a_d), (sp.true, 0, b_d)]


def frame_exit_velocity(M, H, v, frame: int, cos_t, sin_t, det_m=None):
    """``v⁺ = |v|_M (cos t ê + sin t n)`` for ``n = 2``: ``ê`` the M-unit edge of the wedge lying in
    surface ``frame`` (``H_frame ê = 0``, the other row positive), ``n`` that surface's M-normal, ``t``
    the exit's angle from that edge (issue 15: ``H⁻¹ c'`` lost an exit whose rows are parallel to 4e7,
    ``v_1⁺ = −v_1`` to 1e-23 came back off by 901 eps; here ``ê = sgn(det H) adj(H)_{:,other} / √q``,
    ``q = H_i adj(M) H_iᵀ = |adj(H)_{:,other}|²_M``, ``n = adj(M) H_iᵀ / √(det M q)``: no ``1/det H``).

    Equal to ``H⁻¹ c'`` with the trigonometric ``c'`` (proved in :func:`frame_exit_steps`).

    Examples
    --------
    The quadrant ``v_1 ≥ 0`` (A), ``v_0 ≥ 0`` (B) with ``M = I``: A's edge is ``(1, 0)``, B's ``(0, 1)``.

    >>> H = sp.Matrix([[0, 1], [1, 0]])
    >>> frame_exit_velocity(sp.eye(2), H, sp.Matrix([3, 4]), 0, sp.Rational(3, 5), sp.Rational(4, 5)).T
    Matrix([[3, 4]])
    >>> frame_exit_velocity(sp.eye(2), H, sp.Matrix([3, 4]), 1, sp.Rational(3, 5), sp.Rational(4, 5)).T
    Matrix([[4, 3]])
    """
    det_m = M.det() if det_m is None else det_m
    i, j = frame, 1 - frame
    adj_m = M.adjugate()
    row = H[i, :].T
    q = (row.T * adj_m * row)[0, 0]
    dh = H.det()
    e = H.adjugate()[:, j] * dh / sp.Abs(dh)
    speed = sp.sqrt((v.T * M * v)[0, 0])
    return speed * (cos_t * e / sp.sqrt(q) + sin_t * adj_m * row / sp.sqrt(det_m * q))


@_derived_once
def frame_exit_steps() -> dict:
    """Prove ``H v⁺ = c'`` for :func:`frame_exit_velocity` in both frames: ``c'_i = √s_i |p| sin t``,
    ``c'_j = √s_j |p| sin(β − t) = √s_j |p| (sin β cos t − cos β sin t)``, with ``s = q/det M``,
    ``g = H_A adj(M) H_Bᵀ / det M``, ``√Δ = |det H|/√det M`` (``Δ = det H²/det M``), ``|p|² = vᵀMv`` (n = 2),
    ``cos β = −g/√(s_A s_B)``, ``sin β = √Δ/√(s_A s_B)``. Every square root is a symbol ``r`` and the
    difference's numerator is reduced modulo ``r² − (its radicand)``: exactly zero.

    >>> frame_exit_steps()["proven"]
    True
    """
    m00, m01, m11, h00, h01, h10, h11, v0, v1 = sp.symbols("m00 m01 m11 h00 h01 h10 h11 v0 v1", real=True)
    M = sp.Matrix([[m00, m01], [m01, m11]])
    H = sp.Matrix([[h00, h01], [h10, h11]])
    v = sp.Matrix([v0, v1])
    cs, sn = sp.symbols("cos_t sin_t", real=True)
    r_d, r_v, r_0, r_1, sg = sp.symbols("r_D r_v r_0 r_1 sigma", positive=True)
    det_m, dh, adj_m = M.det(), H.det(), M.adjugate()
    q = [(H[i, :] * adj_m * H[i, :].T)[0, 0] for i in range(2)]
    gq = (H[0, :] * adj_m * H[1, :].T)[0, 0]
    r = [r_0, r_1]
    rels = [(r_d, det_m), (r_v, (v.T * M * v)[0, 0]), (r_0, q[0]), (r_1, q[1]), (sg, dh**2)]
    ok = True
    for i in range(2):
        j = 1 - i
        # frame_exit_velocity with sqrt(q_i) = r_i, sqrt(det M q_i) = r_D r_i, |v|_M = r_v, |det H| = sigma
        e = H.adjugate()[:, j] * dh / sg
        vp = r_v * (cs * e / r[i] + sn * adj_m * H[i, :].T / (r_d * r[i]))
        root_s = [r[0] / r_d, r[1] / r_d]  # sqrt(s_i) = sqrt(q_i / det M)
        root_ss = root_s[0] * root_s[1]
        cos_b, sin_b = -(gq / det_m) / root_ss, (sg / r_d) / root_ss
        want = [None, None]
        want[i] = root_s[i] * r_v * sn
        want[j] = root_s[j] * r_v * (sin_b * cs - cos_b * sn)
        for comp in range(2):
            num, _ = sp.fraction(sp.together((H[comp, :] * vp)[0, 0] - want[comp]))
            num = sp.expand(num)
            for sym, val in rels:
                num = sp.expand(sp.rem(num, sym**2 - val, sym))
            ok &= num == 0
    return {"proven": bool(ok)}


#: the floor of the float det(M) of the (M, H, v) closed form, relative to m_00 m_11 (about the
#: rounding error of m_00 m_11 - m_01^2)
DET_M_FLOOR = sp.Rational(1, 2**52)


def _floored_det_m(outs, m00, m01, m11):
    """``outs`` with ``det M = m_00 m_11 − m_01²`` evaluated as ``max(det M, 2⁻⁵² m_00 m_11)`` (issue 15).

    An SPD ``M`` with ``cond ≥ 1e16`` (``m_00 m_11 ≈ m_01²``) has a float ``det M`` of ``0`` (or
    negative): ``1/det M`` was ``inf`` and the count ``⌈ψ/β⌉`` came out of ``atan2(inf, inf)`` as 1
    where every input within 64 eps needs 5 (or 4896700). ``det M`` enters the outputs only through
    ``√Δ = √det M |det H|`` (with ``adj M``, which is accurate): in a thin wedge ``ψ`` and ``β`` are both
    proportional to ``√det M`` and the count and exits depend on their ratio. Below the floor the
    exact ``det M`` of the float data is within about one rounding error, ``eps m_00 m_11``, of the
    floor: the floored value is the ``det M`` of an input within 1 eps (``m_00`` raised by at most
    ``2⁻⁵²`` relative, since ``0 < det M < floor``), the backward perturbation a float evaluation
    commits anyway. The 50-digit references evaluate the formulas without the floor (the kernel's
    ``exact_outputs``): where the exact ``det M ≤ 0`` (M not positive definite) they leave the domain. At or above the
    floor the expression is unchanged: every output is identical to the proved form there (asserted:
    the substitution leaves no other ``det M``).

    >>> a, b, c, d = sp.symbols("a b c d", positive=True)
    >>> _floored_det_m([1 / (a * c - b**2) + d], a, b, c)[0]
    d + 1/Max(a*c/4503599627370496, a*c - b**2)
    """
    det = m00 * m11 - m01**2
    d = sp.Symbol("det_M_floored", positive=True)
    from .codegen import _distinct_nodes, _has_any, _xreplace_shared

    # o.subs(det, d) is the replacement of every node det (and -det) when no other sum holds det's
    # terms or their negatives among others (Add._eval_subs matches those as well; Mul, Pow, the
    # functions and the conditions rebuild their arguments, Piecewise and And drop what becomes
    # False or follows a True as their construction does): checked, else subs itself. One
    # replacement shared by the outputs, which repeat each other's subexpressions (issue 15)
    terms = [set(det.args), set((-det).args)]
    nodes = set().union(*(_distinct_nodes(sp.sympify(o)) for o in outs))
    if any(isinstance(n, sp.Add) and n not in (det, -det) and any(t <= set(n.args) for t in terms) for n in nodes):
        subbed = [o.subs(det, d) for o in outs]
    else:
        memo: dict = {}
        subbed = [_xreplace_shared(sp.sympify(o), {det: d, -det: -d}, memo) for o in outs]
    if any(_has_any(s, [m00 * m11]) for s in subbed):
        raise DerivationError("derivation check failed: det M occurs in a form the floor does not reach")
    floor = DET_M_FLOOR * m00 * m11
    back: dict = {}
    return [_xreplace_shared(s, {d: sp.Max(det, floor)}, back) for s in subbed]  # a fresh symbol: xreplace is subs


def kernels() -> list:
    """Float kernels of the O(1) two-surface resolution (uncertified: the law certifies).

    * ``two_surface_reflection_count(s_a, s_b, g, c_a, c_b)``: the count of each branch
      (``-1`` when the branch does not exist: that surface is not approached; ``0`` when the
      velocity is already valid);
    * ``two_surface_resolution(s_a, s_b, g, c_a, c_b)``: counts and exit relative velocities
      ``H v⁺`` of both branches;
    * ``two_surface_exit_velocity(mass_matrix, gradients, velocity)``: general n, both branches'
      counts and exit velocities ``v⁺ = v + W Γ⁻¹ (c' − c)``;
    * ``two_surface_resolution_2``: the n = 2 closed form from ``M`` (upper triangle), ``H``, ``v``.
    """
    sa, sb, gg, ca, cb = _ARGS
    if not count_form_steps()["proven"]:
        raise DerivationError("derivation check failed: the emitted count is not ceiling(psi/beta)")
    if not frame_exit_steps()["proven"]:
        raise DerivationError("derivation check failed: the frame exit is not H^-1 c'")
    valid = sp.And(ca >= 0, cb >= 0)
    outs_count, outs_res = [], []
    for first_is_a, c_first in ((True, ca), (False, cb)):
        count, ea, eb = _branch_expressions(first_is_a)
        cnt = sp.Piecewise((0, valid), (count, c_first < 0), (-1, True))
        outs_count.append(cnt)
        nan = sp.nan
        outs_res += [cnt,
                     sp.Piecewise((ca, valid), (ea, c_first < 0), (nan, True)),
                     sp.Piecewise((cb, valid), (eb, c_first < 0), (nan, True))]
    doc_c = ("Reflection counts (count_a, count_b) of the branches that start with surface A, B\n"
             "(Seghete & Murphey sec. III-B/C): ceil(psi/beta), psi = atan2(-c_i sqrt(Delta), s_i c_j - g c_i),\n"
             "beta = atan2(sqrt(Delta), -g), Delta = s_a s_b - g^2; counts 1, 2, 3 from the signs of the\n"
             "iterates themselves (rational in s, g, c), equal to the ceiling; 0 when c >= 0 (valid), -1 when\n"
             "the branch does not exist. Float arithmetic, uncertified: impactsym.laws.two_surface certifies.")
    doc_r = ("Counts and exit relative velocities (H v+) of both branches: (count_a, ca_a, cb_a,\n"
             "count_b, ca_b, cb_b). After 1-3 reflections the reflections themselves (rational);\n"
             "above, c' = (sqrt(s_a)|p| sin th, sqrt(s_b)|p| sin(beta - th)),\n"
             "th = sigma (m beta - psi) + (1 - sigma) beta / 2, sigma = (-1)^m (A-first frame).\n"
             "Float: the angle error grows like m * eps; the law gives certified values.")
    out = [
        ScalarKernel("two_surface_reflection_count", list(_ARGS), outs_count, ["count_a", "count_b"], doc_c),
        ScalarKernel("two_surface_resolution", list(_ARGS), outs_res,
                     ["count_a", "ca_a", "cb_a", "count_b", "ca_b", "cb_b"], doc_r),
    ]
    general = ArrayKernel(
        "two_surface_exit_velocity",
        '''
        def two_surface_exit_velocity(mass_matrix, gradients, velocity):
            """Both branches of a two-surface impact in general dimension n (float, uncertified).

            Returns (counts, exits): counts (2,) as in two_surface_reflection_count, exits (2, n) the
            exit velocities v+ = v + W Gamma^-1 (c' - c) of the branches starting with row 0 and row 1
            (NaN rows for a branch that does not exist). W = M^-1 H^T, Gamma = H M^-1 H^T.
            """
            mass_matrix = numpy.asarray(mass_matrix, dtype=float)
            gradients = numpy.asarray(gradients, dtype=float)
            velocity = numpy.asarray(velocity, dtype=float)
            if velocity.shape == (2,):  # n = 2: the closed form below, proved equal to this one by its
                # derivation; Gamma formed in floats loses det(Gamma) ~ beta^2 at a thin wedge (issue 15)
                res = two_surface_resolution_2(mass_matrix[0, 0], mass_matrix[0, 1], mass_matrix[1, 1],
                                               *gradients.ravel(), velocity[0], velocity[1])
                return numpy.array([res[0], res[3]]), numpy.array([[res[1], res[2]], [res[4], res[5]]])
            # n >= 3: the same wedge in the coordinates q' = T^-1 q with H T = [H_P, 0], T = [[I, -X], [0, I]],
            # X = H_P^-1 H_R (P: the pair of columns of H that complete pivoting picks, |X| <= 2): the
            # impact acts on q'_P as the n = 2 problem (M2, H_P, v'_P), M2 the Schur complement of
            # M' = T^T M T on P, v'_P = v_P + X v_R, and moves q'_R by -Y (y+ - v'_P), Y = M'_RR^-1 M'_RP.
            # Gamma is never formed (its det ~ beta^2 cancelled); where H touches two coordinates only
            # (X = 0) or M couples P to nothing else (Y = 0) no rounding enters the reduction.
            n = velocity.shape[-1]
            r0 = int(numpy.argmax(numpy.abs(gradients).max(axis=1)))
            p0 = int(numpy.argmax(numpy.abs(gradients[r0])))
            rest = gradients[1 - r0] - gradients[1 - r0, p0] / gradients[r0, p0] * gradients[r0]
            rest[p0] = 0.0
            p1 = int(numpy.argmax(numpy.abs(rest)))
            P = sorted((p0, p1))
            R = [j for j in range(n) if j not in P]
            h_p, h_r = gradients[:, P], gradients[:, R]
            x = numpy.linalg.solve(h_p, h_r)
            m_pp, m_pr, m_rr = mass_matrix[numpy.ix_(P, P)], mass_matrix[numpy.ix_(P, R)], mass_matrix[numpy.ix_(R, R)]
            mp_pr = m_pr - m_pp @ x
            y = numpy.linalg.solve(m_rr - m_pr.T @ x - x.T @ mp_pr, mp_pr.T)
            m2 = m_pp - mp_pr @ y
            v2 = velocity[P] + x @ velocity[R]
            res = two_surface_resolution_2(m2[0, 0], m2[0, 1], m2[1, 1], *h_p.ravel(), v2[0], v2[1])
            counts = numpy.array([res[0], res[3]])
            exits = numpy.empty((2, n))
            for i, yp in enumerate((numpy.array(res[1:3]), numpy.array(res[4:6]))):
                exits[i, R] = velocity[R] - y @ (yp - v2)
                exits[i, P] = yp - x @ exits[i, R]
            return counts, exits
        ''',
    )
    out.append(general)
    # n = 2 closed form from the matrices
    m00, m01, m11 = sp.symbols("m_00 m_01 m_11", real=True)
    h = sp.symbols("h_00 h_01 h_10 h_11", real=True)
    v0, v1 = sp.symbols("v_0 v_1", real=True)
    M = sp.Matrix([[m00, m01], [m01, m11]])
    H = sp.Matrix([[h[0], h[1]], [h[2], h[3]]])
    v = sp.Matrix([v0, v1])
    adj = M.adjugate()
    det = M.det()
    W = adj * H.T / det
    # simplify(H W) of these fixed symbols is signsimp(together(.)) of each entry, srepr for srepr
    # (SymPy pinned: tests/test_codegen_sync diffs the kernels): the sum over det M, 0.33 -> 0.02 s
    gram = (H * W).applyfunc(lambda x: sp.signsimp(sp.together(x)))
    cvec = H * v
    sub = {sa: gram[0, 0], sb: gram[1, 1], gg: gram[0, 1], ca: cvec[0], cb: cvec[1]}
    outs2, names2 = [], []
    # Stable form (factored discriminant): Delta = det(Gamma) = s_a s_b - g^2 computed from the Gram
    # entries loses ~eps/beta^2 for a wedge of angle beta; for n = 2, Gamma = H M^-1 H^T gives
    # det(Gamma) = det(H)^2 / det(M) (product of determinants), whose only cancellation is det(H)'s,
    # ~eps/beta, the conditioning of the wedge angle w.r.t. H itself. Gamma^-1 = adj(Gamma)/Delta.
    delta_f = H.det() ** 2 / det
    if not is_zero(gram[0, 0] * gram[1, 1] - gram[0, 1] ** 2 - delta_f):  # exact (rational_zero)
        raise DerivationError('derivation check failed: sp.simplify(gram[0, 0] * gram[1, 1] - gram[0, 1] ** 2 - delta_f) == 0')
    dsym = sp.Symbol("Delta_f", positive=True)
    ginv = sp.Matrix([[gram[1, 1], -gram[0, 1]], [-gram[0, 1], gram[0, 0]]]) / delta_f
    if not all(is_zero(x) for x in W * ginv - H.adjugate() / H.det()):  # exact (rational_zero)
        raise DerivationError('derivation check failed: W * ginv - H.adjugate() / H.det() is not the zero matrix')

    # and c^T adj(Gamma) c = c_a^2 s_b - 2 c_a c_b g + c_b^2 s_a (the squared wedge-plane speed times
    # Delta) equals Delta * v^T M v for n = 2 (c = H v, H square): a sum of squares instead of a
    # cancelling quadratic form
    quad = ca**2 * sb - 2 * ca * cb * gg + cb**2 * sa
    qsym = sp.Symbol("Q_f", positive=True)
    quad_f = delta_f * (v.T * M * v)[0, 0]
    if not is_zero(quad.subs(sub) - quad_f):  # exact (rational_zero)
        raise DerivationError('derivation check failed: sp.simplify(quad.subs(sub) - quad_f) == 0')

    # and adj(Gamma) c = Delta Gamma^-1 c = det(H)/det(M) adj(H)^T M v (the second argument of psi's
    # atan2, which otherwise cancels as c_b s_a - g c_a with both terms O(1) and the result O(beta^2))
    adjc = H.det() / det * (H.adjugate().T * M * v)
    lin = [sb * ca - gg * cb, sa * cb - gg * ca]
    lsym = sp.symbols("L0_f L1_f", real=True)
    for i in range(2):
        if not is_zero(lin[i].subs(sub) - adjc[i]):  # exact (rational_zero)
            raise DerivationError('derivation check failed: sp.simplify(lin[i].subs(sub) - adjc[i]) == 0')

    delta_gram = sa * sb - gg**2
    factored_forms = {quad: qsym, -quad: -qsym, lin[0]: lsym[0], -lin[0]: -lsym[0], lin[1]: lsym[1],
                      -lin[1]: -lsym[1], delta_gram: dsym, -delta_gram: -dsym}

    from .codegen import _has_any

    def _factored(expr):
        # the stable forms by one xreplace of each form and its negative (what subs does at a node equal
        # to them); subs differs from it only at a sum holding the terms of one (or of its negative)
        # among others, which has() finds (it matches such sums): then the three subs in a row, as
        # before (srepr-identical on all 36 forms, 0.40 -> 0.13 s with a cold SymPy cache)
        # (has: once per distinct subexpression, _has_any)
        got = expr.xreplace(factored_forms)
        if _has_any(got, factored_forms):
            got = expr.subs(quad, qsym).subs({lin[0]: lsym[0], lin[1]: lsym[1]}).subs(delta_gram, dsym)
        expr = got
        if _has_any(expr, (delta_gram, quad)):
            raise DerivationError('derivation check failed: not expr.has(sa * sb - gg**2) and not expr.has(quad)')
        # symbols by expressions free of every key: one simultaneous replacement (xreplace) gives
        # the two subs in a row (the generated kernels are byte-identical: tests/test_codegen_sync)
        return expr.xreplace({**sub, dsym: delta_f, qsym: quad_f, lsym[0]: adjc[0], lsym[1]: adjc[1]})

    adjM = M.adjugate()
    for k, tag in ((0, "a"), (3, "b")):
        cnt = _factored(outs_res[k])
        # v+ = v + W Gamma^-1 (c' - c): for n = 2, H is square and W Gamma^-1 = H^-1 (checked above), so
        # v+ = H^-1 c'; the general form adds and cancels terms of size |Gamma^-1| ~ 1/Delta ~ 1/beta^2
        # around an O(1) result. Every branch below is H^-1 c' in a form that does not divide by det H.
        # Issue 15: H^-1 c' amplifies the rounding of c' by cond(H), which a valid velocity (v+ = v:
        # v_0 = 1e-12 next to v_1 = 1e12 came back as 0) or nearly parallel rows with one or two
        # reflections (beta near pi, cond(H) ~ 1/(pi - beta)) do not have. Counts 0..3 take the
        # velocity itself and its reflections v <- v - 2 (H_i v) u_i, u_i = adj(M) H_i^T / (H_i adj(M) H_i^T)
        # (M^-1 H_i^T / s_i with det M cancelled), with the tested components H_i v of the rational
        # iterates (the count's own signs); H v_j equals the j-th rational iterate (asserted), so
        # each equals H^-1 c' on its count.
        first, other = (0, 1) if k == 0 else (1, 0)
        rows = [H[first, :], H[other, :]]
        u = [adjM * r.T / (r * adjM * r.T)[0, 0] for r in rows]
        iters = few_reflections(sa, sb, gg, ca, cb) if k == 0 else \
            [(b, a) for a, b in few_reflections(sb, sa, gg, cb, ca)]
        iters = [tuple(_factored(x) for x in it) for it in iters]  # (c_A, c_B) in the rows' order
        c_first, tested = cvec[first], [iters[0][other], iters[1][first]]
        vr1 = v - 2 * c_first * u[0]
        vr2 = vr1 - 2 * tested[0] * u[1]
        vr3 = vr2 - 2 * tested[1] * u[0]
        for j, (vj, it) in enumerate(((vr1, iters[0]), (vr2, iters[1]), (vr3, iters[2])), start=1):
            if not all(is_zero(x) for x in H * vj - sp.Matrix(it)):  # exact (rational_zero)
                raise DerivationError(f"derivation check failed: H v_{j} != the rational iterate {j} ({tag})")
        t1, t2, t3 = (_factored(t) for t in (count_tests(sa, sb, gg, ca, cb) if k == 0 else
                                              count_tests(sb, sa, gg, cb, ca)))
        # above three reflections the exit in the frame of the nearer edge (frame_exit_velocity, equal
        # to H^-1 c' by frame_exit_steps): H^-1 c' amplified the rounding of c' by cond(H) (issue 15)
        frames = [(_factored(cond), row, _factored(angle)) for cond, row, angle in _branch_frames(k == 0)]
        vframe = [sp.Piecewise(*[(frame_exit_velocity(M, H, v, row, sp.cos(angle), sp.sin(angle), det)[i],
                                  True if n == len(frames) - 1 else cond)
                                 for n, (cond, row, angle) in enumerate(frames)]) for i in range(2)]
        valid2, approach = sp.And(cvec[0] >= 0, cvec[1] >= 0), cvec[first] < 0
        vexit = [sp.Piecewise((v[i], valid2), (sp.Piecewise((vr1[i], t1), (vr2[i], t2), (vr3[i], t3), (vframe[i], True)),
                                               approach), (sp.nan, True)) for i in range(2)]
        outs2 += [cnt, vexit[0], vexit[1]]
        names2 += [f"count_{tag}", f"v0_{tag}", f"v1_{tag}"]
    exact2, outs2 = outs2, _floored_det_m(outs2, m00, m01, m11)
    out.append(ScalarKernel(
        "two_surface_resolution_2", [m00, m01, m11, *h, v0, v1], outs2, names2,
        "n = 2 closed form: M by its upper triangle, H = [[h_00, h_01], [h_10, h_11]], v = (v_0, v_1).\n"
        "Returns (count_a, v0_a, v1_a, count_b, v0_b, v1_b): counts and exit velocities of the branches\n"
        "starting with row 0 (a) and row 1 (b): v itself when valid, its reflections for counts 1-3,\n"
        "above H^-1 c' as |v|_M (cos t e + sin t n) in the frame of the nearer edge (no 1/det H); det M\n"
        "floored at 2^-52 m_00 m_11. Float, uncertified (see impactsym.laws.two_surface).\n\n"
        "Precondition: rows of H of order one. The law does not change when a row of H is scaled by a\n"
        "positive factor, so normalize the rows first; then M and v may take any scales within 2^±480\n"
        "(about 1e±144) for which v^T M v is a normal float (tested at the corners). H itself scaled by\n"
        "2^±360 (about 1e±108) gave a wrong exit velocity, silently (0.117 instead of 0.0165), and\n"
        "scaled by 2^±200 together with M or v scaled by 2^±480 as well: products of the inputs left\n"
        "the normal floats.",
        exact_outputs=exact2,  # the references evaluate the true det M (the floor is a float guard)
    ))
    return out


MODULE_DOC = """O(1) resolution of a two-surface impact (Seghete & Murphey sec. III-B, III-C).

The alternating reflections act on the 2-plane span(M^-1 H_1^T, M^-1 H_2^T) as reflections in a
wedge of opening beta = pi - phi (phi the kinetic angle); the branch starting with surface i needs
ceil(psi_i / beta) reflections. Float kernels, uncertified; impactsym.laws.two_surface certifies.
"""


def generate(outdir) -> list[Path]:
    """Write ``two_surface.py`` into ``outdir`` (committed copy in ``impactsym/kernels``)."""
    path = Path(outdir) / "two_surface.py"
    path.write_text(render_family("two_surface", "two_surface", MODULE_DOC, kernels()))
    return [path]
