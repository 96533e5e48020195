"""Closed forms of the 3-ball chain (Acary & Taha sec. 3.3, eqs. 13–18), derived from the general law.

Nothing here is typed from the paper: every closed form is the general impulse-ratio quadratic
(:func:`derivations.impulse_ratio.general_quadratic`, eq. 38) applied to the chain scene
(:func:`impactsym.models.acary_taha.chain3`, eqs. 13–14), then recomposed as

    p₁ = (−B + √Δ) / (2A),   p₂ = α p₁,   q̇⁺ = q̇⁻ + p₁ M⁻¹Hᵀ(1, α)ᵀ,

with ``A``, ``B``, ``C`` and the discriminant ``Δ = B² − 4AC`` read off the derived quadratic.
The paper's printed eq. 18 is kept only as a *transcription* (:func:`printed_eq18`) so that the
two can be compared (:func:`compare_eq18`).

Quantity names (stable; the paper-audit helper keys on them)
-------------------------------------------------------------
``"A"``, ``"B"``, ``"C"``  coefficients of ``A p₁² + B p₁ + C = 0``
``"Delta"``                the discriminant ``B² − 4AC`` (the paper's Δ for the unit-speed chain)
``"p1"``, ``"p2"``         impulses at contacts 1–2 and 2–3
``"q1+"``, ``"q2+"``, ``"q3+"``  post-impact velocities of balls 1, 2, 3

Results are cached (``functools.lru_cache``): the returned dicts are shared, copy before
modifying.

Findings against the print (proved in :func:`compare_eq18` and the tests)
--------------------------------------------------------------------------
* eq. 18, ``q̇₃⁺``: printed ``−(1+√Δ)α / (2(1−α+α²))``, derived ``+(1+√Δ)α / (2(1−α+α²))``
  (sign misprint). Proof: momentum ``Σ m q̇ᵢ⁺ = m`` holds for the derived value and fails for the
  printed one (``Σ = 1 − (1+√Δ)α/(1−α+α²) ≠ 1`` for ``α > 0``); also eq. 13's third line,
  ``m(q̇₃⁺ − 0) = p₂ ≥ 0``, forbids a negative ``q̇₃⁺``.
* every other entry of eq. 18 (``p₁``, ``p₂``, ``q̇₁⁺``, ``q̇₂⁺``, ``Δ``) equals the derived form.
* eq. 17 and eq. 12 read ``½ q̇⁺ᵀMq̇⁺ = e q̇⁻ᵀMq̇⁻`` without ½ on the right in eq. 12; eq. 17 (no
  ½ on either side) is the reading used here, ``T⁺ = e T⁻`` (``CONVENTIONS.md``).

Examples
--------
>>> cf = chain3_equal_masses()
>>> cf["Delta"]
2*alpha**2*e - 2*alpha**2 - 2*alpha*e + 2*alpha + 2*e - 1
>>> cf["p1"]
m*(sqrt(2*alpha**2*e - 2*alpha**2 - 2*alpha*e + 2*alpha + 2*e - 1) + 1)/(2*(alpha**2 - alpha + 1))
>>> {k: v for k, v in compare_eq18().items() if not v}
{'q3+': False}
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import sympy as sp

from .memo import simplify
from .rational_zero import is_zero_rational_function
from impactsym.models.acary_taha import chain3

from .codegen import ScalarKernel, render_family
from .impulse_ratio import QuadraticLaw, general_quadratic, on_energy_line
from .rational_zero import is_zero_rational_function

from impactsym.errors import DerivationError

__all__ = [
    "SYMBOLS",
    "chain3_law",
    "closed_form",
    "chain3_equal_masses",
    "chain3_general",
    "printed_eq18",
    "compare_eq18",
    "momentum_energy_residuals",
    "stable_root",
    "kernels",
    "generate",
]

alpha, e, m = sp.symbols("alpha e m", positive=True)
m1, m2, m3 = sp.symbols("m1 m2 m3", positive=True)
v1, v2, v3 = sp.symbols("v1 v2 v3", real=True)

#: the symbols the closed forms are written in (``alpha`` = α = p₂/p₁, ``e`` the energetic coefficient)
SYMBOLS = {"alpha": alpha, "e": e, "m": m, "m1": m1, "m2": m2, "m3": m3, "v1": v1, "v2": v2, "v3": v3}

VELOCITY_NAMES = ("q1+", "q2+", "q3+")


def chain3_law(masses=(m, m, m), velocities=(1, 0, 0), ratio=alpha, restitution=e) -> QuadraticLaw:
    """The general quadratic (eq. 38) for the chain scene with the given masses and velocities.

    Parameters
    ----------
    masses, velocities : three numbers or SymPy symbols each (default: equal masses ``m``,
        ``q̇⁻ = (1, 0, 0)`` as in sec. 3.2)
    ratio : the impulse ratio α = p₂/p₁ (eq. 17)
    restitution : the energetic coefficient e (eq. 12/17)

    Returns
    -------
    QuadraticLaw

    Examples
    --------
    >>> sp.factor(chain3_law().A)
    (alpha**2 - alpha + 1)/m

    References
    ----------
    Acary & Taha, eqs. 13, 17, 38.
    """
    sc = chain3(masses, velocities)
    return on_energy_line(general_quadratic(sc.M, sc.H, sc.v, restitution, [ratio]), sc.M, sc.v, restitution)


def closed_form(scene, law: QuadraticLaw, velocity_names, impulse_names=None) -> dict:
    """Recompose a derived law into readable closed forms keyed by quantity name.

    ``p₁ = (−B + √Δ)/(2A)`` with ``A`` factored and ``Δ`` expanded; ``p_j = α₁ⱼ p₁``; each
    post-impact velocity is ``v⁻ᵢ + cᵢ p₁`` with ``c = M⁻¹Hᵀa`` (entries factored). This equals
    the law's own ``p`` and ``v⁺`` by construction; the tests check it symbolically.

    Parameters
    ----------
    scene : the :class:`impactsym.scenes.Scene` the law was derived for (``M``, ``H``, ``v⁻``)
    law : QuadraticLaw from :func:`derivations.impulse_ratio.general_quadratic` on that scene
    velocity_names : names of the post-impact velocity components, in coordinate order
    impulse_names : names of the impulses (default ``p1, p2, ...``)

    Returns
    -------
    dict
        ``{"A", "B", "C", "Delta", impulse names..., velocity names...}``

    Examples
    --------
    >>> sc = chain3((1, 1, 1), (1, 0, 0))
    >>> law = general_quadratic(sc.M, sc.H, sc.v, 1, [sp.Rational(1, 2)])
    >>> closed_form(sc, law, VELOCITY_NAMES)["q3+"]
    2/3
    """
    A = sp.factor(law.A)
    B = simplify(law.B)
    C = sp.factor(law.C)
    Delta = sp.expand(law.D)
    p1 = (-B + sp.sqrt(Delta)) / (2 * A)
    out = {"A": A, "B": B, "C": C, "Delta": Delta}
    names = impulse_names or [f"p{i + 1}" for i in range(len(law.ratios))]
    for name, r in zip(names, law.ratios):
        out[name] = p1 if r == 1 else sp.factor(r) * p1
    direction = scene.M.LUsolve(scene.H.T * law.ratios)
    for name, vm, c in zip(velocity_names, scene.v, direction):
        c = sp.factor(simplify(c))
        out[name] = simplify(vm) + c * p1 if c != 0 else simplify(vm)
    return out


@lru_cache(maxsize=None)
def chain3_equal_masses() -> dict:
    """Eq. 18 derived: equal masses ``m``, ``q̇⁻ = (1, 0, 0)``, ratio α, coefficient e.

    Returns
    -------
    dict
        keys ``A, B, C, Delta, p1, p2, q1+, q2+, q3+`` (see the module docstring).

    Examples
    --------
    >>> cf = chain3_equal_masses()
    >>> cf["q3+"]
    alpha*(sqrt(2*alpha**2*e - 2*alpha**2 - 2*alpha*e + 2*alpha + 2*e - 1) + 1)/(2*(alpha**2 - alpha + 1))

    References
    ----------
    Acary & Taha, eqs. 13, 17, 18.
    """
    sc = chain3((m, m, m), (1, 0, 0))
    # checked against the energy line T⁺ = eT⁻ before any closed form is built
    law = on_energy_line(general_quadratic(sc.M, sc.H, sc.v, e, [alpha]), sc.M, sc.v, e)
    return closed_form(sc, law, VELOCITY_NAMES)


@lru_cache(maxsize=None)
def chain3_general() -> dict:
    """The chain with unequal masses ``m1, m2, m3`` and any pre-impact velocities ``v1, v2, v3``.

    Returns
    -------
    dict
        keys ``A, B, C, Delta, p1, p2, q1+, q2+, q3+``; ``B = (v2 − v1) + α (v3 − v2)`` is the
        ratio-weighted relative velocity (approaching along ``(1, α)`` when ``B < 0``).

    Examples
    --------
    >>> g = chain3_general()
    >>> g["A"]
    (alpha**2*m1*m2 + alpha**2*m1*m3 - 2*alpha*m1*m3 + m1*m3 + m2*m3)/(2*m1*m2*m3)
    >>> g["B"]
    -alpha*v2 + alpha*v3 - v1 + v2

    References
    ----------
    Acary & Taha, eqs. 13, 17 (generalized), 38.
    """
    sc = chain3((m1, m2, m3), (v1, v2, v3))
    law = on_energy_line(general_quadratic(sc.M, sc.H, sc.v, e, [alpha]), sc.M, sc.v, e)
    out = closed_form(sc, law, VELOCITY_NAMES)
    out["B"] = sp.expand(out["B"])
    out["Delta"] = sp.factor(sp.cancel(out["Delta"]))
    return out


def printed_eq18():
    """TRANSCRIPTION of the paper's printed eq. 18 (for comparison only; never used to compute).

    Returns
    -------
    dict with keys ``p1, p2, q1+, q2+, q3+, Delta`` as printed (``m`` the common mass).

    Examples
    --------
    >>> printed_eq18()["q3+"]
    alpha*(-sqrt(2*alpha**2*e - 2*alpha**2 - 2*alpha*e + 2*alpha + 2*e - 1) - 1)/(2*alpha**2 - 2*alpha + 2)
    """
    Delta = -1 + 2 * e - 2 * alpha * e + 2 * alpha + 2 * alpha**2 * e - 2 * alpha**2
    den = 2 * (1 - alpha + alpha**2)
    s = 1 + sp.sqrt(Delta)
    return {
        "p1": s * m / den,
        "p2": s * m * alpha / den,
        "q1+": -s / den + 1,
        "q2+": -s * (alpha - 1) / den,
        "q3+": -s * alpha / den,
        "Delta": Delta,
    }


def compare_eq18() -> dict:
    """For each quantity of eq. 18: does the derived closed form equal the transcription?

    Equality is decided exactly: ``Δ`` is a polynomial (expanded difference), the others are
    rational in ``√Δ`` (``√Δ`` replaced by a fresh symbol ``s``, then the difference cancelled),
    so a ``True`` is an identity in ``α, e, m`` and a ``False`` a non-identity.

    Examples
    --------
    >>> compare_eq18()
    {'p1': True, 'p2': True, 'q1+': True, 'q2+': True, 'q3+': False, 'Delta': True}
    """
    derived, printed = chain3_equal_masses(), printed_eq18()
    return {k: _identical(derived[k], printed[k], derived["Delta"]) for k in printed}


def _identical(a, b, Delta) -> bool:
    from .pool import _sqrt_delta_to_symbol

    d = _sqrt_delta_to_symbol(sp.sympify(a) - sp.sympify(b), Delta)
    # a rational function (√Δ a symbol): its numerator decided by flint; SymPy's cancel otherwise
    zero = is_zero_rational_function(d)
    return zero if zero is not None else sp.cancel(sp.together(d)) == 0


def momentum_energy_residuals(velocities: dict, masses=(m, m, m), vminus=(1, 0, 0)) -> dict:
    """Momentum and energy residuals of a post-impact state: ``Σmᵢq̇ᵢ⁺ − Σmᵢq̇ᵢ⁻`` and
    ``T⁺ − e T⁻`` (simplified). Used to prove the eq. 18 misprint.

    Examples
    --------
    >>> r = momentum_energy_residuals(printed_eq18())
    >>> sp.factor(r["momentum"])
    -alpha*m*(sqrt(2*alpha**2*e - 2*alpha**2 - 2*alpha*e + 2*alpha + 2*e - 1) + 1)/(alpha**2 - alpha + 1)
    >>> momentum_energy_residuals(chain3_equal_masses())
    {'momentum': 0, 'energy': 0}
    """
    qp = [velocities[k] for k in VELOCITY_NAMES]
    mom = sum(mi * (q - v) for mi, q, v in zip(masses, qp, vminus))
    en = sum(mi * q**2 for mi, q in zip(masses, qp)) / 2 - e * sum(mi * v**2 for mi, v in zip(masses, vminus)) / 2
    return {"momentum": _simplified(mom), "energy": _simplified(sp.expand(en))}


def _simplified(x):
    """``simplify(x)``, or 0 at once when the exact zero test proves ``x`` zero (what simplify
    returns for these residuals, in milliseconds instead of a tenth of a second)."""
    from .rational_zero import is_zero_algebraic

    return sp.Integer(0) if is_zero_algebraic(x) else simplify(x)


def stable_root(A, B, C, D=None):
    """The physical root ``(−B + √D)/(2A)`` of ``A p² + B p + C``, in cancellation-free form.

    ``D = B² − 4AC`` (or the given form of it, checked equal). For ``B ≤ 0`` the two terms of ``−B + √D = |B| + √D`` have the same sign,
    so ``(|B| + √D)/(2A)`` loses nothing; for ``B > 0`` the same root is ``−2C/(|B| + √D)`` (the
    product of the roots is ``C/A``), again without cancellation. Writing ``|B|`` in both
    branches keeps the branch that is not selected free of ``0/0`` when a vectorized kernel
    evaluates both. Both branches equal ``(−B + √D)/(2A)`` on their side (proved in the tests).

    Examples
    --------
    >>> a, b, c = sp.symbols("a b c", positive=True)
    >>> stable_root(a, -b, c)
    (b + sqrt(-4*a*c + b**2))/(2*a)
    """
    if D is None:
        D = B**2 - 4 * A * C
    else:  # an emitted form of the discriminant: must be B^2 - 4AC
        if not (_zero_rational(D - (B**2 - 4 * A * C))):
            raise DerivationError(D)
    return sp.Piecewise(
        ((sp.Abs(B) + sp.sqrt(D)) / (2 * A), B <= 0),
        (-2 * C / (sp.Abs(B) + sp.sqrt(D)), True),
    )


def _zero_rational(x) -> bool:
    """``cancel(x) == 0``: decided by the flint zero test of a rational function
    (:func:`derivations.rational_zero.is_zero_rational_function`, exact) when ``x`` is one with
    rational coefficients, else by ``sympy.cancel``."""
    verdict = is_zero_rational_function(x)
    return sp.cancel(x) == 0 if verdict is None else verdict


def emitted_coefficients():
    """``(A, B, C)`` of the chain's quadratic in the form the kernel evaluates, each proved equal
    to the derived coefficient of :func:`chain3_general` (``cancel(emitted − derived) == 0``,
    asserted here, every time).

    The derived ``A`` expands ``m1 m3 (1 − α)²``; in floats that cancels as ``α → 1`` when
    ``m2 ≪ m1, m3`` (issue 15: ``p1`` wrong in the 5th digit at masses ``(1, 1e-12, 1)``,
    ``α = 1 − 1e-12``). The emitted ``A`` keeps a sum of non-negative terms,
    ``(m1 m3 (1 − α)² + m2 (m3 + α² m1)) / (2 m1 m2 m3)``, with ``1 − α`` exact (Sterbenz) near 1;
    ``B`` keeps the velocity differences, ``(v2 − v1) + α (v3 − v2)`` (the expanded
    ``α v3 − α v2`` cancels at large ``α`` when ``v2 ≈ v3``); ``C = (1 − e)(m1 v1² + m2 v2² + m3 v3²)/2``.

    Examples
    --------
    >>> A, B, C = emitted_coefficients()
    >>> B
    alpha*(-v2 + v3) - v1 + v2
    """
    g = chain3_general()
    one_minus_alpha = 1 - alpha
    A = (m1 * m3 * one_minus_alpha**2 + m2 * (m3 + alpha**2 * m1)) / (2 * m1 * m2 * m3)
    B = (v2 - v1) + alpha * (v3 - v2)
    C = (1 - e) * (m1 * v1**2 + m2 * v2**2 + m3 * v3**2) / 2
    for emitted, derived in ((A, g["A"]), (B, g["B"]), (C, g["C"])):
        if not (_zero_rational(emitted - derived)):
            raise DerivationError((emitted, derived))
    return A, B, C


def emitted_discriminant():
    """The discriminant ``D = B² − 4AC`` as the kernel evaluates it, proved equal (asserted).

    With ``x = M^(−1/2) Hᵀ(1, α)ᵀ`` and ``y = M^(1/2) v``: ``2A = |x|²``, ``B = x·y`` and
    ``2C = (1 − e)|y|²``, so by Lagrange's identity ``|x|²|y|² − (x·y)² = |x ∧ y|²``,
    ``D = e B² − (1 − e) Σ_{i<j} (c_i m_j v_j − c_j m_i v_i)² / (m_i m_j)`` with ``c = (−1, 1 − α, α)``:
    a non-negative term minus a sum of squares, exact in both corners (``D = B²`` at ``e = 1``,
    ``D = −|x ∧ y|²`` at ``e = 0``). The expanded ``B² − 4AC`` cancels to
    rounding noise when ``4AC ≈ B²`` although the exact ``D`` is of order ``B²`` relative to neither
    (at ``e = 0``, masses ``(1e-12, 1e-12, 1e12)``, ``α = 1``: exact ``D = −1e-24``, float ``0``, a
    number where no solution exists); here the sign of ``D`` is decided to within rounding of its
    own terms, and ``D < 0`` identically at ``e = 0`` (unless ``x ∥ y``).

    Examples
    --------
    >>> emitted_discriminant().subs({m1: 1, m2: 1, m3: 1, v1: 1, v2: 0, v3: 0, e: 0, alpha: 1})
    -1
    """
    A, B, C = emitted_coefficients()
    c = (-1, 1 - alpha, alpha)
    ms, vs = (m1, m2, m3), (v1, v2, v3)
    wedge = sum((c[i] * ms[j] * vs[j] - c[j] * ms[i] * vs[i]) ** 2 / (ms[i] * ms[j])
                for i in range(3) for j in range(i + 1, 3))
    D = e * B**2 - (1 - e) * wedge
    if not (_zero_rational(D - (B**2 - 4 * A * C))):
        raise DerivationError('derivation check failed: sp.cancel(D - (B**2 - 4 * A * C)) == 0')
    return D


def _emitted_w3(A, B, D, p1):
    """``w3 = v3 + α p1 / m3`` as the kernel evaluates it (asserted equal on each branch).

    On the approach branch (``B ≤ 0``, ``p1 = (|B| + √D)/(2A)``) the sum cancels when ball 3 is
    light and bounces back slowly (found by the search: masses ``(1, 1e12, 1e-12)``, ``v3 = −1``,
    ``e = 1.6e-4``: ``−1 + 1.012``, 78 eps against a condition number of 1.7). There
    ``w3 = (N + α√D) / (2A m3)`` with ``N = 2A m3 v3 + α|B| = m3 v3 ((1 − α)²/m2 + 1/m1) + α(v1 − (1 − α) v2)``,
    whose terms are products of the data (no ``v3 + α|B|/(2A m3)`` difference).
    """
    N = m3 * v3 * ((1 - alpha) ** 2 / m2 + 1 / m1) + alpha * (v1 - (1 - alpha) * v2)
    r = sp.Symbol("r", positive=True)
    if not (_zero_rational(N - (2 * A * m3 * v3 - alpha * B))):  # |B| = -B on this branch
        raise DerivationError('derivation check failed: sp.cancel(N - (2 * A * m3 * v3 - alpha * B)) == 0')
    approach = (N + alpha * sp.sqrt(D)) / (2 * A * m3)
    if not (_zero_rational((N + alpha * r) / (2 * A * m3) - (v3 + alpha * (-B + r) / (2 * A * m3)))):
        raise DerivationError('derivation check failed: sp.cancel((N + alpha * r) / (2 * A * m3) - (v3 + alpha * (-B + r) / (2 * A * m3))) == 0')
    (_, cond1), (leave, _) = p1.args
    return sp.Piecewise((approach, cond1), (v3 + alpha * leave / m3, True))


MODULE_DOC = """Impulse-ratio law for the 3-ball chain (Acary & Taha sec. 3.3, eqs. 13-18), general masses
and pre-impact velocities; the physical root in cancellation-free form ((|B| + sqrt(D))/(2A) for
B <= 0, -2C/(|B| + sqrt(D)) for B > 0)."""


def kernels():
    """The chain3 family: ``chain3_impulse_ratio`` and the eq. 19 boundary ``chain3_alpha_max``.

    Examples
    --------
    >>> [k.name for k in kernels()]
    ['chain3_impulse_ratio', 'chain3_alpha_max']
    """
    g = chain3_general()
    sc = chain3((m1, m2, m3), (v1, v2, v3))
    c = sc.M.LUsolve(sc.H.T * sp.Matrix([1, alpha]))
    A, B, C = emitted_coefficients()
    D = emitted_discriminant()
    p1 = stable_root(A, B, C, D)
    w = [vi + sp.factor(ci) * p1 for vi, ci in zip((v1, v2, v3), c)]
    w[2] = _emitted_w3(A, B, D, p1)
    law_kernel = ScalarKernel(
        "chain3_impulse_ratio",
        [m1, m2, m3, v1, v2, v3, e, alpha],
        [p1, alpha * p1, *w],
        ["p1", "p2", "w1", "w2", "w3"],
        """The impulse-ratio law on the 3-ball chain (Acary & Taha eqs. 13, 17, 38), any masses
