"""The single-impact map ``G_u`` and the Newton-restitution map ``G_u(e)``, derived by SymPy.

Seghete & Murphey, sec. II-A, eqs. 1a–1b. For a simple mechanical system (``L = ½q̇ᵀMq̇ − V``)
a single impact against the surface ``φ = 0`` with gradient covector ``u = Dφ`` is

* momentum jump along ``u`` (eq. 1a, read as the jump of ``∂L/∂q̇`` across the impact):
  ``M q̇⁺ − M q̇⁻ + λ uᵀ = 0``;
* energy conservation (eq. 1b, the jump of the energy ``∂L/∂q̇·q̇ − L``): ``q̇⁺ᵀMq̇⁺ − q̇⁻ᵀMq̇⁻ = 0``.

SymPy solves the momentum equation for ``q̇⁺``, substitutes it into the energy equation, obtains
``λ (λ uM⁻¹uᵀ − 2 u q̇⁻) = 0``, discards the trivial root (reason recorded), and reads off
``G_u = ∂q̇⁺/∂q̇⁻``. With Newton restitution the energy equation is replaced by
``u q̇⁺ = −e u q̇⁻``. The same derivation is carried out in general dimension in the
non-commutative algebra of :mod:`derivations.algebra`.

Conventions: ``λ`` is the paper's multiplier; impactsym's impulse is ``p = −λ``
(``CONVENTIONS.md``), ``p ≥ 0`` for an approaching velocity.

Examples
--------
>>> d = derive_single_impact(2)
>>> d.discarded_roots
[(0, 'lambda = 0 gives qdot+ = qdot- ...')]
>>> d.matches_printed_G, d.matches_printed_lambda
(True, True)
>>> r = run_proof("det(G)=-1", "n")
>>> r.proven, r.method.split(":")[0]
(True, 'structural')
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Callable

import sympy as sp

from .memo import simplify
from .algebra import block_determinant_lemma, nc_symbols, rewrite
from .codegen import ArrayKernel, ScalarKernel, numpy_code, render_family
from .rational_zero import cancel, factor, factored_numerator, is_zero, is_zero_rational_function

from impactsym.arithmetic.remembered import solve_remembered
from impactsym.errors import DerivationError

__all__ = [
    "symbolic_mass_matrix",
    "symbolic_covector",
    "G_matrix",
    "scaled_G",
    "printed_G",
    "printed_lambda",
    "derive_single_impact",
    "derive_restitution",
    "derive_general",
    "ProofResult",
    "PROPERTIES",
    "run_proof",
    "prove_all",
    "general_emitted_proof",
    "general_emitted_pieces",
    "kernels",
    "generate",
]

TRIVIAL_ROOT_REASON = (
    "lambda = 0 gives qdot+ = qdot- (no momentum jump): the pre-impact velocity approaches the "
    "surface (u qdot- < 0), so keeping it would cross the constraint; Seghete & Murphey: "
    "'no change occurred through the collision. We know this to always be false'"
)


# --------------------------------------------------------------------------- symbols
def symbolic_mass_matrix(n: int) -> sp.Matrix:
    """A fully symbolic symmetric ``n×n`` mass matrix with entries ``m_ij = m_ji``.

    >>> symbolic_mass_matrix(2)
    Matrix([
    [m_00, m_01],
    [m_01, m_11]])
    """
    return sp.Matrix(n, n, lambda i, j: sp.Symbol(f"m_{min(i, j)}{max(i, j)}", real=True))


def symbolic_covector(n: int, name: str = "u") -> sp.Matrix:
    """A symbolic row covector ``[u_0, ..., u_{n-1}]``."""
    return sp.Matrix([[sp.Symbol(f"{name}_{i}", real=True) for i in range(n)]])


def symbolic_vector(n: int, name: str) -> sp.Matrix:
    return sp.Matrix([sp.Symbol(f"{name}_{i}", real=True) for i in range(n)])


def G_matrix(w, u, s, e=1, identity=None):
    """``G_u(e) = I − (1+e) w u / s``: the one statement of the map in the derivations, which every
    proof, the two-surface derivation and :func:`printed_G` call (``CONVENTIONS.md``).

    ``w`` is ``M⁻¹uᵀ`` or any multiple of it (``adj(M) uᵀ`` keeps entries polynomial) and ``s = u w``
    the matching multiple of ``u M⁻¹ uᵀ``. Works on SymPy matrices (``identity`` defaults to
    ``I_n``) and on the non-commutative symbols of the general-``n`` proofs (``identity=1``).

    >>> G_matrix(sp.Matrix([1, 0]), sp.Matrix([[1, 0]]), 1)
    Matrix([
    [-1, 0],
    [ 0, 1]])
    """
    if identity is None:
        identity = sp.eye(w.rows)
    return identity - (1 + e) * w * u / s


def scaled_G(w, u, s, e=1):
    """``s G_u(e) = s I − (1+e) w u``: :func:`G_matrix` with its denominator cleared (polynomial
    entries for ``w = adj(M) uᵀ``), for the direct proofs."""
    return s * sp.eye(w.rows) - (1 + e) * w * u


def printed_G(M: sp.Matrix, u: sp.Matrix, e=1) -> sp.Matrix:
    """The paper's printed map, transcribed: ``I − (1+e) M⁻¹uᵀu / (u M⁻¹ uᵀ)`` (e = 1: ``G_u``).

    Computed with the adjugate (``M⁻¹ = adj M / det M``; the determinant cancels).
    """
    w = M.adjugate() * u.T
    return G_matrix(w, u, (u * w)[0, 0], e)


def printed_lambda(M: sp.Matrix, u: sp.Matrix, qm: sp.Matrix) -> sp.Expr:
    """The paper's printed multiplier ``λ_A = 2 Dφ q̇⁻ / (Dφ M⁻¹ Dφᵀ)``, transcribed."""
    return 2 * (u * qm)[0, 0] / (u * M.inv() * u.T)[0, 0]


def _is_zero_rational(expr) -> bool:
    """Exact zero test of a rational function: the numerator over a product of non-zero
    denominators, expanded by python-flint (:mod:`derivations.rational_zero`, milliseconds), or,
    for anything else, SymPy's cancel to lowest terms and the expanded numerator."""
    fast = is_zero_rational_function(expr)
    if fast is not None:
        return fast
    num, _den = sp.fraction(sp.cancel(sp.together(expr)))
    return sp.expand(num) == 0


def _matrix_is_zero(A: sp.Matrix) -> bool:
    return all(_is_zero_rational(x) for x in A)


