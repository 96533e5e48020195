"""The O(1) two-surface law against explicit iteration of single impacts.

References used here:

* ``iterate_reflect``: the paper's algorithm literally, with ``impactsym.laws.reflection.reflect``
  (exact SymPy) applied until the velocity is valid;
* ``iterate_fraction``: the same iteration in exact rationals (python-flint ``fmpq``, which is
  ``Fraction``'s arithmetic at C speed; ``G_u v = v − 2w(uv)/(uw)``),
  checked against ``iterate_reflect`` below, used for the thousands of random cases and for float
  input through the floats' exact binary values (so the reference decisions are exact);
* ``iterate_mpmath``: the iteration at 80 digits, for certified digits at large counts.
"""

from __future__ import annotations

import random
from fractions import Fraction

import mpmath
from flint import fmpq, fmpq_mat
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from impactsym.errors import ImpactInputError
from impactsym.laws.reflection import reflect
from impactsym.laws.two_surface import AlternatingOrder, resolve_two_surfaces


# --------------------------------------------------------------------------- references
def _q(x) -> fmpq:
    """``x`` (int, Fraction, float's binary value, fmpq) as an exact ``fmpq``."""
    if type(x) is fmpq:
        return x
    f = x if type(x) is Fraction else Fraction(x)
    return fmpq(f.numerator, f.denominator)


def _solve(M, b):
    """The exact solution of ``M x = b`` in rationals (``fmpq_mat.solve``: fraction-free elimination)."""
    n = len(M)
    x = fmpq_mat(n, n, [_q(a) for row in M for a in row]).solve(fmpq_mat(n, 1, [_q(a) for a in b]))
    return [x[i, 0] for i in range(n)]


def _solve_rows(M, H):
    """``[M⁻¹ h for h in H]`` in rationals: one exact solve with the rows of ``H`` as right-hand
    sides (the unique solution, column by column, as :func:`_solve` gives it)."""
    n, k = len(M), len(H)
    x = fmpq_mat(n, n, [_q(a) for row in M for a in row]).solve(
        fmpq_mat(n, k, [_q(H[j][i]) for i in range(n) for j in range(k)]))
    return [[x[i, j] for i in range(n)] for j in range(k)]


def iterate_fraction(M, H, v, first, cap=10**6):
    """Explicit alternating reflections from surface ``first``; returns (order, velocity) or None
    when the branch does not exist; (``[]``, v) when v is valid."""
    n = len(v)
    v = [_q(x) for x in v]
    H = [[_q(x) for x in h] for h in H]
    hv = [sum(h[j] * v[j] for j in range(n)) for h in H]  # (H_0 v, H_1 v) of the current v
    if all(x >= 0 for x in hv):
        return [], v
    if hv[first] >= 0:
        return None
    ws = _solve_rows(M, H)
    ss = [sum(h[j] * w[j] for j in range(n)) for h, w in zip(H, ws)]
    order, i = [], first
    while True:
        w, uv = ws[i], hv[i]
        assert uv < 0, "the forced surface must be violated"
        coef = 2 * uv / ss[i]  # (exact: v - 2 w (uv)/(uw) componentwise)
        v = [v[j] - coef * w[j] for j in range(n)]
        order.append(i)
        hv = [sum(h[j] * v[j] for j in range(n)) for h in H]
        if all(x >= 0 for x in hv):
            return order, v
        i = 1 - i
        assert len(order) < cap


def iterate_reflect(M, H, v, first):
    """The same with ``impactsym.laws.reflection.reflect`` (exact SymPy)."""
    Ms, v = sp.Matrix(M), sp.Matrix(v)
    Hs = [sp.Matrix([h]) for h in H]
    if all((h * v)[0] >= 0 for h in Hs):
        return [], v
    if (Hs[first] * v)[0] >= 0:
        return None
    order, i = [], first
    while True:
        v = reflect(Ms, Hs[i], v)
        order.append(i)
        if all((h * v)[0] >= 0 for h in Hs):
            return order, v
        i = 1 - i


