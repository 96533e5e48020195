"""The sequential law's sparse rational path (impactsym.laws.sequential.sparse and the incremental
search): the same decisions, messages, outcomes and ordering counts as the dense definitions,
and a cost that follows the reflections, not the number of bodies."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
from flint import fmpq, fmpq_mat

from impactsym.arithmetic.fields import RationalField
from impactsym.arithmetic.linalg import nullspace
from impactsym.errors import ImpactInputError, VerificationError
from impactsym.laws.sequential import resolve_sequential
from impactsym.laws.sequential.sparse import read_rational, verify_outcome
from impactsym.mechanics import check_mass_matrix


def _random_symmetric(rng, n):
    if rng.random() < 0.5:
        B = sp.Matrix(n, n, lambda i, j: rng.randint(-2, 2))
        return B.T * B + sp.eye(n) * rng.choice([0, 1])
    A = sp.zeros(n, n)
    dens = rng.choice([0.2, 0.6, 1.0])
    for i in range(n):
        for j in range(i, n):
            if i == j or rng.random() < dens:
                A[i, j] = A[j, i] = sp.Rational(rng.randint(-6, 9), rng.randint(1, 4))
    return A


def _sylvester(A):
    """The reference: the first non-positive leading principal minor, by SymPy determinants (of its
    DomainMatrix over ZZ/QQ: SymPy's exact determinant without the Matrix layer)."""
    D = A.to_DM()
    for k in range(1, A.shape[0] + 1):
        d = D.domain.to_sympy(D.extract(list(range(k)), list(range(k))).det())
        if d <= 0:
            return f"not positive definite (leading principal minor {k} is {d})"
    return None


def test_spd_decisions_and_messages_match_sylvester():
    """Dense (fraction-free LU in flint) and sparse (symmetric elimination) decisions, in
    mechanics.check_mass_matrix and the sequential reader, against SymPy's leading minors."""
    rng = random.Random(15)
    refused = accepted = 0
    for _ in range(120):
        n = rng.choice([2, 3, 5, 8, 9, 12])
        A = _random_symmetric(rng, n)
        want = _sylvester(A)
        for check in (lambda: check_mass_matrix(A), lambda: read_rational(A, sp.ones(1, n), sp.ones(n, 1))):
            if want is None:
                check()
            else:
                with pytest.raises(ImpactInputError) as info:
                    check()
                assert want in str(info.value)
        refused += want is not None
        accepted += want is None
    assert refused > 10 and accepted > 10


def test_asymmetric_mass_matrix_is_named_like_mechanics():
    A = "1,0,0;0,1,2;0,3,1"
    with pytest.raises(ImpactInputError, match=r"not symmetric \(entry \(1, 2\) is 2 but \(2, 1\) is 3\)"):
        read_rational(A, "1,0,0", "1,0,0")
    with pytest.raises(ImpactInputError, match=r"not symmetric \(entry \(1, 2\) is 2 but \(2, 1\) is 3\)"):
        check_mass_matrix(A)


def test_reader_leaves_what_it_does_not_read_to_the_general_path():
    assert read_rational("sqrt(2),0;0,1", "1,0", "1,1") is None
    assert read_rational("1e-3,0;0,1", "1,0", "1,1") is None  # exponent literals: the general parser
    assert read_rational([[1.0, 0], [0, 1]], [[1, 0]], [1, 1]) is None  # floats: the float path
    assert read_rational("1,0;0,1", "1,0,0", "1,1") is None  # a shape error is worded there
    d = read_rational("1.5,0;0,1/3", [[1, 0]], np.array([1, -2]))
    assert d.M == [{0: fmpq(3, 2)}, {1: fmpq(1, 3)}] and d.v0 == (fmpq(1), fmpq(-2))
    with pytest.raises(ImpactInputError, match="row 1 is the zero covector"):
        read_rational("1,0;0,1", "1,0;0,0", "1,1")


@pytest.mark.parametrize("seed", range(6))
def test_sparse_solve_null_vector_and_rank_match_dense_linear_algebra(seed):
    rng = random.Random(100 + seed)
    n = rng.choice([3, 6, 10])
    B = sp.Matrix(n, n, lambda i, j: rng.randint(-1, 1) if rng.random() < 0.4 else 0)
    M = B.T * B + sp.eye(n)
    k = rng.randint(1, n + 1)
    H = sp.Matrix(k, n, lambda i, j: rng.randint(-2, 2) if rng.random() < 0.5 else 0)
    for i in range(k):
        if all(x == 0 for x in H[i, :]):
            H[i, rng.randrange(n)] = 1
    d = read_rational(M, H, sp.ones(n, 1))
    Mq = fmpq_mat([[fmpq(int(x)) for x in M.row(i)] for i in range(n)])
    for i in range(k):
        x = dict(d.solve([(j, fmpq(int(H[i, j]))) for j in range(n) if H[i, j] != 0]))
        ref = Mq.solve(fmpq_mat([[fmpq(int(H[i, j]))] for j in range(n)]))
        assert [x.get(j, fmpq(0)) for j in range(n)] == [ref[j, 0] for j in range(n)]
    rows = [[fmpq(int(H[i, j])) for j in range(n)] for i in range(k)]
    ns = nullspace(rows, n, RationalField)
    assert d.rank() == H.rank()
    assert (d.null_vector() is None) == (not ns)
    if ns:
        assert d.null_vector() == ns[0]


def test_sparse_verification_rejects_each_broken_condition():
    d = read_rational("1,0;0,1", "1,0;-1,1", "-1,-2")
    verify_outcome("sequential", d, [fmpq(1), fmpq(2)], [fmpq(6), fmpq(4)])
    with pytest.raises(VerificationError, match="H_2 v\\+ = -1 < 0"):
        verify_outcome("sequential", d, [fmpq(1), fmpq(0)], [fmpq(2), fmpq(0)])
    with pytest.raises(VerificationError, match="kinetic energy"):
        verify_outcome("sequential", d, [fmpq(1), fmpq(3)], [fmpq(6), fmpq(4)])
    with pytest.raises(VerificationError, match="momentum"):
        verify_outcome("sequential", d, [fmpq(1), fmpq(2)], [fmpq(6), fmpq(5)])
    d2 = read_rational("1,0;0,1", "1,0;1,0;0,1", "-1,-1")  # a repeated row: p_1 + p_2 = 2 only
    verify_outcome("sequential", d2, [fmpq(1), fmpq(1)], [fmpq(1), fmpq(1), fmpq(2)])
    with pytest.raises(VerificationError, match="impulse p_2 = -1 < 0"):
        verify_outcome("sequential", d2, [fmpq(1), fmpq(1)], [fmpq(3), fmpq(-1), fmpq(2)])


def _brute_force(M, H, v):
    """Every ordering of the branching rule by plain recursion in SymPy (no memo, dense
    algebra): {ordering: outcome velocity}."""
    Minv = M.inv()
    out = {}

    def rec(vel, order):
        w = H * vel
        legal = [i for i in range(H.rows) if w[i] < 0]
        if not legal:
            out[tuple(order)] = tuple(vel)
            return
        for i in legal:
            h = H[i, :]
            W = Minv * h.T
            rec(vel - W * (2 * w[i] / (h * W)[0, 0]), order + [i])

    rec(v, [])
    return out


@pytest.mark.parametrize("seed", range(25))
def test_incremental_search_equals_brute_force_enumeration(seed):
    """Outcomes, orderings (each with its outcome), counts and lengths of the sparse
    incremental search equal a plain recursive enumeration, on chains and on dense systems."""
    rng = np.random.default_rng(500 + seed)
    if seed % 2:
        n = int(rng.integers(3, 6))
        M = sp.diag(*[int(m) for m in rng.integers(1, 4, size=n)])
        H = sp.Matrix(n - 1, n, lambda i, j: -1 if j == i else 1 if j == i + 1 else 0)
    else:
        n = int(rng.integers(2, 4))
        A = rng.integers(-2, 3, size=(n, n))
        M = sp.Matrix(A.T @ A + 2 * np.eye(n, dtype=int))
        H = sp.Matrix(rng.integers(-2, 3, size=(int(rng.integers(1, 4)), n)))
        if any(all(x == 0 for x in H[i, :]) for i in range(H.rows)):
            return
    v = sp.Matrix(rng.integers(-3, 4, size=n))
    try:
        r = resolve_sequential(M, H, v, select=False, two_surface="iterate", max_reflections=12)
    except Exception:  # noqa: BLE001 - refused (no valid velocity, or too long): nothing to compare
        return
    ref = _brute_force(M, H, v)
    got = {o: tuple(r.outcomes[i].velocity) for o, i in r.iter_orderings()}
    assert got == ref
    assert r.orderings == len(ref)
    for o in r.outcomes:
        lens = [len(k) for k, vel in ref.items() if vel == tuple(o.velocity)]
        assert (o.orderings, o.reflections_min, o.reflections_max) == (len(lens), min(lens), max(lens))
        shortest = min((k for k, vel in ref.items() if vel == tuple(o.velocity)), key=lambda k: (len(k), k))
        assert o.order == shortest


def test_thousand_ball_cradle_is_exact_and_linear_in_states():
    """A 1000-ball one-striker cradle: 1000 states, one outcome (the last ball leaves with the
    striker's velocity), every impulse 1, and the incremental sign tests: four per state (the
    contact that fired and its neighbours), not a thousand."""
    n = 1000
    H = sp.SparseMatrix(n - 1, n, {**{(i, i): -1 for i in range(n - 1)}, **{(i, i + 1): 1 for i in range(n - 1)}})
    r = resolve_sequential(sp.eye(n), H, sp.SparseMatrix(n, 1, {(0, 0): 1}))
    (o,) = r.outcomes
    assert list(o.velocity) == [0] * (n - 1) + [1] and list(o.impulse) == [1] * (n - 1)
    assert r.states_visited == n and r.orderings == 1 and o.reflections == n - 1
    assert r.sign_tests < 4 * n
    assert r.selected == (o.velocity,) and list(r.selected_impulses[0]) == [1] * (n - 1)


def test_memo_hash_collisions_are_resolved_exactly(monkeypatch):
    """Every state hashed alike: the exact comparison alone decides sharing, and the search
    gives the same states, orderings and outcomes."""
    from impactsym.laws.sequential import search

    n = 5
    H = sp.Matrix(n - 1, n, lambda i, j: -1 if j == i else 1 if j == i + 1 else 0)
    v = sp.Matrix([3, 0, 2, 0, 1])
    ref = resolve_sequential(sp.eye(n), H, v, two_surface="iterate")
    monkeypatch.setattr(search, "_mix", lambda z: 7)
    got = resolve_sequential(sp.eye(n), H, v, two_surface="iterate")
    assert (got.states_visited, got.orderings) == (ref.states_visited, ref.orderings) and got.states_visited > 10
    assert [(o.order, list(o.velocity), o.orderings) for o in got.outcomes] == \
        [(o.order, list(o.velocity), o.orderings) for o in ref.outcomes]


@pytest.mark.parametrize("M, H, v, path", [
    ("11/10,0;0,1", "1,0;-1,1", "-1,-2", "closed-form"),
    ("11/10,0;0,1", "1,0;-1,1", "-1,-2", "auto"),
    ("1,0;0,1", "1,0;-5,1", "-1,-6", "auto"),  # a long wedge: the closed form
    ("1,0,0,0;0,2,0,0;0,0,3,0;0,0,0,1", "-1,1,0,0;0,-1,1,0;0,0,-1,1", "2,1,0,-1", "auto"),
])
def test_selected_impulses_are_the_unique_impulses(M, H, v, path):
    """The impulses the law gives with its selected velocities (full-row-rank H) are the unique
    p of M(v+ − v0) = Hᵀp, as the lawbook computed them with SymPy before."""
    from impactsym.lawbook import _impulses_of
    from impactsym.resolution import System

    r = resolve_sequential(M, H, v, two_surface=path)
    Ms, Hs, vs = (sp.Matrix([[sp.Rational(x) for x in row.split(",")] for row in t.split(";")]) for t in (M, H, v))
    vs = vs.T
    assert r.selected and len(r.selected_impulses) == len(r.selected)
    system = System(Ms, Hs, vs, None)
    for s, p in zip(r.selected, r.selected_impulses):
        assert Ms * (s - vs) == Hs.T * p
        assert p == _impulses_of(system, s)