# --------------------------------------------------------------------------- derivations
@dataclass
class Derivation:
    """What a derivation found: the multiplier, the map, and the roots it discarded."""

    n: int | str
    M: object
    u: object
    qminus: object
    lam: sp.Expr
    qplus: object
    G: object
    roots: list  # as sp.solve(..., simplify=False) finds them (simplify to print)
    discarded_roots: list = field(default_factory=list)
    matches_printed_G: bool | None = None
    matches_printed_lambda: bool | None = None
    energy_change: sp.Expr | None = None
    matches_printed_energy_loss: bool | None = None
    seconds: float = 0.0


def _short(reason: str) -> str:
    return reason.split(":")[0] + " ..." if False else reason[: reason.find("qdot-") + 5] + " ..."


def _jacobian_of_linear(qplus, qm) -> sp.Matrix:
    """``∂q̇⁺/∂q̇⁻`` of a ``q̇⁺`` linear in ``q̇⁻`` (the single-impact maps): column ``j`` is ``q̇⁺``
    at ``q̇⁻ = e_j``, in ``sympy.cancel``'s normal form (the form ``jacobian(...).applyfunc(cancel)``
    gave, at a fraction of the cost of differentiating the rational functions). Verified before it
    is returned: ``G`` is free of ``q̇⁻`` and ``G q̇⁻ = q̇⁺`` identically, so ``G`` is the Jacobian.

    >>> a, b, k = sp.symbols("a b k")
    >>> _jacobian_of_linear(sp.Matrix([a + k * b, b / k]), sp.Matrix([a, b]))
    Matrix([
    [1,   k],
    [0, 1/k]])
    """
    n = len(qm)
    zero = {s: 0 for s in qm}
    G = sp.Matrix(len(qplus), n, lambda i, j: cancel(qplus[i].xreplace({**zero, qm[j]: 1})))
    if any(x.has(*qm) for x in G) or not all(is_zero_rational_function(x) for x in G * qm - qplus):
        raise DerivationError("q+ is not linear in q-: its Jacobian is not the map G")
    return G


def _momentum_solution(M, u, qm, lam, qp_syms) -> dict:
    """The one solution ``q̇⁺ = q̇⁻ − λ adj(M)uᵀ/det M`` of eq. 1a, ``M q̇⁺ − M q̇⁻ + λuᵀ = 0``
    (linear in ``q̇⁺``; unique because ``det M`` is not the zero polynomial, decided exactly), as a
    substitution for ``qp_syms``. Cramer's rule instead of ``sympy.solve``'s elimination over the
    symbolic field; the callers check that it satisfies eq. 1a exactly and read only normal forms
    of it (the factored energy numerator, flint's cancel), so the derivation is the same."""
    det = M.det(method="berkowitz")
    if is_zero_rational_function(det) is not False:
        raise DerivationError("the momentum equation is linear in qdot+ with an invertible M: det M = 0")
    w = M.adjugate(method="berkowitz") * u.T
    return {qp: q - lam * wi / det for qp, q, wi in zip(qp_syms, qm, w)}


@lru_cache(maxsize=None)
def derive_single_impact(n: int) -> Derivation:
    """Solve eqs. 1a–1b for ``λ`` and ``q̇⁺`` with a fully symbolic symmetric ``M`` (n = 2, 3, ...).

    Returns a :class:`Derivation` whose ``G`` is ``∂q̇⁺/∂q̇⁻`` of the non-trivial root, and which
    records whether ``G`` and ``λ`` equal the paper's printed forms (exact rational-function test).
    """
    t0 = time.perf_counter()
    M, u, qm = symbolic_mass_matrix(n), symbolic_covector(n), symbolic_vector(n, "qm")
    qp_syms = symbolic_vector(n, "qp")
    lam = sp.Symbol("lambda", real=True)
    momentum = M * qp_syms - M * qm + lam * u.T  # eq. 1a, as the jump of dL/dqdot
    # (check=False: the same solutions in the same form; they are checked below, exactly, by flint)
    sol = _momentum_solution(M, u, qm, lam, qp_syms)
    if not all(is_zero_rational_function(x.xreplace(sol)) for x in momentum):
        raise DerivationError("the solution of the momentum equation does not satisfy it")
    qp_of_lam = qp_syms.subs(sol)
    energy = (qp_of_lam.T * M * qp_of_lam)[0, 0] - (qm.T * M * qm)[0, 0]  # eq. 1b
    # its numerator over the denominators' product (det M powers, free of lambda), factored by flint
    energy_num = factored_numerator(energy, free_of=[lam])
    # the roots as solve finds them, unsimplified (simplifying costs more than the solve; only the
    # n = 2 roots are printed, and the claims that print them simplify them: solve's default form,
    # tests/test_reflection_roots.py); the kept root is factored below, the zero root decided exactly
    roots = solve_remembered(energy_num, lam, check=False, simplify=False)
    if not all(is_zero_rational_function(energy_num.xreplace({lam: r})) for r in roots):
        raise DerivationError("a root of the energy equation does not satisfy it")
    discarded = [(r, TRIVIAL_ROOT_REASON) for r in roots if is_zero(r)]
    kept = [r for r in roots if not is_zero(r)]
    if not (len(kept) == 1):
        raise DerivationError(f"expected one non-trivial root, got {kept}")
    lam_star = factor(kept[0])  # sympy.factor's form, by flint
    qplus = qp_of_lam.subs(lam, lam_star).applyfunc(cancel)  # sympy.cancel's normal form, by flint
    G = _jacobian_of_linear(qplus, qm)
    d = Derivation(n, M, u, qm, lam_star, qplus, G, roots,
                   [(r, _short(reason)) for r, reason in discarded])
    d.matches_printed_G = _matrix_is_zero(G - printed_G(M, u))
    d.matches_printed_lambda = _is_zero_rational(lam_star - printed_lambda(M, u, qm))
    d.seconds = time.perf_counter() - t0
    return d