def iterate_mpmath(M, H, v, first, dps=80):
    with mpmath.workdps(dps):
        Mm = mpmath.matrix([[mpmath.mpf(Fraction(x).numerator) / Fraction(x).denominator for x in r] for r in M])
        Hm = [mpmath.matrix([mpmath.mpf(Fraction(x).numerator) / Fraction(x).denominator for x in h]) for h in H]
        vm = mpmath.matrix([mpmath.mpf(Fraction(x).numerator) / Fraction(x).denominator for x in v])
        ws = [mpmath.lu_solve(Mm, h) for h in Hm]
        ss = [sum(h[j] * w[j] for j in range(len(v))) for h, w in zip(Hm, ws)]
        # the iteration on lists of mpf: the same operations as on mpmath matrices (each component
        # v_j - (2 uv / s) w_j), without a matrix object per step
        n = len(v)
        Hl, wl, vl = [[h[j] for j in range(n)] for h in Hm], [[w[j] for j in range(n)] for w in ws], list(vm)
        i, count = first, 0
        while True:
            uv = sum(Hl[i][j] * vl[j] for j in range(n))
            coef = 2 * uv / ss[i]
            vl = [vl[j] - coef * wl[i][j] for j in range(n)]
            count += 1
            if all(sum(h[j] * vl[j] for j in range(n)) >= 0 for h in Hl):
                return count, mpmath.matrix(vl)
            i = 1 - i


def _fr_matrix(A):
    return [[Fraction(x) for x in row] for row in A]


def _text(A):
    return ";".join(",".join(str(x) for x in row) for row in A)


def _random_case(rng, n, size=9):
    """A random rational SPD mass matrix (LLᵀ + I), two gradient rows and a velocity."""
    def q():
        return Fraction(rng.randint(-size, size), rng.randint(1, size))
    # M exactly in fmpq (Fraction's arithmetic at C speed), returned as Fractions; symmetric by construction
    L = [[fmpq(rng.randint(-size, size), rng.randint(1, size)) for _ in range(n)] for _ in range(n)]
    Mq = [[None] * n for _ in range(n)]
    for i in range(n):
        for j in range(i, n):
            Mq[i][j] = Mq[j][i] = sum((L[i][k] * L[j][k] for k in range(n)), fmpq(1 if i == j else 0))
    M = [[Fraction(int(x.p), int(x.q)) for x in row] for row in Mq]
    while True:
        H = [[q() for _ in range(n)] for _ in range(2)]
        ws = _solve_rows(Mq, H)
        gram = [[sum(_q(H[i][k]) * ws[j][k] for k in range(n)) for j in range(2)] for i in range(2)]
        if all(any(x != 0 for x in h) for h in H) and gram[0][0] * gram[1][1] != gram[0][1] ** 2:
            break
    v = [q() for _ in range(n)]
    return M, H, v


def _check_against(res, M, H, v, ref_fn=iterate_fraction):
    refs = {f: ref_fn(M, H, v, f) for f in (0, 1)}
    if refs[0] is not None and refs[0][0] == []:
        assert len(res.outcomes) == 1 and res.outcomes[0].reflections == 0
        assert res.by_first == {0: None, 1: None}
        return refs
    for f in (0, 1):
        o = res.by_first[f]
        if refs[f] is None:
            assert o is None
            continue
        order, vel = refs[f]
        assert o.reflections == len(order)
        assert o.order == order
        if o.exact:
            assert [sp.Rational(x.numerator, x.denominator) for x in vel] == list(o.velocity)
    assert len(res.outcomes) == sum(r is not None for r in refs.values())
    return refs


# --------------------------------------------------------------------------- exact, against iteration
def test_fraction_reference_agrees_with_reflect():
    rng = random.Random(7)
    for _ in range(25):
        M, H, v = _random_case(rng, rng.choice([2, 3]))
        for f in (0, 1):
            a, b = iterate_fraction(M, H, v, f), iterate_reflect(M, H, v, f)
            assert (a is None) == (b is None)
            if a is not None:
                assert a[0] == b[0]
                assert [sp.Rational(x.numerator, x.denominator) for x in a[1]] == list(b[1])


