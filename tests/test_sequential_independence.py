"""Independent impacts (impactsym.laws.sequential.independence): the commutation condition proved,
and the split search equal to the whole one (outcomes, counts, lengths, representatives, the
orderings themselves), with fewer states."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from impactsym.laws.sequential import resolve_sequential
from impactsym.laws.sequential import resolve as seq_resolve


def _G(N, u, e=1):
    """G_u(e) = I − (1+e) N uᵀu/(u N uᵀ), N = M⁻¹ (symmetric)."""
    return sp.eye(N.rows) - (1 + e) * N * u.T * u / (u * N * u.T)[0, 0]


def test_commutator_is_proportional_to_the_kinetic_coupling():
    """For any symmetric N = M⁻¹ (3×3, symbolic), rows u, w and restitutions e_u, e_w:
    G_u G_w − G_w G_u = (1+e_u)(1+e_w) (u N wᵀ)/(s_u s_w) (N uᵀ w − N wᵀ u), so the impacts commute
    when u M⁻¹ wᵀ = 0; and w G_u v = w v − (1+e_u)(u v)(w N uᵀ)/s_u, unchanged then.

    Proved with the denominators cleared: G_u = Ĝ_u/s_u with Ĝ_u = s_u I − (1+e_u) N uᵀu, a
    polynomial matrix, so the first identity times s_u s_w (≠ 0) reads Ĝ_u Ĝ_w − Ĝ_w Ĝ_u =
    (1+e_u)(1+e_w) (u N wᵀ)(N uᵀ w − N wᵀ u), and the second times s_u reads
    w Ĝ_u v = s_u (w v) − (1+e_u)(u v)(u N wᵀ); both are checked in the polynomial ring
    Q[N, u, w, v, e_u, e_w] (exact arithmetic: SymPy's DomainMatrix)."""
    from sympy.polys.matrices import DomainMatrix

    a = sp.symbols("a0:6")
    us, ws, vs = sp.symbols("u0:3"), sp.symbols("w0:3"), sp.symbols("v0:3")
    eu, ew = sp.symbols("e_u e_w")
    Q = sp.QQ[(*a, *us, *ws, *vs, eu, ew)]

    def poly_matrix(rows):
        return DomainMatrix([[Q.from_sympy(sp.sympify(x)) for x in r] for r in rows], (len(rows), len(rows[0])), Q)

    N = poly_matrix([[a[0], a[1], a[2]], [a[1], a[3], a[4]], [a[2], a[4], a[5]]])
    u, w, v = poly_matrix([us]), poly_matrix([ws]), poly_matrix([[x] for x in vs])
    one_eu, one_ew = Q.from_sympy(1 + eu), Q.from_sympy(1 + ew)

    def scalar(m):
        return m[0, 0].element

    su, sw, c = scalar(u * N * u.transpose()), scalar(w * N * w.transpose()), scalar(u * N * w.transpose())
    eye = DomainMatrix.eye(3, Q)

    def G_hat(x, s, one_e):  # s_x G_x(e)
        return eye * s - N * x.transpose() * x * one_e

    lhs = G_hat(u, su, one_eu) * G_hat(w, sw, one_ew) - G_hat(w, sw, one_ew) * G_hat(u, su, one_eu)
    rhs = (N * u.transpose() * w - N * w.transpose() * u) * (one_eu * one_ew * c)
    assert (lhs - rhs).is_zero_matrix
    assert not rhs.is_zero_matrix  # the commutator vanishes only through the coupling c = u N wᵀ
    after = scalar(w * G_hat(u, su, one_eu) * v)
    assert after - (su * scalar(w * v) - one_eu * scalar(u * v) * c) == Q.zero


def test_disjoint_supports_are_not_enough_for_a_coupled_mass_matrix():
    M = sp.Matrix([[2, 1, 0], [1, 2, 1], [0, 1, 2]])
    Minv = M.inv()
    u, w = sp.Matrix([[1, 0, 0]]), sp.Matrix([[0, 0, 1]])  # disjoint supports
    assert (u * Minv * w.T)[0, 0] != 0
    assert _G(Minv, u) * _G(Minv, w) != _G(Minv, w) * _G(Minv, u)
    w2 = sp.Matrix([[1, 0, 0]]) - (u * Minv * sp.Matrix([[1, 0, 0]]).T)[0, 0] / (u * Minv * u.T)[0, 0] * u \
        + sp.Matrix([[0, 1, 0]])  # overlapping support, made M-orthogonal below
    w2 = w2 - (u * Minv * w2.T)[0, 0] / (u * Minv * u.T)[0, 0] * u
    assert (u * Minv * w2.T)[0, 0] == 0 and w2[0] != 0
    assert _G(Minv, u) * _G(Minv, w2) == _G(Minv, w2) * _G(Minv, u)


def _block_system(rng, blocks):
    """Block-diagonal M and H: each block a small chain or a random dense group, so that contacts
    of different blocks are independent."""
    Ms, Hs, vs = [], [], []
    for kind, n in blocks:
        if kind == "chain":
            Ms.append(sp.diag(*[int(x) for x in rng.integers(1, 4, size=n)]))
            Hs.append(sp.Matrix(n - 1, n, lambda i, j: -1 if j == i else 1 if j == i + 1 else 0))
        else:
            A = rng.integers(-2, 3, size=(n, n))
            Ms.append(sp.Matrix(A.T @ A + 2 * np.eye(n, dtype=int)))
            Hs.append(sp.Matrix(rng.integers(-2, 3, size=(int(rng.integers(1, 3)), n))))
        vs.append(sp.Matrix(rng.integers(-3, 4, size=n)))
    M = sp.diag(*Ms)
    H = sp.zeros(sum(h.rows for h in Hs), M.rows)
    r = c = 0
    for h in Hs:
        H[r:r + h.rows, c:c + h.cols] = h
        r, c = r + h.rows, c + h.cols
    return M, H, sp.Matrix.vstack(*vs)


def _both(monkeypatch, *args, **kw):
    whole_kw = dict(kw)
    split = resolve_sequential(*args, **kw)
    monkeypatch.setattr(seq_resolve, "DECOMPOSE_INDEPENDENT", False)
    whole = resolve_sequential(*args, **whole_kw)
    monkeypatch.setattr(seq_resolve, "DECOMPOSE_INDEPENDENT", True)
    return split, whole


def _same(split, whole, orderings=True):
    assert split.orderings == whole.orderings and split.max_reflections_used == whole.max_reflections_used
    assert [(o.order, list(o.velocity), list(o.impulse), o.orderings, o.reflections_min, o.reflections_max)
            for o in split.outcomes] == \
        [(o.order, list(o.velocity), list(o.impulse), o.orderings, o.reflections_min, o.reflections_max)
         for o in whole.outcomes]
    assert split.selected == whole.selected
    assert split.states_visited <= whole.states_visited
    if orderings:
        assert list(split.iter_orderings()) == list(whole.iter_orderings())


@pytest.mark.parametrize("seed", range(30))
def test_split_search_equals_the_whole_search(seed, monkeypatch):
    rng = np.random.default_rng(700 + seed)
    blocks = [(str(rng.choice(["chain", "dense"])), int(rng.integers(2, 4))) for _ in range(int(rng.integers(2, 4)))]
    M, H, v = _block_system(rng, blocks)
    if any(all(x == 0 for x in H[i, :]) for i in range(H.rows)):
        return
    try:
        whole_first = resolve_sequential(M, H, v, two_surface="iterate", max_reflections=30, select=False)
    except Exception:  # noqa: BLE001 - refused: compared in test_refusals_agree
        return
    split, whole = _both(monkeypatch, M, H, v, two_surface="iterate", max_reflections=30, select=False)
    assert whole_first.orderings == whole.orderings
    _same(split, whole, orderings=whole.orderings <= 3000)


def test_two_cradles_side_by_side_visit_the_sum_of_their_states(monkeypatch):
    """Two 5-ball cradles with every contact approaching, in one system: 2 × 120 states instead
    of 120², the same 108973522944 orderings (C(20, 10) · 768²)."""
    n = 5
    H = sp.zeros(2 * (n - 1), 2 * n)
    for i in range(n - 1):
        H[i, i], H[i, i + 1] = -1, 1
        H[n - 1 + i, n + i], H[n - 1 + i, n + i + 1] = -1, 1
    v = sp.Matrix(list(range(n, 0, -1)) + list(range(2 * n, n, -1)))
    split, whole = _both(monkeypatch, sp.eye(2 * n), H, v)
    assert split.states_visited == 240 and whole.states_visited == 120 ** 2
    assert split.orderings == 108973522944 == 184756 * 768 ** 2
    _same(split, whole, orderings=False)
    assert list(split.iter_orderings(limit=200)) == list(whole.iter_orderings(limit=200))


def test_refusals_agree(monkeypatch):
    """A cap exceeded by the interleaving (each component alone within it) is refused like the
    whole search refuses it."""
    from impactsym.errors import NonTermination

    H = sp.Matrix([[-1, 1, 0, 0, 0, 0], [0, -1, 1, 0, 0, 0], [0, 0, 0, -1, 1, 0], [0, 0, 0, 0, -1, 1]])
    v = sp.Matrix([3, 2, 1, 3, 2, 1])
    for decompose in (True, False):
        monkeypatch.setattr(seq_resolve, "DECOMPOSE_INDEPENDENT", decompose)
        with pytest.raises(NonTermination, match="max_reflections"):
            resolve_sequential(sp.eye(6), H, v, max_reflections=5, two_surface="iterate")
        assert resolve_sequential(sp.eye(6), H, v, max_reflections=6, two_surface="iterate").orderings == 20 * 2 * 2