@lru_cache(maxsize=None)
def derive_restitution(n: int) -> Derivation:
    """The Newton-restitution map: eq. 1a with ``u q̇⁺ = −e u q̇⁻`` in place of energy conservation.

    Also derives the kinetic-energy change ``ΔT = T⁺ − T⁻`` and compares it with
    ``−(1 − e²)(u q̇⁻)² / (2 u M⁻¹ uᵀ)``.
    """
    t0 = time.perf_counter()
    M, u, qm = symbolic_mass_matrix(n), symbolic_covector(n), symbolic_vector(n, "qm")
    qp_syms = symbolic_vector(n, "qp")
    lam, e = sp.Symbol("lambda", real=True), sp.Symbol("e", nonnegative=True)
    momentum = M * qp_syms - M * qm + lam * u.T
    sol = _momentum_solution(M, u, qm, lam, qp_syms)  # checked exactly below
    if not all(is_zero_rational_function(x.xreplace(sol)) for x in momentum):
        raise DerivationError("the momentum equation's one solution does not satisfy it")
    qp_of_lam = qp_syms.subs(sol)
    restitution = (u * qp_of_lam)[0, 0] + e * (u * qm)[0, 0]
    # the condition is linear in lambda: a lambda + b = 0 with a != 0 (its numerator over the
    # denominators' product, which is free of lambda), so the one root is -b/a
    linear = sp.Poly(factored_numerator(restitution, free_of=[lam]), lam)
    if linear.degree() != 1:
        raise DerivationError(f"u q+ = -e u q- is not linear in lambda: degree {linear.degree()}")
    a, b = linear.all_coeffs()
    if is_zero_rational_function(a) is not False:
        raise DerivationError("u q+ = -e u q- does not involve lambda (a = 0)")
    roots = [-b / a]
    lam_star = factor(roots[0])  # sympy.factor's form, by flint
    qplus = qp_of_lam.subs(lam, lam_star).applyfunc(cancel)  # sympy.cancel's normal form, by flint
    G = _jacobian_of_linear(qplus, qm)
    dT = ((qplus.T * M * qplus)[0, 0] - (qm.T * M * qm)[0, 0]) / 2
    s = (u * M.adjugate() * u.T)[0, 0] / M.det()
    printed_dT = -(1 - e**2) * (u * qm)[0, 0] ** 2 / (2 * s)
    d = Derivation(n, M, u, qm, lam_star, qplus, G, roots)
    d.matches_printed_G = _matrix_is_zero(G - printed_G(M, u, e))
    d.matches_printed_lambda = _is_zero_rational(lam_star - (1 + e) * (u * qm)[0, 0] / s)
    d.energy_change = dT
    d.matches_printed_energy_loss = _is_zero_rational(dT - printed_dT)
    d.seconds = time.perf_counter() - t0
    return d


# The general-dimension algebra: W = M⁻¹uᵀ (column), U = u (row), Q = q̇⁻ (column), their
# transposes, M; scalars s = u M⁻¹ uᵀ, c = u q̇⁻.
W, U, MM, Wt, Ut, Q, Qt, X, Xt, Y, Yt = nc_symbols("W U M Wt Ut Q Qt X Xt Y Yt")
s_, c_, e_, alpha_ = sp.symbols("s c e alpha", real=True, nonzero=True)
RULES = {U * W: s_, MM * W: Ut, Wt * MM: U, Wt * Ut: s_, U * Q: c_, Qt * Ut: c_}
RULE_REASONS = {
    "U*W -> s": "definition s = u M^-1 u^T (s > 0 for SPD M and u != 0)",
    "M*W -> Ut": "definition w = M^-1 u^T",
    "Wt*M -> U": "transpose of M w = u^T with M^T = M",
    "Wt*Ut -> s": "transpose of u w = s",
    "U*Q -> c, Qt*Ut -> c": "definition c = u qdot- (a scalar, equal to its transpose)",
}


@lru_cache(maxsize=None)
def derive_general(restitution: bool = False) -> Derivation:
    """The derivation in general dimension, in the non-commutative algebra of ``W, U, M, Q``.

    ``q̇⁺ = Q − λW`` solves eq. 1a (checked: ``M(Q − λW) − MQ + λUᵀ`` rewrites to 0); the energy
    equation rewrites to ``λ²s − 2λc``; the non-trivial root is ``λ = 2c/s`` (``(1+e)c/s`` with
    restitution), and ``q̇⁺ = (1 − 2WU/s) Q``.
    """
    t0 = time.perf_counter()
    lam = sp.Symbol("lambda", real=True)
    qplus = Q - lam * W
    momentum_residual = rewrite(MM * qplus - MM * Q + lam * Ut, RULES)
    if not (momentum_residual == 0):
        raise DerivationError(momentum_residual)
    if restitution:
        condition = rewrite(U * qplus + e_ * U * Q, RULES)  # u q+ = -e u q-
        e_val = e_
    else:
        qplus_t = Qt - lam * Wt
        condition = rewrite(qplus_t * MM * qplus - Qt * MM * Q, RULES)  # energy jump
        e_val = 1
    roots = solve_remembered(condition, lam)
    discarded = [(r, TRIVIAL_ROOT_REASON) for r in roots if r == 0]
    kept = [r for r in roots if r != 0]
    if not (len(kept) == 1):
        raise DerivationError('derivation check failed: len(kept) == 1')
    lam_star = sp.factor(kept[0])
    # q+ = Q - lam* W with lam* = coeff*c/s = coeff*(U Q)/s  ->  G = 1 - coeff W U / s
    coeff = 1 + e_val
    G = G_matrix(W, U, s_, e_val, identity=1)
    check = rewrite(G * Q - (Q - lam_star * W), RULES)
    if not (check == 0):
        raise DerivationError(check)
    d = Derivation("n", MM, U, Q, lam_star, Q - lam_star * W, G, roots,
                   [(r, _short(reason)) for r, reason in discarded])
    d.matches_printed_lambda = is_zero(lam_star - coeff * c_ / s_)
    d.matches_printed_G = True  # G is read off in the printed form I - coeff M^-1 u^T u/(u M^-1 u^T)
    d.seconds = time.perf_counter() - t0
    return d


# --------------------------------------------------------------------------- proofs
@dataclass
class ProofResult:
    """One machine-checked property of ``G_u``."""

    name: str
    dimension: int | str
    method: str
    proven: bool
    seconds: float
    steps: list = field(default_factory=list)

    def as_dict(self) -> dict:
        return {"name": self.name, "dimension": self.dimension, "proven": bool(self.proven),
                "method": self.method, "seconds": round(self.seconds, 4), "steps": self.steps}


def _adjugate_G(n: int, e=1):
    """``G = I − (1+e) w u / s`` with ``w = adj(M) uᵀ`` and ``s = u w``: polynomial ``w`` and ``s``,
    the structure that keeps direct proofs fast (``det M`` cancels from ``M⁻¹uᵀ/(uM⁻¹uᵀ)``)."""
    M, u = symbolic_mass_matrix(n), symbolic_covector(n)
    w = M.adjugate() * u.T
    s = sp.expand((u * w)[0, 0])
    return M, u, w, s


@lru_cache(maxsize=None)
def _direct_G_equals_derived(n: int) -> tuple[bool, float]:
    """Step 0 of every direct proof: the G derived from eqs. 1a-1b equals I - 2 w u/s with
    w = adj(M)u^T (cached; returns the verdict and the seconds the derivation and check took)."""
    t0 = time.perf_counter()
    M, u, w, s = _adjugate_G(n)
    ok = _matrix_is_zero(derive_single_impact(n).G - G_matrix(w, u, s))
    return ok, time.perf_counter() - t0