@pytest.mark.parametrize("cases, seed", [(1000, 2024), pytest.param(10000, 77, marks=pytest.mark.slow)])
def test_random_rational_cases_against_iteration(cases, seed):
    rng = random.Random(seed)
    seen_counts = set()
    for _ in range(cases):
        n = rng.choice([2, 2, 3, 4])
        M, H, v = _random_case(rng, n)
        res = resolve_two_surfaces(sp.Matrix(M), sp.Matrix(H), sp.Matrix(v))
        _check_against(res, M, H, v)
        seen_counts |= {o.reflections for o in res.outcomes}
    assert {0, 1, 2, 3} <= seen_counts  # the sample exercises several counts


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10**6))
@example(3)
def test_hypothesis_against_reflect(seed):
    rng = random.Random(seed)
    M, H, v = _random_case(rng, rng.choice([2, 3]), size=5)
    res = resolve_two_surfaces(sp.Matrix(M), sp.Matrix(H), sp.Matrix(v))
    _check_against(res, M, H, v, iterate_reflect)


def test_exit_is_valid_energy_preserving_and_impulses_nonnegative():
    rng = random.Random(11)
    for _ in range(200):
        M, H, v = _random_case(rng, 3)
        Ms, Hs, vs = sp.Matrix(M), sp.Matrix(H), sp.Matrix(v)
        res = resolve_two_surfaces(Ms.copy(), Hs.copy(), vs.copy())  # (copies: the checks read the data as given)
        for o in res.outcomes:
            assert all(x >= 0 for x in Hs * o.velocity)
            assert (o.velocity.T * Ms * o.velocity)[0] == (vs.T * Ms * vs)[0]
            assert Ms * (o.velocity - vs) == Hs.T * o.impulse  # the momentum jump lies in span(Hᵀ)
            assert all(p >= 0 for p in o.impulse)  # ... in the cone: every single impulse is >= 0


# --------------------------------------------------------------------------- large counts
@pytest.mark.parametrize("eps_den, v", [(50, "-1,0"), (300, "-1,-1"), (300, "-3,2"),
                                        pytest.param(1000, "-1,-7", marks=pytest.mark.slow)])
def test_large_counts_exact_against_iteration(eps_den, v):
    M, H = [[1, 0], [0, 2]], [[1, 0], [-eps_den, 1]]
    vv = [Fraction(x) for x in v.split(",")]
    res = resolve_two_surfaces(_text(M), _text(H), v, max_exact_digits=10**6)
    refs = _check_against(res, _fr_matrix(M), _fr_matrix(H), vv)
    assert max(len(r[0]) for r in refs.values() if r) > 20


def test_certified_digits_against_80_digit_iteration():
    M, H, v = [[2, 1], [1, 3]], [[1, 0], [-4000, 1]], [Fraction(-1), Fraction(-1, 3)]
    res = resolve_two_surfaces(_text(M), _text(H), "-1,-1/3", max_exact_digits=0, digits=40)
    for o in res.outcomes:
        count, vm = iterate_mpmath(M, H, v, o.first)
        assert o.reflections == count > 1000 and not o.exact and o.digits == 40
        with mpmath.workdps(80):
            scale = max(abs(vm[i]) for i in range(2))
            for i in range(2):
                err = abs(o.velocity[i] - vm[i])
                assert err <= mpmath.mpf(10) ** -40 * max(abs(vm[i]), mpmath.mpf(10) ** -40 * scale)
                assert err <= o.error_bound + mpmath.mpf(10) ** -70


def test_exact_and_certified_paths_agree():
    M, H, v = "3,1;1,2", "1,0;-200,1", "-2,1"
    ex = resolve_two_surfaces(M, H, v, max_exact_digits=10**5)
    ce = resolve_two_surfaces(M, H, v, max_exact_digits=0, digits=50)
    for a, b in zip(ex.outcomes, ce.outcomes):
        assert a.exact and not b.exact and a.reflections == b.reflections
        with mpmath.workdps(60):
            for i in range(2):
                ref = mpmath.mpf(a.velocity[i].p) / a.velocity[i].q
                assert abs(ref - b.velocity[i]) <= mpmath.mpf(10) ** -49 * max(1, abs(ref))