and pre-impact velocities: p = p1 (1, alpha), w = post-impact velocities.

p1 is the physical root (-B + sqrt(D))/(2A) of A p1^2 + B p1 + C = 0, evaluated without
cancellation: (|B| + sqrt(D))/(2A) for B <= 0, -2C/(|B| + sqrt(D)) for B > 0. D < 0 (no solution) gives nan. No admissibility check: see
impactsym.domains.validity_domain and the impulse-ratio law for those.

Precondition: masses, velocities and momenta m_i v_j whose squares are normal floats (each |x|
and each |m_i v_j| zero or in [1e-150, 1e150]). Squares that underflow make D = B^2 - 4AC round
to 0 when it is exactly negative (found by Hypothesis with v3 = 6.8e-272, alpha = 0), and with
every mass and velocity at 1e-90 (momenta 1e-180, squared 1e-360) the outputs were 10% off. The
law is homogeneous: p scales with the masses (w does not), p and w with the velocities, so rescale
them first when they are that extreme (by powers of two the outputs scale exactly).
""",
    )
    from .domains import chain3_alpha_max_expr

    amax = ScalarKernel(
        "chain3_alpha_max",
        [e],
        [chain3_alpha_max_expr()],
        ["alpha_max"],
        """Upper end of the chain's admissible impulse ratios at energetic coefficient e