def _step0(n: int) -> tuple[bool, str]:
    ok, secs = _direct_G_equals_derived(n)
    return ok, (f"step 0: G derived from eqs. 1a-1b equals I - 2wu/s with w = adj(M)u^T, s = uw: {ok} "
                f"(derivation and check {secs:.2f} s, once per n)")


def _all_zero_polynomials(entries) -> bool:
    """Every entry (a polynomial) expands to the zero polynomial, expanded exactly by python-flint
    (:func:`derivations.rational_zero.is_zero_rational_function`; SymPy's ``expand`` when an entry
    is not a rational function over Q)."""
    for x in entries:
        fast = is_zero_rational_function(x)
        if fast is None:
            fast = sp.expand(x) == 0
        if not fast:
            return False
    return True


def _bareiss_det_plus_is_zero(N: sp.Matrix, c) -> bool:
    """Whether ``det(N) + c`` is the zero polynomial: ``det N`` by fraction-free (Bareiss)
    elimination in python-flint's exact polynomials (every division exact), then compared with
    ``-c`` exactly. SymPy's ``det(method="bareiss")`` and ``expand`` when an entry is not a
    polynomial over Q."""
    from .rational_zero import to_fraction

    syms = sorted(set().union(*[x.free_symbols for x in N], sp.sympify(c).free_symbols), key=str)
    try:
        fr = [[to_fraction(N[i, j], syms) for j in range(N.cols)] for i in range(N.rows)]
        cn, cd = to_fraction(c, syms)
    except TypeError:
        return sp.expand(N.det(method="bareiss") + c) == 0
    if any(d != 1 for row in fr for _, d in row) or cd != 1:
        return sp.expand(N.det(method="bareiss") + c) == 0
    A = [[x for x, _ in row] for row in fr]
    n = len(A)
    sign, prev = 1, A[0][0] ** 0 if n else None
    for k in range(n - 1):
        if A[k][k] == 0:
            swap = next((i for i in range(k + 1, n) if A[i][k] != 0), None)
            if swap is None:
                return cn == 0
            A[k], A[swap] = A[swap], A[k]
            sign = -sign
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                A[i][j] = (A[i][j] * A[k][k] - A[i][k] * A[k][j]) / prev  # exact (Sylvester's identity)
        prev = A[k][k]
    det = sign * A[n - 1][n - 1]
    return det + cn == 0


def _direct_square(n: int):
    M, u, w, s = _adjugate_G(n)
    N = scaled_G(w, u, s)  # N = s G
    residual = N * N - s**2 * sp.eye(n)
    return _all_zero_polynomials(residual), [
        "cleared denominators: (sG)^2 - s^2 I expands to the zero polynomial matrix",
    ]


def _direct_metric(n: int):
    M, u, w, s = _adjugate_G(n)
    N = scaled_G(w, u, s)
    residual = N.T * M * N - s**2 * M
    return _all_zero_polynomials(residual), [
        "cleared denominators: (sG)^T M (sG) - s^2 M expands to the zero polynomial matrix"
    ]


def _direct_det(n: int):
    M, u, w, s = _adjugate_G(n)
    N = scaled_G(w, u, s)
    ok = _bareiss_det_plus_is_zero(N, s**n)  # fraction-free elimination of a polynomial matrix
    return ok, [
        "det(sG) = s^n det(G) computed by fraction-free (Bareiss) elimination on the polynomial "
        "matrix sI - 2wu (w = adj(M)u^T), instead of det of the rational matrix G",
        f"det(sI - 2wu) + s^{n} expands to 0, so det(G) = -1 (s != 0 for SPD M, u != 0)",
    ]


def _direct_scale(n: int):
    M, u, w, s = _adjugate_G(n)
    a = sp.Symbol("alpha", real=True, nonzero=True)
    G = G_matrix(w, u, s)
    Ga = printed_G(M, a * u)
    return _matrix_is_zero(Ga - G), ["G_{alpha u} - G_u cancels to the zero matrix (alpha != 0)"]


def _direct_flip(n: int):
    M, u, w, s = _adjugate_G(n)
    v = symbolic_vector(n, "v")
    G = G_matrix(w, u, s)
    return _is_zero_rational((u * G * v)[0, 0] + (u * v)[0, 0]), ["u (G v) + u v cancels to 0"]


def _direct_fixes(n: int):
    M, u, w, s = _adjugate_G(n)
    x = symbolic_vector(n, "x")
    G = G_matrix(w, u, s)
    # G x - x = -2 w (u x)/s identically, so G x = x exactly when u x = 0.
    residual = G * x - x + 2 * w * (u * x)[0, 0] / s
    # and a basis of ker u: u_0 != 0, x_k = u_0 e_k - u_k e_0, k = 1..n-1
    basis_ok = True
    for k in range(1, n):
        xk = sp.zeros(n, 1)
        xk[k], xk[0] = u[0], -u[k]
        basis_ok &= sp.expand((u * xk)[0, 0]) == 0 and _matrix_is_zero(G * xk - xk)
    return _matrix_is_zero(residual) and basis_ok, [
        "G x - x = -2 w (u x)/s identically",
        "G fixes each vector of the basis {u_0 e_k - u_k e_0} of ker u (u_0 != 0)",
    ]


def _direct_restitution(n: int):
    d = derive_restitution(n)
    return bool(d.matches_printed_energy_loss and d.matches_printed_G), [
        "Newton restitution u qdot+ = -e u qdot- solved with eq. 1a: G(e) = I - (1+e) M^-1u^T u/(u M^-1 u^T)",
        "T+ - T- - (-(1-e^2)(u v)^2/(2 u M^-1 u^T)) cancels to 0",
    ]


def _direct_restitution_one(n: int):
    M, u = symbolic_mass_matrix(n), symbolic_covector(n)
    d = derive_restitution(n)
    return _matrix_is_zero(d.G.subs(sp.Symbol("e", nonnegative=True), 1) - derive_single_impact(n).G), [
        "G_u(e) at e = 1 minus the elastic G_u (both derived) cancels to 0"
    ]


def _general_square():
    G = derive_general().G
    r = rewrite(G * G, RULES)
    return r == 1, ["G = 1 - 2WU/s (derived)", f"G*G expands and rewrites (U*W -> s) to {r}"]