def test_billion_reflections_count_against_closed_forms():
    """H_B = [-10^9, 1]: the wedge is ~1e-9 rad; v = (-1, 0) makes ψ = π/2 exactly (M = I)."""
    res = resolve_two_surfaces("1,0;0,1", "1,0;-1000000000,1", "-1,0")
    o = res.outcomes[0]
    with mpmath.workdps(60):
        beta = mpmath.atan2(1, 10**9)
        assert o.reflections == int(mpmath.ceil(mpmath.pi / 2 / beta)) > 10**9
        assert res.bound == int(mpmath.ceil(mpmath.pi / beta))
        m = o.reflections
        th = (m * beta - mpmath.pi / 2) if m % 2 == 0 else (mpmath.pi / 2 - (m - 1) * beta)
        # frame: E1 = e_A = (0, 1), E2 = n_A = (1, 0); v = (sin θ, cos θ)
        assert abs(o.velocity[0] - mpmath.sin(th)) < mpmath.mpf(10) ** -30
        assert abs(o.velocity[1] - mpmath.cos(th)) < mpmath.mpf(10) ** -30
    assert list(o.order[:4]) == [0, 1, 0, 1] and len(o.order) == o.reflections


# --------------------------------------------------------------------------- float input
@pytest.mark.parametrize("cases, seed", [(1000, 5), pytest.param(5000, 55, marks=pytest.mark.slow)])
def test_float_input_against_exact_iteration_of_the_binary_values(cases, seed):
    """Random float cases. Reference: exact rational (fmpq) iteration of the floats' binary values
    (counts up to 60; beyond, the rationals' sizes explode and the 120-digit iteration is used)."""
    rng = np.random.default_rng(seed)
    long_branches = 0
    for _ in range(cases):
        n = int(rng.integers(2, 5))
        A = rng.normal(size=(n, n))
        M = A @ A.T + 0.5 * np.eye(n)
        H = rng.normal(size=(2, n))
        v = rng.normal(size=n)
        res = resolve_two_surfaces(M, H, v)
        assert not res.exact
        Mf = [[Fraction(float(x)) for x in r] for r in M]
        Hf = [[Fraction(float(x)) for x in r] for r in H]
        vf = [Fraction(float(x)) for x in v]
        for f in (0, 1):
            o = res.by_first[f]
            if o is None:  # no branch starts with f: v is valid, or does not approach surface f
                ref = iterate_fraction(Mf, Hf, vf, f)
                assert ref is None or ref[0] == []
                continue
            assert isinstance(o.velocity, np.ndarray)
            if o.reflections <= 60:
                order, vel = iterate_fraction(Mf, Hf, vf, f)
                assert o.reflections == len(order)
                exact = np.array([float(x) for x in vel])
            else:
                long_branches += 1
                count, vm = iterate_mpmath(Mf, Hf, vf, f, dps=120)
                assert o.reflections == count
                exact = np.array([float(vm[i]) for i in range(n)])
            np.testing.assert_allclose(o.velocity, exact, rtol=0, atol=4e-16 * np.max(np.abs(exact)))
    assert long_branches >= 1


def test_float_near_tie_is_decided_exactly():
    """Equal masses, wedge π/4: v = (−1, −1) puts iterates exactly on edges (ψ/β = 3). A float
    copy of a tie is still an exact tie of the binary values and must be decided as such."""
    res = resolve_two_surfaces(np.eye(2), np.array([[1.0, 0.0], [-1.0, 1.0]]), np.array([-1.0, -1.0]))
    assert [o.reflections for o in res.outcomes] == [3]
    assert res.decisions.get("exact_tie", 0) >= 1
    exact = resolve_two_surfaces("1,0;0,1", "1,0;-1,1", "-1,-1")
    assert exact.outcomes[0].reflections == 3 and list(exact.outcomes[0].velocity) == [1, 1]


