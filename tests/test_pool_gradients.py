"""impactsym.models.acary_taha._pool_gradients simplifies each ± pair of gradient entries once
(a contact's gradient wrt one ball is minus its gradient wrt the other): the result must be the
matrix of per-entry ``simplify`` it replaces, entry for entry and in printed form."""
import pytest
import sympy as sp

from impactsym.models.acary_taha import _coords, _pool_gradients, pool_positions


def _per_entry(theta, third_contact, constraint, a):
    q, _ = _coords(3, planar=True)
    G = [sp.Matrix(q[0:2]), sp.Matrix(q[2:4]), sp.Matrix(q[4:6])]
    pairs = [(0, 1), (1, 2)] + ([(0, 2)] if third_contact else [])
    hs = []
    for i, j in pairs:
        d2 = (G[j] - G[i]).dot(G[j] - G[i])
        hs.append(sp.sqrt(d2) - 2 * a if constraint == "distance" else d2 - 4 * a**2)
    at = dict(zip(q, [x for P in pool_positions(theta, a) for x in P]))
    return sp.ImmutableMatrix([[sp.simplify(sp.diff(h, qj).subs(at)) for qj in q] for h in hs])


@pytest.mark.parametrize("theta, third, constraint", [
    (sp.Symbol("theta", real=True), False, "distance"),
    (3 * sp.pi / 5, False, "distance"),
    (2 * sp.pi / 3, True, "distance"),
    (2 * sp.pi / 3, True, "squared"),
    (sp.pi / 4, False, "distance"),
])
def test_pool_gradients_equal_per_entry_simplify(theta, third, constraint):
    new = _pool_gradients.__wrapped__(theta, third, constraint, sp.Integer(1))
    ref = _per_entry(theta, third, constraint, sp.Integer(1))
    assert new == ref
    assert [str(x) for x in new] == [str(x) for x in ref]
    assert any(x != 0 for x in new)  # a real gradient, not a vacuous comparison