def _general_metric():
    G = derive_general().G
    Gt = G_matrix(Ut, Wt, s_, identity=1)  # G^T: the transposed factors
    r = rewrite(Gt * MM * G, RULES)
    return r == MM, ["G^T = 1 - 2 Ut Wt / s", f"G^T M G rewrites (M*W -> Ut, Wt*M -> U, Wt*Ut -> s) to {r}"]


def _general_det():
    product, lemma_ok = block_determinant_lemma()
    G = derive_general().G
    # G = I + a b with a = -2W/s (column), b = U (row): b a = -2 U W / s = -2
    ba = rewrite(U * (-2 * W / s_), RULES)
    eig_w = rewrite(G * W, RULES)
    eig_x = rewrite(G * X, {**RULES, U * X: 0})
    ok = lemma_ok and ba == -2 and 1 + ba == -1 and eig_w == -W and eig_x == X
    return ok, [
        "block identity [[I,0],[b,1]][[I+ab,a],[0,1]][[I,0],[-b,1]] = [[I,a],[0,1+ba]] verified "
        f"by non-commutative block multiplication: {lemma_ok}",
        "hence det(I + ab) = 1 + ba (outer factors unit block-triangular)",
        f"with a = -2w/s, b = u: ba rewrites to {ba}; det(G) = 1 + ba = {1 + ba}",
        f"eigen-structure: G w = {eig_w} (eigenvalue -1), G x = {eig_x} for u x = 0 (eigenvalue 1, "
        "multiplicity n-1); w is not in ker u since u w = s != 0, so det G = (-1)(1)^(n-1) = -1",
    ]


def _general_scale():
    a = alpha_
    # G_{a u}: w -> a w, u -> a u, s -> a^2 s
    Ga = G_matrix(a * W, a * U, a**2 * s_, identity=1)
    r = sp.expand(Ga - derive_general().G)
    return r == 0, ["w_{a u} = a w, s_{a u} = a^2 s", f"G_(a u) - G_u expands to {r}"]


def _general_flip():
    r = rewrite(U * derive_general().G * Y + U * Y, RULES)
    return r == 0, [f"u (G v) + u v rewrites (U*W -> s) to {r}"]


def _general_fixes():
    r = rewrite(derive_general().G * X - X, {**RULES, U * X: 0})
    return r == 0, [f"G x - x rewrites, with u x = 0, to {r}"]


def _general_restitution():
    e = e_
    G = derive_general(restitution=True).G
    Gt = G_matrix(Ut, Wt, s_, e, identity=1)
    dT = rewrite((Qt * Gt * MM * G * Q - Qt * MM * Q) / 2, RULES)
    target = -(1 - e**2) * c_**2 / (2 * s_)
    return is_zero(dT - target), [
        "G(e) = 1 - (1+e) W U / s (derived from u q+ = -e u q-)",
        f"T+ - T- = (Q^T G^T M G Q - Q^T M Q)/2 rewrites to {sp.factor(dT)}",
    ]


def _general_restitution_one():
    r = sp.expand(derive_general(restitution=True).G.subs(e_, 1) - derive_general().G)
    return r == 0, [f"G(e)|_(e=1) - G expands to {r}"]


#: property name -> (direct proof for n = 2, 3 (called with n), structural proof for general n)
PROPERTIES: dict[str, tuple[Callable, Callable]] = {
    "G^2=I": (_direct_square, _general_square),
    "G^TMG=M": (_direct_metric, _general_metric),
    "det(G)=-1": (_direct_det, _general_det),
    "G_{alpha u}=G_u": (_direct_scale, _general_scale),
    "u.(G_u v)=-u.v": (_direct_flip, _general_flip),
    "G_u x=x on ker u": (_direct_fixes, _general_fixes),
    "Delta T=-(1-e^2)(u v)^2/(2 u M^-1 u^T)": (_direct_restitution, _general_restitution),
    "G_u(1)=G_u": (_direct_restitution_one, _general_restitution_one),
}

_METHODS = {
    "direct": "direct symbolic simplification with fully symbolic symmetric M and u "
    "(denominators cleared with w = adj(M)u^T, then polynomial expansion)",
    "n": "structural: verified rewriting in the algebra of w = M^-1 u^T, u, M "
    "(rank-one structure G = I - 2wu/(uw), determinant lemma, eigen-structure)",
}


def run_proof(name: str, dimension: int | str) -> ProofResult:
    """Prove one property for ``dimension`` 2, 3 (or any int ≥ 1) or ``"n"`` (general).

    >>> run_proof("G^2=I", 2).proven
    True
    """
    if name not in PROPERTIES:
        raise KeyError(f"unknown property {name!r}; known: {sorted(PROPERTIES)}")
    direct, general = PROPERTIES[name]
    t0 = time.perf_counter()
    if dimension == "n":
        ok, steps = general()
        method = _METHODS["n"]
    else:
        n = int(dimension)
        ok0, step0 = _step0(n)
        ok, steps = direct(n)
        ok, steps = ok and ok0, [step0, *steps]
        method = _METHODS["direct"]
    return ProofResult(name, dimension, method, bool(ok), time.perf_counter() - t0, steps)


def prove_all(dimensions=(2, 3, "n"), names=None) -> list[ProofResult]:
    """Run every property proof for every dimension (the content of ``impactsym prove``).

    With :data:`PROPERTIES` (the property names), this is the public entry point of the
    derivations for ``impactsym prove``: the only import of ``derivations`` in the package
    (``tests/test_import_layers.py``).
    """
    names = list(PROPERTIES) if names is None else list(names)
    return [run_proof(nm, d) for nm in names for d in dimensions]


# --------------------------------------------------------------------------- code generation
def _coefficient() -> sp.Expr:
    """The scalar of the rank-one term, read off the derived general-n map: ``G = 1 − c W U``."""
    G = derive_general(restitution=True).G
    c = -sp.expand(G - 1).coeff(W * U)
    return simplify(c)


#: the NumPy general-n kernels' shared text (each printed kernel carries it, so that it runs on its
#: own): the sums without the i-th term, and w = M^-1 u^T on M equilibrated by powers of two
_EXCLUDING = """            def excluding(t):  # sum_(k != i) t_k for every i (last axis): prefix + suffix sums
                zero = numpy.zeros_like(t[..., :1])
                before = numpy.concatenate([zero, numpy.cumsum(t[..., :-1], axis=-1)], axis=-1)
                after = numpy.concatenate([numpy.cumsum(t[..., :0:-1], axis=-1)[..., ::-1], zero], axis=-1)
                return before + after"""