# --------------------------------------------------------------------------- special cases
def test_valid_and_grazing_velocities():
    r = resolve_two_surfaces("1,0;0,1", "1,0;-1,1", "0,0")
    assert [o.reflections for o in r.outcomes] == [0] and r.by_first == {0: None, 1: None}
    r = resolve_two_surfaces("1,0;0,1", "1,0;-1,1", "1,1")  # grazing B, leaving A
    assert [o.reflections for o in r.outcomes] == [0]
    # n = 3, v in ker H_A ∩ ker H_B (the M-orthogonal complement of the plane): valid, unchanged
    r = resolve_two_surfaces("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "5,5,5")
    assert r.outcomes[0].reflections == 0 and list(r.outcomes[0].velocity) == [5, 5, 5]


def test_complement_component_is_untouched():
    """The part of v in ker H_A ∩ ker H_B passes through every reflection (plane reduction)."""
    base = resolve_two_surfaces("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
    shifted = resolve_two_surfaces("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "8,7,7")  # + 7(1,1,1)
    assert [o.reflections for o in base.outcomes] == [o.reflections for o in shifted.outcomes]
    for a, b in zip(base.outcomes, shifted.outcomes):
        assert b.velocity - a.velocity == sp.Matrix([7, 7, 7])


def test_paper_examples():
    # two balls and a wall, equal masses: -v0 for both orderings, 4 reflections
    r = resolve_two_surfaces("1,0;0,1", "1,0;-1,1", "-1,-2")
    assert [(list(o.order), o.reflections, list(o.velocity)) for o in r.outcomes] == \
        [([0, 1, 0, 1], 4, [1, 2]), ([1, 0, 1, 0], 4, [1, 2])]
    assert r.bound == 4 and r.kinetic_angle_cos == -sp.sqrt(2) / 2
    # three-ball cradle, eq. 4: [1,1,0] -> [0,1,1]
    r = resolve_two_surfaces("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,1,0")
    assert [list(o.velocity) for o in r.outcomes] == [[0, 1, 1]] and r.bound == 3
    # M = diag(11/10, 1): v4a and v4b (the matrices of sec. III-B.3) when 4 reflections are needed
    M = sp.diag(sp.Rational(11, 10), 1)
    v0 = sp.Matrix([-1, -2])
    r = resolve_two_surfaces(M, "1,0;-1,1", v0)
    v4a = sp.Matrix([[-439, -40], [44, -439]]) / 441
    v4b = sp.Matrix([[-439, 40], [-44, -439]]) / 441
    assert r.outcomes[0].velocity == v4a * v0 and r.outcomes[1].velocity == v4b * v0


@pytest.mark.parametrize("t, counts", [(sp.Rational(11, 10), (3, 4)), (2, (4, 4)), (20, (4, 3)),
                                       (sp.Rational(23, 19), (3, 4)), (sp.Rational(439, 40), (4, 3))])
def test_paper_diag_11_10_counts_depend_on_v0(t, counts):
    """u-first needs 4 iff t > 23/19, v-first iff t < 439/40 (v0 = -(1, t)); boundaries are ties."""
    r = resolve_two_surfaces("11/10,0;0,1", "1,0;-1,1", sp.Matrix([-1, -t]))
    assert tuple(o.reflections for o in r.outcomes) == counts
    assert r.bound == 4


def test_irrational_input_exact_path():
    # wedge exactly pi/3 with irrational data: M = I, H_B at 120 degrees from H_A
    r = resolve_two_surfaces("1,0;0,1", "1,0;-1/2,sqrt(3)/2", "-1,-sqrt(3)")
    assert r.bound == 3 and all(o.exact for o in r.outcomes)
    for o in r.outcomes:
        ref = iterate_reflect([[1, 0], [0, 1]], [[1, 0], [-sp.Rational(1, 2), sp.sqrt(3) / 2]],
                              [-1, -sp.sqrt(3)], o.first)
        assert o.reflections == len(ref[0])
        assert all(sp.simplify(a - b) == 0 for a, b in zip(o.velocity, ref[1]))
    r2 = resolve_two_surfaces("sqrt(2),0;0,1", "1,0;-1,1", "-1,-2")
    for o in r2.outcomes:
        ref = iterate_reflect(sp.diag(sp.sqrt(2), 1), [[1, 0], [-1, 1]], [-1, -2], o.first)
        assert o.reflections == len(ref[0])
        assert all(sp.simplify(a - b) == 0 for a, b in zip(o.velocity, ref[1]))


# --------------------------------------------------------------------------- bound and outcomes
def test_counts_never_exceed_the_bound_and_both_approaching_counts():
    rng = random.Random(99)
    for _ in range(400):
        M, H, v = _random_case(rng, 2)
        r = resolve_two_surfaces(sp.Matrix(M), sp.Matrix(H), sp.Matrix(v))
        assert all(o.reflections <= r.bound for o in r.outcomes)
        assert 1 <= len(r.outcomes) <= 2  # the paper: "no less than one and no more than two"
        if len(r.outcomes) == 2:  # approaching both: counts in {N-1, N}
            assert {o.reflections for o in r.outcomes} <= {r.bound - 1, r.bound}


def test_bound_is_attained():
    # close to the edge e_A from outside (psi -> pi): the count reaches N
    r = resolve_two_surfaces("11/10,0;0,1", "1,0;-1,1", "-1,-1000")
    assert r.outcomes[0].reflections == r.bound == 4


def test_outcomes_coincide_when_pi_over_beta_is_an_integer():
    # beta = pi/4 (equal masses): one distinct outcome for every approaching v0
    rng = random.Random(3)
    for _ in range(50):
        v = sp.Matrix([-rng.randint(1, 50), -rng.randint(51, 200)])
        r = resolve_two_surfaces("1,0;0,1", "1,0;-1,1", v)
        assert len(r.outcomes) == 2 and r.outcomes[0].velocity == r.outcomes[1].velocity == -v


def test_alternating_order():
    o = AlternatingOrder(0, 10**9)
    assert len(o) == 10**9 and o[10**9 - 1] == 1 and o[-2] == 0 and o[:3] == [0, 1, 0]
    assert o.to_json() == {"first": 0, "length": 10**9, "alternating": True}
    assert AlternatingOrder(1, 3).to_json() == [1, 0, 1]
    with pytest.raises(IndexError):
        o[10**9]


# --------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("M, H, v, words", [
    ("1,0;0,1", "1,0", "-1,0", "exactly 2 rows"),
    ("1,0,0;0,1,0;0,0,1", "1,0,0;0,1,0;0,0,1", "-1,0,0", "exactly 2 rows"),
    ("1,0;0,1", "1,0;2,0", "-1,0", "parallel"),
    ("1,0;0,1", "1,0;-3,0", "-1,0", "parallel"),
    ("2", "1;1", "-1", "parallel"),
    ("1,2;2,1", "1,0;0,1", "-1,0", "positive definite"),
    ("1,0;0,1", "1,0;0,0", "-1,0", "zero covector"),
    ("1,0;0,1", "1,0;0,1", "-1,0,0", "length"),
])
def test_bad_input(M, H, v, words):
    with pytest.raises(ImpactInputError, match=words):
        resolve_two_surfaces(M, H, v)


def test_bad_float_input():
    with pytest.raises(ImpactInputError):
        resolve_two_surfaces(np.eye(2), np.array([[1.0, 0.0], [np.nan, 1.0]]), np.array([-1.0, 0.0]))
    with pytest.raises(ImpactInputError, match="parallel"):
        resolve_two_surfaces(np.eye(2), np.array([[1.0, 0.5], [-2.0, -1.0]]), np.array([-1.0, 0.0]))
    with pytest.raises(ImpactInputError, match="digits"):
        resolve_two_surfaces("1,0;0,1", "1,0;-1,1", "-1,-1", digits=0)


def test_outcomes_differ_when_pi_over_beta_is_not_an_integer():
    # M = diag(11/10, 1): pi/beta = 3.88...; m_A + m_B = 2*pi/beta is impossible, so the two
    # outcomes differ except on a measure-zero set of velocities
    rng = random.Random(8)
    for _ in range(50):
        v = sp.Matrix([-rng.randint(1, 50), -rng.randint(51, 200)])
        r = resolve_two_surfaces("11/10,0;0,1", "1,0;-1,1", v)
        assert len(r.outcomes) == 2 and r.outcomes[0].velocity != r.outcomes[1].velocity


@pytest.mark.parametrize("q", [318, pytest.param(3183, marks=pytest.mark.slow)])
def test_large_count_by_exact_signs_of_exact_iterates(q):
    """Independent of the angle formula: the law's count m is right iff the exact m-th iterate is
    valid and the exact (m−1)-th is not. Exact iterates from the derivation's Fraction closed form
    α ρ^k (equal to the products of G's: tests/test_two_surface_derivation.py)."""
    from derivations.two_surface import exact_exit_relative_velocity as iterate_closed_form

    res = resolve_two_surfaces(sp.eye(2), sp.Matrix([[1, 0], [-q, 1]]), sp.Matrix([-1, -(q + 1)]))
    sA, sB, g = 1, q * q + 1, -q
    cA, cB = -1, -1  # H v for v = (-1, -(q+1))
    for o in res.outcomes:
        args = (sA, sB, g, cA, cB) if o.first == 0 else (sB, sA, g, cB, cA)
        last = iterate_closed_form(*args, o.reflections)
        before = iterate_closed_form(*args, o.reflections - 1)
        assert min(last) >= 0 and min(before) < 0
        assert o.reflections > 3 * q - 1


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10**6), st.fractions(min_value=Fraction(1, 50), max_value=50),
       st.fractions(min_value=Fraction(1, 50), max_value=50))
