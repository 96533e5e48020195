"""The impulse-ratio law (Acary & Taha eq. 38): exact values, every violated condition, the
float path against 50-digit mpmath references, and Hypothesis properties on random scenes."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from derivations.impulse_ratio import general_coefficients_proof, general_quadratic, physical_root_proof
from impactsym.errors import DomainError, ImpactInputError
from impactsym.exact import certified_sign
from impactsym.laws.impulse_ratio import impulse_ratio_law
from impactsym.models.acary_taha import chain3, pool

I3 = "1,0,0;0,1,0;0,0,1"
H_CHAIN = "-1,1,0;0,-1,1"


def zero(x) -> bool:
    return certified_sign(sp.sympify(x)) == 0


# ----------------------------------------------------------------------------- exact values

def test_chain_alpha_half_is_newton_solution():
    r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", 1, ["1/2"])
    assert r.exact and r.valid and r.violations == []
    assert list(r.velocity) == [sp.Rational(-1, 3), sp.Rational(2, 3), sp.Rational(2, 3)]
    assert list(r.impulses) == [sp.Rational(4, 3), sp.Rational(2, 3)]


def test_chain_alpha_one_e_one_gives_0_0_1():
    # sec. 3.3: "[0, 0, 1] is encompassed by setting alpha = 1 and e = 1"
    r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", 1, ["1"])
    assert list(r.velocity) == [0, 0, 1] and list(r.impulses) == [1, 1]


def test_chain_delta_is_papers_delta():
    # eq. 18: Delta = -1 + 2e - 2 alpha e + 2 alpha + 2 alpha^2 e - 2 alpha^2 (transcription); B = -1 here
    for alpha, e in [("1/2", "1/3"), ("3/4", "9/10"), ("2", "1"), ("1", "1/2")]:
        a, ee = sp.Rational(alpha), sp.Rational(e)
        printed = -1 + 2 * ee - 2 * a * ee + 2 * a + 2 * a**2 * ee - 2 * a**2
        r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", e, [alpha], allow_invalid=True)
        assert r.coefficients[1] == -1
        assert r.delta == printed and r.delta_normalized == printed


def test_chain_delta_scales_with_speed():
    # D is in units of B^2; the normalized Delta does not depend on the approach speed
    r1 = impulse_ratio_law(I3, H_CHAIN, "1,0,0", "1/2", ["3/4"])
    r3 = impulse_ratio_law(I3, H_CHAIN, "3,0,0", "1/2", ["3/4"])
    assert r3.delta == 9 * r1.delta and r3.delta_normalized == r1.delta_normalized
    assert list(r3.velocity) == [3 * x for x in r1.velocity]


def test_chain_p_matches_printed_eq18():
    # eq. 18 (transcription, m = 1): p1 = (1 + sqrt(Delta)) / (2 (1 - alpha + alpha^2))
    a, e = sp.symbols("alpha e", positive=True)
    law = general_quadratic(sp.eye(3), chain3().H, chain3().v, e, [a])
    Delta = law.D / law.B**2
    printed_p1 = (1 + sp.sqrt(Delta)) / (2 * (1 - a + a**2))
    for av, ev in [(sp.Rational(1, 2), sp.Rational(1, 2)), (sp.Rational(9, 10), sp.Rational(3, 4))]:
        r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", ev, [av])
        assert zero(r.impulses[0] - printed_p1.subs({a: av, e: ev}))


def test_general_quadratic_agrees_with_law():
    M = sp.Matrix([[2, 1, 0], [1, 3, 1], [0, 1, 2]])
    H = sp.Matrix([[1, -1, 0], [0, 1, -2]])
    v = sp.Matrix([-1, 2, 1])
    e, ratios = sp.Rational(1, 2), [sp.Rational(1, 3)]
    law = general_quadratic(M, H, v, e, ratios)
    r = impulse_ratio_law(M, H, v, e, ratios, allow_invalid=True)
    assert (law.A, law.B, law.C) == r.coefficients and law.D == r.delta
    assert all(zero(x - y) for x, y in zip(law.p, r.impulses))
    assert all(zero(x - y) for x, y in zip(law.vplus, r.velocity))


def test_proofs_hold():
    assert physical_root_proof()["proven"]
    assert general_coefficients_proof()["proven"]


def test_pool_tau0_delta_matches_eq27():
    # eq. 27: Delta = 2 (e - 1)(alpha^2 - alpha cos(theta) + 1) + 1 (transcription)
    for th in (0, sp.pi / 6, sp.pi / 4, sp.pi / 3):
        sc = pool(th)
        for al, e in [(sp.Rational(1, 2), sp.Rational(3, 4)), (sp.Rational(2), sp.Rational(1))]:
            r = impulse_ratio_law(sc.M, sc.H, sc.v, e, [al], allow_invalid=True)
            printed = 2 * (e - 1) * (al**2 - al * sp.cos(th) + 1) + 1
            assert zero(r.delta - printed) and zero(r.coefficients[1] + 1)


def test_pool_theta0_is_the_chain():
    sc = pool(0)
    r = impulse_ratio_law(sc.M, sc.H, sc.v, "1/2", ["3/4"])
    c = impulse_ratio_law(I3, H_CHAIN, "1,0,0", "1/2", ["3/4"])
    assert [r.velocity[i] for i in (0, 2, 4)] == list(c.velocity)
    assert all(r.velocity[i] == 0 for i in (1, 3, 5))


# ----------------------------------------------------------------------- violations / domain

def test_negative_discriminant_named_and_refused():
    with pytest.raises(DomainError, match="negative-discriminant"):
        impulse_ratio_law(I3, H_CHAIN, "1,0,0", "1/10", ["1"])
    r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", "1/10", ["1"], allow_invalid=True)
    assert r.impulses is None and r.velocity is None and not r.real_solution and not r.valid
    assert r.delta == sp.Rational(-4, 5)


def test_every_violation_listed():
    # negative ratio: p_2 < 0, and the chain then penetrates at contact 2 as well
    r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", 1, ["-1"], allow_invalid=True)
    conds = [(v.condition, v.contact) for v in r.violations]
    assert ("negative-impulse", 2) in conds and ("penetration", 2) in conds
    assert list(r.impulses) == [sp.Rational(1, 3), sp.Rational(-1, 3)]  # A = 3, B = -1
    with pytest.raises(DomainError) as exc:
        impulse_ratio_law(I3, H_CHAIN, "1,0,0", 1, ["-1"])
    assert "negative-impulse: p_2 < 0" in str(exc.value) and "penetration: contact 2" in str(exc.value)


def test_no_approach_and_stable_positive_B_root():
    # ball 1 moving away: B = +1 > 0. With e < 1 the root is -2C/(B + sqrt(D)) < 0
    r = impulse_ratio_law(I3, H_CHAIN, "-1,0,0", "1/2", ["1"], allow_invalid=True)
    conds = {v.condition for v in r.violations}
    assert "no-approach" in conds and "negative-impulse" in conds
    with pytest.raises(DomainError, match="no-approach"):
        impulse_ratio_law(I3, H_CHAIN, "-1,0,0", "1/2", ["1"])


def test_boundary_is_valid_exactly():
    # eq. 19's boundary alpha = 1/2 at e = 1: v2+ = v3+ exactly (grazing after impact) is admissible
    r = impulse_ratio_law(I3, H_CHAIN, "1,0,0", 1, ["1/2"])
    assert r.velocity[1] == r.velocity[2] and r.valid


def test_zero_direction_refused():
    with pytest.raises(DomainError, match="H\\^T a = 0"):
        impulse_ratio_law("1,0;0,1", "1,0;1,0", "-1,0", 1, ["-1"], allow_invalid=True)


@pytest.mark.parametrize(
    "args, match",
    [
        (("1,2;2,1", "1,0", "-1,0", 1, None), "not positive definite"),
        (("1,0;1,1", "1,0", "-1,0", 1, None), "not symmetric"),
        (("1,0;0,1", "0,0", "-1,0", 1, None), "zero covector"),
        (("1,0;0,1", "1,0,0", "-1,0", 1, None), "columns"),
        (("1,0;0,1", "1,0", "-1,0,0", 1, None), "length 3"),
        (("1,0;0,1", "1,0;0,1", "-1,0", 1, None), "expected 1 ratio"),
        (("1,0;0,1", "1,0;0,1", "-1,0", 1, ["1", "2"]), "expected 1 ratio"),
        (("1,0;0,1", "1,0;0,1", "-1,0", 1, ["nan"]), "finite"),
    ],
)
def test_bad_input(args, match):
    with pytest.raises(ImpactInputError, match=match):
        impulse_ratio_law(*args)


@pytest.mark.parametrize("e", ["-1/10", "11/10"])
def test_restitution_out_of_range(e):
    with pytest.raises(DomainError, match="restitution"):
        impulse_ratio_law(I3, H_CHAIN, "1,0,0", e, ["1/2"])


def test_float_nan_refused():
    with pytest.raises(ImpactInputError):
        impulse_ratio_law(np.eye(2), [[1.0, 0.0]], [float("nan"), 0.0], 1.0)
    with pytest.raises(ImpactInputError):
        impulse_ratio_law(np.eye(2), [[1.0, 0.0]], [-1.0, 0.0], float("nan"))


# ------------------------------------------------------------------------ coupling in the law

def test_coupling_sets_alpha12_zero_for_pool_theta_ge_half_pi():
    for th in (sp.pi / 2, 3 * sp.pi / 5):
        sc = pool(th)
        r = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["1/2"], coupling=True)
        assert r.ratios[1] == 0 and r.impulses[1] == 0
        assert r.coupling and r.coupling[0]["ratio"] == "alpha_12" and r.coupling[0]["equation"] == "43"
        # without coupling the ratio is kept (and the result is formally admissible: eq. 43 is needed)
        r2 = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["1/2"], allow_invalid=True)
        assert r2.ratios[1] == sp.Rational(1, 2)


def test_coupling_keeps_coupled_ratio_and_needs_it():
    sc = pool(sp.pi / 4)
    r = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["1/2"], coupling=True)
    assert r.ratios[1] == sp.Rational(1, 2) and r.coupling == []
    with pytest.raises(ImpactInputError, match="alpha_12 is needed"):
        impulse_ratio_law(sc.M, sc.H, sc.v, 1, None, coupling=True)
    # a decoupled ratio need not be given
    sc = pool(sp.pi / 2)
    assert impulse_ratio_law(sc.M, sc.H, sc.v, 1, None, coupling=True).ratios[1] == 0


# --------------------------------------------------------------------- float path vs mpmath

def mp_reference(M, H, v, e, ratios, dps=50):
    with mpmath.workdps(dps):
        Mm = mpmath.matrix([[mpmath.mpf(float(x)) for x in row] for row in M])
        Hm = mpmath.matrix([[mpmath.mpf(float(x)) for x in row] for row in H])
        vm = mpmath.matrix([mpmath.mpf(float(x)) for x in v])
        a = mpmath.matrix([mpmath.mpf(1)] + [mpmath.mpf(float(x)) for x in ratios])
        r = Hm.T * a
        w = mpmath.lu_solve(Mm, r)
        A = (r.T * w)[0] / 2
        B = (a.T * (Hm * vm))[0]
        C = (1 - mpmath.mpf(float(e))) * (vm.T * Mm * vm)[0] / 2
        D = B * B - 4 * A * C
        p1 = (-B + mpmath.sqrt(D)) / (2 * A)
        return [p1 * x for x in a], [vm[i] + p1 * w[i] for i in range(len(vm))], D


def rel_err(x, ref):
    scale = max(abs(r) for r in ref)
    return max(abs(mpmath.mpf(float(a)) - b) for a, b in zip(x, ref)) / scale


@pytest.mark.parametrize("seed", range(20))
def test_float_path_matches_50_digit_reference(seed):
    rng = np.random.default_rng(seed)
    n, k = 4, 3
    L = rng.normal(size=(n, n))
    M = L @ L.T + n * np.eye(n)
    H = rng.normal(size=(k, n))
    v = rng.normal(size=n)
    e = float(rng.uniform(0.3, 1.0))
    ratios = list(rng.uniform(0.0, 2.0, size=k - 1))
    r = impulse_ratio_law(M, H, v, e, ratios, allow_invalid=True)
    assert not r.exact
    pref, vref, Dref = mp_reference(M, H, v, e, ratios)
    if Dref < 0:
        assert r.impulses is None
        return
    assert rel_err(r.impulses, pref) < 1e-12
    assert rel_err(r.velocity, vref) < 1e-12


def test_float_cancellation_free_root_when_B_positive():
    # B = +1, C tiny: the naive (-B + sqrt(D)) / (2A) loses all digits, -2C / (B + sqrt(D)) keeps them
    e = 1 - 3.3e-15
    M, H, v = np.eye(3), np.array([[-1.0, 1, 0], [0, -1, 1]]), np.array([-1.0, 0, 0])
    r = impulse_ratio_law(M, H, v, e, [0.7], allow_invalid=True)
    pref, _, _ = mp_reference(M, H, v, e, [0.7])
    assert rel_err(r.impulses, pref) < 1e-15
    A, B, C = r.coefficients
    naive = (-B + np.sqrt(B * B - 4 * A * C)) / (2 * A)
    assert abs(naive - float(pref[0])) / abs(float(pref[0])) > 1e-3  # the naive formula really is bad here (measured: 1.3e-2)


def test_float_validity_decided_exactly_at_the_boundary():
    # alpha = 0.5 exactly at e = 1: v2+ = v3+; in floats H_2 v+ may round either way, the decision is exact
    r = impulse_ratio_law(np.eye(3), [[-1.0, 1, 0], [0, -1, 1]], [1.0, 0, 0], 1.0, [0.5])
    assert r.valid
    # float alpha just below 1/2: truly invalid, exactly decided
    r = impulse_ratio_law(np.eye(3), [[-1.0, 1, 0], [0, -1, 1]], [1.0, 0, 0], 1.0, [np.nextafter(0.5, 0)],
                          allow_invalid=True)
    assert [v.condition for v in r.violations] == ["penetration"]


# ------------------------------------------------------------------- Hypothesis, random scenes

@st.composite
def scenes(draw):
    n = draw(st.integers(2, 4))
    k = draw(st.integers(1, min(3, n)))
    small = st.integers(-3, 3)
    L = sp.Matrix(n, n, [draw(small) for _ in range(n * n)])
    M = L * L.T + sp.eye(n)
    rows = []
    for i in range(k):
        row = [draw(small) for _ in range(n)]
        if not any(row):
            row[i] = 1  # a constraint gradient is non-zero
        rows.append(row)
    H = sp.Matrix(rows)
    v = sp.Matrix([draw(small) for _ in range(n)])
    e = sp.Rational(draw(st.integers(0, 8)), 8)
    ratios = [sp.Rational(draw(st.integers(-2, 12)), 4) for _ in range(k - 1)]
    return M, H, v, e, ratios


def _solve_or_none(M, H, v, e, ratios):
    try:
        return impulse_ratio_law(M, H, v, e, ratios, allow_invalid=True)
    except DomainError as exc:  # H^T a = 0: the only refusal even with allow_invalid
        assert "H^T a = 0" in str(exc)
        assert (H.T * sp.Matrix([1, *ratios])).is_zero_matrix
        return None


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.large_base_example])
@given(scenes())
@example((sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([1, 0, 0]), sp.Integer(1), [sp.Rational(1, 2)]))
def test_momentum_and_energy_exact(scene):
    M, H, v, e, ratios = scene
    r = _solve_or_none(M, H, v, e, ratios)
    if r is None or r.impulses is None:
        return
    # momentum: M (v+ - v-) = H^T p, exactly
    residual = (M * (r.velocity - v) - H.T * r.impulses).applyfunc(lambda x: sp.expand(x))
    assert all(zero(x) for x in residual)
    # energy: T+ = e T-, exactly
    Tp = (r.velocity.T * M * r.velocity)[0, 0] / 2
    Tm = (v.T * M * v)[0, 0] / 2
    assert zero(sp.expand(Tp - e * Tm))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.large_base_example])
@given(scenes())
def test_validity_flag_is_exactly_right(scene):
    M, H, v, e, ratios = scene
    r = _solve_or_none(M, H, v, e, ratios)
    if r is None:
        return
    conds = {(x.condition, x.contact) for x in r.violations}
    a = sp.Matrix([1, *ratios])
    B = (a.T * H * v)[0, 0]
    assert (("no-approach", None) in conds) == (B >= 0)
    if r.impulses is None:
        assert ("negative-discriminant", None) in conds and r.delta < 0
        return
    for j in range(H.rows):
        assert (("negative-impulse", j + 1) in conds) == (certified_sign(r.impulses[j]) < 0)
        assert (("penetration", j + 1) in conds) == (certified_sign((H[j, :] * r.velocity)[0, 0]) < 0)
    if r.valid:  # on the valid domain: p >= 0 and H v+ >= 0, exactly
        assert all(certified_sign(x) >= 0 for x in r.impulses)
        assert all(certified_sign(x) >= 0 for x in H * r.velocity)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.large_base_example])
@given(scenes())
def test_float_path_agrees_with_exact_path(scene):
    M, H, v, e, ratios = scene
    r = _solve_or_none(M, H, v, e, ratios)
    if r is None:
        return
    f = lambda X: np.array(X.tolist(), dtype=float)  # noqa: E731 - small integer/dyadic data, exact in binary
    rf = impulse_ratio_law(f(M), f(H), f(v).reshape(-1), float(e), [float(x) for x in ratios], allow_invalid=True)
    assert [x.condition for x in rf.violations] == [x.condition for x in r.violations]
    if r.impulses is not None:
        ref = [float(x) for x in r.velocity]
        scale = max(1.0, max(abs(x) for x in ref))
        assert max(abs(a - b) for a, b in zip(rf.velocity, ref)) <= 1e-9 * scale


def test_eq12_as_printed_contradicts_sec33():
    # eq. 12 prints (1/2) q+^T M q+ = e q-^T M q-  (no 1/2 on the right), i.e. T+ = 2 e T-.
    # Sec. 3.3 says alpha = 1, e = 1 gives [0, 0, 1]: true with 1/2 on both sides (CONVENTIONS), false as printed.
    sc = chain3()
    both = general_quadratic(sc.M, sc.H, sc.v, 1, [1])
    printed = general_quadratic(sc.M, sc.H, sc.v, 2, [1])  # T+ = 2 e T- at e = 1
    assert list(both.vplus) == [0, 0, 1]
    assert sp.simplify(printed.p1 - (1 + sp.sqrt(3)) / 2) == 0 and list(printed.vplus) != [0, 0, 1]
    # and the printed form makes the elastic law create energy: T+ = 2 T-
    T = lambda x: (x.T * sc.M * x)[0, 0] / 2  # noqa: E731
    assert sp.simplify(T(printed.vplus) - 2 * T(sc.v)) == 0


def test_no_impact_root_is_papers_sign_device():
    # eq. 35 with epsilon = sign(cos tau) = -1 gives v+ = v-; the law's + root at e = 1, B > 0 is p = 0
    tau = 2 * sp.pi / 3
    sc = pool(0, tau)
    r = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["1/2"], allow_invalid=True)
    assert list(r.impulses) == [0, 0] and r.velocity == sc.v
    assert [v.condition for v in r.violations] == ["no-approach"]


def test_canonical_forms_made_on_first_read_are_the_values():
    """The exact values (and the penetration messages) are tidied when first read: every way of
    reading them (attribute, ``dataclasses.fields``, ``==``, ``repr``) sees the value, never the
    deferred computation, and the value is the tidied one."""
    import dataclasses

    from impactsym.laws import impulse_ratio as ir
    from impactsym.laws.delassus import tidy

    args = ("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1/2", ["1/4"])
    r, again = (impulse_ratio_law(*args, allow_invalid=True) for _ in range(2))
    assert r == again  # compares the values (both resolved by reading)
    for f in dataclasses.fields(r):
        assert type(getattr(r, f.name)) is not ir._Later, f.name
    assert "_Later" not in repr(r)
    A, B, _ = r.coefficients
    p1 = tidy((-B + sp.sqrt(r.delta)) / (2 * A))
    assert r.impulses == sp.Matrix([p1, p1 / 4]).applyfunc(tidy)
    pen = [v for v in r.violations if v.condition == "penetration"]
    assert pen and all(isinstance(v.message, str) and "v+ = " in v.message for v in pen)