_EQUILIBRATED = """            # w = M^-1 u^T on M equilibrated by powers of two (exact): D M D has unit-order diagonal
            # (LU's partial pivoting is not invariant under M's diagonal scaling; Cholesky, the C
            # kernel's, is); 1e17 eps on g10 without it at m_11 ~ 1e-10, m_22 ~ 1e12 (issue 15)
            d = numpy.ldexp(1.0, -(numpy.frexp(numpy.diagonal(mass_matrix, axis1=-2, axis2=-1))[1] // 2))
            w = d*numpy.linalg.solve(d[..., :, None]*mass_matrix*d[..., None, :], (d*gradient)[..., :, None])[..., 0]
            t = gradient*w
            s = numpy.sum(t, axis=-1)[..., None]
            e = restitution[..., None]
            rest = excluding(t)"""


def kernels() -> list:
    """The kernels this derivation emits (general n, and closed forms for n = 2 and 3)."""
    e, s = e_, s_
    coeff = _coefficient()  # (e + 1)/s
    if not (is_zero(coeff - (1 + e) / s)):
        raise DerivationError('derivation check failed: sp.simplify(coeff - (1 + e) / s) == 0')
    proof = general_emitted_proof()
    if not proof["proven"]:
        raise DerivationError(f"the general-n emitted forms differ from the printed map: {proof['steps']}")
    pieces = general_emitted_pieces()
    general_map = ArrayKernel(
        "reflection_map",
        f'''
        def reflection_map(mass_matrix, gradient, restitution=1.0):
            """G_u(e) = I - (1+e) w u / (u w), w = M^-1 u^T (Seghete & Murphey sec. II-A; e = 1: G_u).

            Broadcasts over leading axes: mass_matrix (..., n, n), gradient (..., n),
            restitution (...). No input checks (see impactsym.laws.reflection for those).
            The diagonal is emitted as (sum_{{k!=i}} u_k w_k - e u_i w_i)/s, the sum without u_i w_i
            taken as prefix + suffix sums (no subtraction; issue 15).
            """
{_EXCLUDING}

            mass_matrix = numpy.asarray(mass_matrix, dtype=float)
            gradient = numpy.asarray(gradient, dtype=float)
            restitution = numpy.asarray(restitution, dtype=float)
{_EQUILIBRATED}
            diag = ({pieces["diag_num"]})/({pieces["den"]})
            off = ({pieces["off_coeff_num"]})/({pieces["den"]})
            n = gradient.shape[-1]
            return numpy.where(numpy.eye(n, dtype=bool), diag[..., :, None],
                               off[..., None]*(w[..., :, None]*gradient[..., None, :]))
        ''',
    )
    general_apply = ArrayKernel(
        "reflect",
        f'''
        def reflect(mass_matrix, gradient, velocity, restitution=1.0):
            """G_u(e) v = v - (1+e) w (u v) / (u w), w = M^-1 u^T, without forming G.

            Broadcasts over leading axes: mass_matrix (..., n, n), gradient and velocity (..., n).
            Emitted as ((sum_{{k!=i}} u_k w_k - e u_i w_i) v_i - (1+e) w_i sum_{{k!=i}} u_k v_k)/s,
            each sum without the i-th term taken as prefix + suffix sums (issue 15).
            """
{_EXCLUDING}

            mass_matrix = numpy.asarray(mass_matrix, dtype=float)
            gradient = numpy.asarray(gradient, dtype=float)
            velocity = numpy.asarray(velocity, dtype=float)
            restitution = numpy.asarray(restitution, dtype=float)
{_EQUILIBRATED}
            rest_uv = excluding(gradient*velocity)
            return ({pieces["apply_num"]})/({pieces["den"]})
        ''',
    )
    cp = general_emitted_pieces("c")
    general_map.sources["c"] = C_HELPER + f"""
/* G_u(e) = I - (1+e) w u / (u w), w = M^-1 u^T (Seghete & Murphey sec. II-A; e = 1: G_u).
 * The diagonal is (sum_{{k!=i}} u_k w_k - e u_i w_i)/s, the sum without u_i w_i taken as prefix + suffix
 * sums (no subtraction; issue 15).
 * mass_matrix: n*n row-major SPD, gradient: n, G: n*n row-major output.
 * Returns 0, or -1 when the Cholesky factorization of M fails (M not positive definite). */
int reflection_map(size_t n, const double *mass_matrix, const double *gradient, double restitution, double *G)
{{
    double w[n > 0 ? n : 1];
    double rest[n > 0 ? n : 1];
    if (reflection_w(n, mass_matrix, gradient, w) != 0) {{
        return -1;
    }}
    const double s = reflection_excluding(n, gradient, w, rest);
    const double e = restitution;
    const double off = ({cp["off_coeff_num"]})/({cp["den"]});
    for (size_t i = 0; i < n; ++i) {{
        const double t = gradient[i] * w[i];
        for (size_t j = 0; j < n; ++j) {{
            G[i * n + j] = i == j ? ({cp["diag_num"]})/({cp["den"]}) : off * (w[i] * gradient[j]);
        }}
    }}
    return 0;
}}"""
    general_apply.sources["c"] = f"""
/* G_u(e) v = v - (1+e) w (u v) / (u w), w = M^-1 u^T, without forming G, emitted as
 * ((sum_{{k!=i}} u_k w_k - e u_i w_i) v_i - (1+e) w_i sum_{{k!=i}} u_k v_k)/s (issue 15).
 * mass_matrix: n*n row-major SPD; gradient, velocity, out: n. Returns 0, or -1 (M not SPD). */
int reflect(size_t n, const double *mass_matrix, const double *gradient, const double *velocity,
            double restitution, double *out)
{{
    double w[n > 0 ? n : 1];
    double rest[n > 0 ? n : 1];
    double rest_uv[n > 0 ? n : 1];
    if (reflection_w(n, mass_matrix, gradient, w) != 0) {{
        return -1;
    }}
    const double s = reflection_excluding(n, gradient, w, rest);
    (void)reflection_excluding(n, gradient, velocity, rest_uv);
    const double e = restitution;
    for (size_t i = 0; i < n; ++i) {{
        const double t = gradient[i] * w[i];
        out[i] = ({cp["apply_num"]})/({cp["den"]});
    }}
    return 0;
}}"""
    out = [general_map, general_apply]
    for n in (2, 3):
        M, u = symbolic_mass_matrix(n), symbolic_covector(n)
        v = symbolic_vector(n, "v")
        esym = sp.Symbol("e")
        G = printed_G(M, u, esym)
        # the printed map equals the derived one (restitution derivation), checked exactly:
        if not (_matrix_is_zero(G - derive_restitution(n).G.subs(sp.Symbol("e", nonnegative=True), esym))):
            raise DerivationError('derivation check failed: _matrix_is_zero(G - derive_restitution(n).G.subs(sp.Symbol("e", nonnegative=True), esym))')
        margs = [M[i, j] for i in range(n) for j in range(i, n)]
        args = margs + list(u) + [esym]
        G, Gv = stable_G(M, u, v, esym)
        if not (_matrix_is_zero(G - printed_G(M, u, esym)) and _matrix_is_zero(Gv - printed_G(M, u, esym) * v)):
            raise DerivationError('derivation check failed: _matrix_is_zero(G - printed_G(M, u, esym)) and _matrix_is_zero(Gv - printed_G(M, u, esym) * v)')
        out.append(ScalarKernel(
            f"reflection_map_{n}", args, list(G), [f"g{i}{j}" for i in range(n) for j in range(n)],
            f"Closed-form G_u(e) for n = {n} (entries row-major), M given by its upper triangle.\n"
            "Uses adj(M): det(M) cancels from M^-1 u^T / (u M^-1 u^T).",
            defaults={"e": 1.0},
        ))
        out.append(ScalarKernel(
            f"reflect_{n}", margs + list(u) + list(v) + [esym], list(Gv), [f"w{i}" for i in range(n)],
            f"Closed-form G_u(e) v for n = {n}, M given by its upper triangle.",
            defaults={"e": 1.0},
        ))
    return out