@example(0, Fraction(1), Fraction(1))
# found by Hypothesis: 56 reflections, where the scaled rows make the exact exit exceed
# max_exact_digits, so that branch is certified to 30 digits instead of exact
@example(40180, Fraction(65561, 1350), Fraction(35583967, 711700))
def test_row_scaling_and_swapping_invariance(seed, a, b):
    """G_{αu} = G_u and validity is unchanged for α > 0: scaling rows changes nothing; swapping
    the rows swaps the branches (their first-surface labels). Exits are compared exactly when
    both are exact, and to the certified digits when one of them is certified instead."""
    rng = random.Random(seed)
    M, H, v = _random_case(rng, rng.choice([2, 3]), size=6)
    r = resolve_two_surfaces(sp.Matrix(M), sp.Matrix(H), sp.Matrix(v))
    Hs = [[x * a for x in H[0]], [x * b for x in H[1]]]
    rs = resolve_two_surfaces(sp.Matrix(M), sp.Matrix(Hs), sp.Matrix(v))
    rw = resolve_two_surfaces(sp.Matrix(M), sp.Matrix([H[1], H[0]]), sp.Matrix(v))
    assert r.bound == rs.bound == rw.bound
    for f in (0, 1):
        o, os_, ow = r.by_first[f], rs.by_first[f], rw.by_first[1 - f]
        assert (o is None) == (os_ is None) == (ow is None)
        if o is not None:
            assert o.reflections == os_.reflections == ow.reflections
            _assert_same_exit(o, os_)
            _assert_same_exit(o, ow)