(eq. 19, 1/3 <= e <= 1): alpha_max(e) = (2e - 2 - sqrt(6e - 2))/(e - 3).
""",
    )
    return [law_kernel, amax]


def generate(outdir) -> list[Path]:
    """Write ``chain3.py`` (the kernels) and ``chain3_naive.py`` (the naive form the benchmark
    compares against) into ``outdir`` (``python -m derivations``)."""
    path = Path(outdir) / "chain3.py"
    path.write_text(render_family("chain3", "chain3", MODULE_DOC, kernels()))
    from .codegen import render_expressions

    naive = Path(outdir) / NAIVE_FILE
    naive.write_text(render_expressions("chain3", "chain3", NAIVE_DOC, naive_impulse_ratio()))
    return [path, naive]


NAIVE_FILE = "chain3_naive.py"
NAIVE_DOC = """The 3-ball chain's impulse-ratio law in its naive form: the quadratic formula
p1 = (-B + sqrt(B^2 - 4AC))/(2A) with the derived coefficients, no stable form, no CSE. Read by
impactsym.bench (its lambdify-naive backend), never by a law."""


def naive_impulse_ratio() -> dict:
    """The chain's law as the textbook quadratic formula (what a naive implementation evaluates):
    ``{"args": ([m1, m2, m3, v1, v2, v3, e, alpha], ...), "outputs": ([p1, p2, w1, w2, w3], ...)}``,
    written to ``impactsym/kernels/chain3_naive.py``.

    Examples
    --------
    >>> d = naive_impulse_ratio()
    >>> [str(a) for a in d["args"][0]]
    ['m1', 'm2', 'm3', 'v1', 'v2', 'v3', 'e', 'alpha']
    """
    g = chain3_general()
    sc = chain3((m1, m2, m3), (v1, v2, v3))
    c = sc.M.LUsolve(sc.H.T * sp.Matrix([1, alpha]))
    p1 = (-g["B"] + sp.sqrt(g["B"] ** 2 - 4 * g["A"] * g["C"])) / (2 * g["A"])
    w = [vi + ci * p1 for vi, ci in zip((v1, v2, v3), c)]
    return {"args": ([m1, m2, m3, v1, v2, v3, e, alpha], "the kernel chain3_impulse_ratio's arguments"),
            "outputs": ([p1, alpha * p1, *w], "p1, p2, w1, w2, w3 by the quadratic formula")}