def stable_G(M: sp.Matrix, u: sp.Matrix, v: sp.Matrix, e):
    """The emitted forms of ``G_u(e)`` and ``G_u(e) v`` (issue 15), each proved equal to the
    printed map where the kernels are built (``_matrix_is_zero`` of the difference).

    With ``w = adj(M) uᵀ`` and ``s = u w = Σ_k u_k w_k``, the diagonal ``1 − (1+e) u_i w_i / s``
    cancels when ``(1+e) u_i w_i ≈ s`` (at ``e = 0`` with ``u_i w_i`` carrying nearly all of ``s``,
    e.g. ``M = diag(1, 1e-12)``, ``u = (−1, 1)``: 1e11 eps against a condition number of 1);
    it is emitted as ``(Σ_{k≠i} u_k w_k − e u_i w_i) / s``. Likewise
    ``(G v)_i = ((Σ_{k≠i} u_k w_k − e u_i w_i) v_i − (1+e) w_i Σ_{k≠i} u_k v_k) / s``.

    Examples
    --------
    >>> M = sp.Matrix([[1, 0], [0, 2]]); u = sp.Matrix([[1, 1]]); v = sp.Matrix([1, 0])
    >>> G, Gv = stable_G(M, u, v, 0)
    >>> list(G), list(Gv)
    ([1/3, -2/3, -1/3, 2/3], [1/3, -1/3])
    """
    n = M.rows
    w = M.adjugate() * u.T
    terms = [u[k] * w[k] for k in range(n)]
    s = sum(terms)
    G = sp.zeros(n, n)
    Gv = sp.zeros(n, 1)
    for i in range(n):
        rest = sum(terms[k] for k in range(n) if k != i)
        diag = rest - e * terms[i]
        for j in range(n):
            G[i, j] = diag / s if i == j else -(1 + e) * w[i] * u[j] / s
        Gv[i] = (diag * v[i] - (1 + e) * w[i] * sum(u[k] * v[k] for k in range(n) if k != i)) / s
    return G, Gv


#: the symbols of the general-n kernels' emitted pieces, for one index i: t = u_i w_i,
#: rest = sum_{k != i} u_k w_k, rest_uv = sum_{k != i} u_k v_k, s = u w (w = M^-1 u^T)
_GEN = dict(zip(("t", "rest", "rest_uv", "e", "s", "w", "v", "u_i", "u_j", "w_j"),
                sp.symbols("t rest rest_uv e s w v u_i u_j w_j", real=True)))


#: Measured on the default corner grid (issue 15) against the alternative of reflecting in the
#: M-orthogonal coordinates (Cholesky M = L L^T, u~ = L^-1 u^T, the Euclidean map
#: I - (1+e) u~ u~^T/|u~|^2 with the same stable diagonal, then back-transformed by L^-T ... L^T):
#: that form has no cancellation in |u~|^2 but loses the exact zeros of G (u = e_0 at e = 0 gives
#: G_00 = 0 only up to rounding of the back-transform: inf eps), 9/300, 12/660, 6/75 and 12/165
#: problems on the reflect_general_2/3 and reflection_map_general_2/3 grids against 0 for this form.
def _general_emitted():
    """The general-n kernels' emitted entries as expressions of the :data:`_GEN` symbols:
    ``(diag numerator, off-diagonal coefficient numerator, G v numerator, denominator)``."""
    g = _GEN
    diag = g["rest"] - g["e"] * g["t"]
    return diag, -(g["e"] + 1), diag * g["v"] - (g["e"] + 1) * g["w"] * g["rest_uv"], g["s"]


def _excluding_symbolic(terms):
    """``sum_{k != i} terms_k`` for every ``i`` as the kernels take it: prefix sum plus suffix sum."""
    n = len(terms)
    before = [sum(terms[:i], sp.Integer(0)) for i in range(n)]
    after = [sum(terms[i + 1:][::-1], sp.Integer(0)) for i in range(n)]
    return [b + a for b, a in zip(before, after)]