def _assert_same_exit(x, y):
    if x.exact and y.exact:
        assert x.velocity == y.velocity
        return
    digits = min(d for d in (x.digits, y.digits) if d is not None)
    with mpmath.workdps(digits + 20):
        for a, b in zip(x.velocity, y.velocity):
            a = mpmath.mpf(sp.N(a, digits + 20)._mpf_) if isinstance(a, sp.Basic) else mpmath.mpf(a)
            b = mpmath.mpf(sp.N(b, digits + 20)._mpf_) if isinstance(b, sp.Basic) else mpmath.mpf(b)
            assert abs(a - b) <= mpmath.mpf(10) ** (1 - digits) * max(abs(a), abs(b))


def test_precision_ladder():
    """The same certified exit at 30 and 60 digits agrees to 30 digits (mpmath's self-check)."""
    args = ("2,1;1,3", "1,0;-50000,1", "-1,-1/3")
    lo = resolve_two_surfaces(*args, digits=30, max_exact_digits=0)
    hi = resolve_two_surfaces(*args, digits=60, max_exact_digits=0)
    with mpmath.workdps(70):
        for a, b in zip(lo.outcomes, hi.outcomes):
            assert a.reflections == b.reflections > 10**5
            for i in range(2):
                assert abs(a.velocity[i] - b.velocity[i]) <= mpmath.mpf(10) ** -30 * abs(b.velocity[i])


def test_irrational_input_certified_path():
    """M = diag(√2, 1) and 264/265 reflections: beyond exact SymPy iteration, certified digits;
    reference: the iteration at 60 digits with √2 at 60 digits."""
    r = resolve_two_surfaces("sqrt(2),0;0,1", "1,0;-100,1", "-1,-101")
    with mpmath.workdps(60):
        Mm = mpmath.matrix([[mpmath.sqrt(2), 0], [0, 1]])
        Hm = [mpmath.matrix([1, 0]), mpmath.matrix([-100, 1])]
        for o in r.outcomes:
            assert not o.exact and o.digits == 30
            v, i, k = mpmath.matrix([-1, -101]), o.first, 0
            while True:
                w = mpmath.lu_solve(Mm, Hm[i])
                v = v - (2 * (Hm[i].T * v)[0] / (Hm[i].T * w)[0]) * w
                k += 1
                if all((h.T * v)[0] >= 0 for h in Hm):
                    break
                i = 1 - i
            assert k == o.reflections
            for j in range(2):
                assert abs(o.velocity[j] - v[j]) <= mpmath.mpf(10) ** -29 * abs(v[j])