@lru_cache(maxsize=None)
def general_emitted_proof(max_n: int = 6) -> dict:
    """Prove that the general-n kernels' emitted entries equal the printed map ``G_u(e)`` and
    ``G_u(e) v`` (issue 15), exactly.

    General n: with ``s = Σ_k u_k w_k`` split at ``i`` as ``s = rest + t`` (``rest = Σ_{k≠i} u_k w_k``,
    ``t = u_i w_i``) and likewise ``u v = rest_uv + u_i v_i``, the emitted diagonal
    ``(rest − e t)/s``, off-diagonal ``−(1+e)/s · w_i u_j`` and ``((rest − e t) v_i − (1+e) w_i rest_uv)/s``
    minus ``1 − (1+e) w_i u_i/s``, ``−(1+e) w_i u_j/s`` and ``v_i − (1+e) w_i (u v)/s`` are the zero
    rational function. For ``n = 1 .. max_n`` the whole matrix and vector, with the sums without the
    i-th term built as prefix + suffix sums the way the kernels build them and free ``w, u, v, e``
    (the identity does not depend on how ``w = M⁻¹uᵀ`` was obtained), minus :func:`G_matrix`'s
    ``I − (1+e) w u / s`` and its product with ``v``, are zero.

    >>> general_emitted_proof(3)["proven"]
    True
    """
    g = _GEN
    diag, off, apply, den = _general_emitted()
    e, t, w, v, ui = g["e"], g["t"], g["w"], g["v"], g["u_i"]
    s = g["rest"] + t  # the definition s = sum_k u_k w_k split at i
    split = {g["s"]: s}
    at_t = {t: ui * w}
    checks = {
        "diagonal": is_zero(((diag / den).xreplace(split) - (1 - (1 + e) * t / s)).xreplace(at_t)),
        "off-diagonal": is_zero((off / den * w * g["u_j"]).xreplace(split) - (-(1 + e) * w * g["u_j"] / s)),
        "G v": is_zero(((apply / den).xreplace(split)
                        - (v - (1 + e) * w * (g["rest_uv"] + ui * v) / s)).xreplace(at_t)),
    }
    steps = [f"general n, {k}: emitted minus printed is 0: {ok}" for k, ok in checks.items()]
    for n in range(1, max_n + 1):
        wv, uv, vv = symbolic_vector(n, "w"), symbolic_covector(n), symbolic_vector(n, "v")
        terms = [uv[k] * wv[k] for k in range(n)]
        ssum = sum(terms, sp.Integer(0))
        rest, rest_uv = _excluding_symbolic(terms), _excluding_symbolic([uv[k] * vv[k] for k in range(n)])
        G = sp.zeros(n, n)
        Gv = sp.zeros(n, 1)
        for i in range(n):
            sub = {g["rest"]: rest[i], g["t"]: terms[i], g["s"]: ssum, g["w"]: wv[i], g["v"]: vv[i],
                   g["rest_uv"]: rest_uv[i]}
            for j in range(n):
                G[i, j] = (diag / den).xreplace(sub) if i == j else (off / den).xreplace(sub) * wv[i] * uv[j]
            Gv[i] = (apply / den).xreplace(sub)
        printed = G_matrix(wv, uv, ssum, e)
        ok = _matrix_is_zero(G - printed) and _matrix_is_zero(Gv - printed * vv)
        checks[f"n = {n}"] = ok
        steps.append(f"n = {n}: the emitted G and G v (prefix + suffix sums) minus I - (1+e) w u/s: 0: {ok}")
    return {"proven": all(checks.values()), "steps": steps}


def general_emitted_pieces(lang: str = "numpy") -> dict:
    """The printed pieces of the general-n kernels (``numpy`` or ``c`` names), from the expressions
    :func:`general_emitted_proof` proves equal to the printed map.

    >>> general_emitted_pieces("c")["diag_num"]
    '-e*t + rest[i]'
    """
    g = _GEN
    diag, off, apply, den = _general_emitted()
    if lang == "numpy":
        names, printer = {"v": "velocity"}, numpy_code
    else:
        names = {"rest": "rest[i]", "rest_uv": "rest_uv[i]", "w": "w[i]", "v": "velocity[i]"}
        printer = _ccode
    sub = {g[k]: sp.Symbol(names.get(k, k), real=True) for k in ("t", "rest", "rest_uv", "e", "s", "w", "v")}
    return {"diag_num": printer(diag.xreplace(sub)), "off_coeff_num": printer(off.xreplace(sub)),
            "apply_num": printer(apply.xreplace(sub)), "den": printer(den.xreplace(sub))}


def _ccode(expr) -> str:
    from .codegen import kernel_code, ScalarKernel as _SK

    return kernel_code(_SK("c", sorted(expr.free_symbols, key=str), [expr], ["o"], "c"), "c").split("*o = ")[1].split(";")[0]


#: the general-n C kernels' shared steps: w = M^-1 u^T by Cholesky, M = L L^T (y = L^-1 u^T,
#: w = L^-T y; a pivot is refused only when it is not positive, so every M with positive pivots in
#: floating point is accepted: the corner grid's SPD M of condition 1e12 is, and so are the same
#: family's up to 1e16), and the sums without the i-th term of the stable form (prefix + suffix;
#: s = u w is their full sum, as in the NumPy kernel). Measured against LU (numpy.linalg.solve)
#: on SPD matrices with condition numbers up to 1e12: the same accuracy (benchmarks/README.md).
C_HELPER = """
/* w = M^-1 u for an n x n SPD M (row-major), by Cholesky M = L L^T: y = L^-1 u, w = L^-T y.
 * Returns -1 when a pivot is not positive (no tolerance: any M whose pivots are positive in
 * floating point is accepted). */
static int reflection_w(size_t n, const double *M, const double *u, double *w)
{
    double L[n > 0 ? n * n : 1];
    if (n == 0) {
        return -1;
    }
    for (size_t j = 0; j < n; ++j) {
        double d = M[j * n + j];
        for (size_t k = 0; k < j; ++k) {
            d -= L[j * n + k] * L[j * n + k];
        }
        if (!(d > 0.0)) {
            return -1;
        }
        L[j * n + j] = sqrt(d);
        for (size_t i = j + 1; i < n; ++i) {
            double t = M[i * n + j];
            for (size_t k = 0; k < j; ++k) {
                t -= L[i * n + k] * L[j * n + k];
            }
            L[i * n + j] = t / L[j * n + j];
        }
    }
    for (size_t i = 0; i < n; ++i) {
        double t = u[i];
        for (size_t k = 0; k < i; ++k) {
            t -= L[i * n + k] * w[k];
        }
        w[i] = t / L[i * n + i];
    }
    for (size_t ii = n; ii-- > 0;) {
        double t = w[ii];
        for (size_t k = ii + 1; k < n; ++k) {
            t -= L[k * n + ii] * w[k];
        }
        w[ii] = t / L[ii * n + ii];
    }
    return 0;
}

/* rest[i] = sum_{k != i} a_k b_k as prefix + suffix sums (no subtraction); returns sum_k a_k b_k. */
static double reflection_excluding(size_t n, const double *a, const double *b, double *rest)
{
    double acc = 0.0;
    for (size_t i = 0; i < n; ++i) {
        rest[i] = acc;
        acc += a[i] * b[i];
    }
    double after = 0.0;
    for (size_t ii = n; ii-- > 0;) {
        rest[ii] += after;
        after += a[ii] * b[ii];
    }
    return acc;
}
"""


MODULE_DOC = """Single-impact reflection and Newton-restitution maps (Seghete & Murphey sec. II-A).

G_u(e) = I - (1+e) M^-1 u^T u / (u M^-1 u^T); e = 1 is the elastic reflection G_u.
"""


def generate(outdir) -> list[Path]:
    """Write ``reflection.py`` into ``outdir`` (the committed copy lives in ``impactsym/kernels``)."""
    path = Path(outdir) / "reflection.py"
    path.write_text(render_family("reflection", "reflection", MODULE_DOC, kernels()))
    return [path]
