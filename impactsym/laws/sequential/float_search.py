"""Float mode of the DAG search: float64 velocities, an error bound on every sign test, and an
exact re-decision (replay in rationals) whenever the bound straddles zero.
"""

from __future__ import annotations

import math

import numpy as np

from ...arithmetic import certified_sign
from .. import _reflection as _r
from ..reflection import FLOAT_ERROR_FACTOR
from .common import FLOAT_SAFETY, _EPS, _Algebraic, _Rational
from .search import _aggregate, _explore, _touching


# ---------------------------------------------------------------------------------------------
# Float mode
# ---------------------------------------------------------------------------------------------
class _FloatSystem:
    def __init__(self, M, H, v0, cap, restitution=None):
        self.M = np.asarray(M, dtype=float)
        self.H = np.asarray(H, dtype=float)
        self.v0 = np.asarray(v0, dtype=float)
        self.n, self.k = self.M.shape[0], self.H.shape[0]
        d = _plain_diagonal(self.M)
        if d is not None and bool(np.all(np.frexp(d)[0] == 0.5)):
            # every mass a power of two: W_i = H_i / d exactly, the dense LU solve's bits
            self.W = self.H / d
        else:
            W = np.linalg.solve(self.M, self.H.T)
            self.W = W.T.copy()
        self.s = np.einsum("ij,ij->i", self.H, self.W)
        # restitution < 1: G_u(e) is non-expansive in the kinetic norm (‖G_u(e)‖_M = max(1, e) = 1),
        # so the bound below (stated for the isometries G_u) still holds
        self.coef = _r.gain(self.s, 1.0 if restitution is None else np.asarray(restitution, dtype=float))
        # a diagonal M: its singular values are the masses, exactly (the SVD's value, without it)
        kappa = float(d.max() / d.min()) if d is not None else float(np.linalg.cond(self.M))
        gamma = FLOAT_ERROR_FACTOR * self.n * kappa * _EPS
        vnorm = math.sqrt(max(float(self.v0 @ self.M @ self.v0), 0.0))
        #: bound on ‖v_float − v_exact‖_M after any ordering of at most `cap` reflections
        self.energy_error = cap * gamma * vnorm
        self.rows = [_nonzeros(r) for r in self.H]
        self.wcols = [_nonzeros(c) for c in self.W]
        self.sqrt_s = np.sqrt(self.s)
        self.k_ = self.k

    def w_and_bound(self, v, i):
        acc = 0.0
        mag = 0.0
        for j, h in self.rows[i]:
            t = h * v[j]
            acc += t
            mag += abs(t)
        bound = FLOAT_SAFETY * (self.sqrt_s[i] * self.energy_error + 2 * self.n * _EPS * mag)
        return acc, bound

    def reflect(self, v, i, wi):
        return _r.reflect_sparse(v, self.wcols[i], self.coef[i] * wi)

    def impulse(self, order):
        v = tuple(float(x) for x in self.v0)
        p = np.zeros(self.k)
        for i in order:
            wi, _ = self.w_and_bound(v, i)
            v, pi = self.reflect(v, i, wi)
            p[i] += pi
        return p


def _affected(fs, system):
    """Per contact ``i``, the contacts ``j`` (increasing) whose sign decision a reflection on ``i``
    can change: ``(H M⁻¹ Hᵀ)_ij ≠ 0`` (the exact ``w_j`` changes, the exact search's
    :attr:`~impactsym.laws.sequential.search._ExactSystem.gcols`), or ``H_j`` shares a coordinate
    with the float ``W_i`` (the float ``w_j`` and its bound are computed from changed entries).
    Any other ``w_j`` is unchanged in floats and exactly, and so is its decision.

    >>> import numpy as np
    >>> from flint import fmpq
    >>> from .search import _ExactSystem
    >>> M, H, v = [[fmpq(1), 0, 0], [0, fmpq(1), 0], [0, 0, fmpq(1)]], [[-1, 1, 0], [0, -1, 1]], [1, 0, 0]
    >>> system = _ExactSystem.from_rationals([[fmpq(x) for x in r] for r in M],
    ...                                      [[fmpq(x) for x in r] for r in H], [fmpq(x) for x in v])
    >>> _affected(_FloatSystem(np.eye(3), np.array(H, dtype=float), np.array(v, dtype=float), 10), system)
    [(0, 1), (0, 1)]
    """
    touching = _touching(fs.rows)
    out = []
    for i in range(fs.k):
        js = {j for j, _ in system.gcols[i]}
        for c, _ in fs.wcols[i]:
            js.update(touching.get(c, ()))
        out.append(tuple(sorted(js)))
    return out


def _plain_diagonal(M):
    """The diagonal of a diagonal ``M`` whose largest entry lies in ``[1e-130, 1e130]``, else
    ``None``. In that range LAPACK's SVD does not rescale the matrix and no Householder step acts
    on a diagonal one, so ``np.linalg.cond(M)`` is exactly ``d.max() / d.min()``.

    >>> _plain_diagonal(np.diag([1.0, 4.0])), _plain_diagonal(np.array([[1.0, 0.5], [0.5, 1.0]]))
    (array([1., 4.]), None)
    """
    d = np.diag(M).copy()
    if np.count_nonzero(M) != np.count_nonzero(d) or not (1e-130 <= d.max() <= 1e130) or d.min() <= 0:
        return None
    return d


def _nonzeros(row):
    """``[(j, x_j), ...]`` over the non-zero entries of a float row (``j`` increasing, Python
    ints and floats).

    >>> _nonzeros(np.array([0.0, -2.5, 0.0, 1.0]))
    [(1, -2.5), (3, 1.0)]
    """
    idx = np.flatnonzero(row)
    return list(zip(idx.tolist(), row[idx].tolist()))


#: restitution < 1, float mode: the most sign decisions re-made exactly before the float search
#: gives way to the exact search (an inelastic collapse drives the velocities towards a limit
#: closer than the float error bound, where every decision falls back and the float memo stops
#: telling states apart)
INELASTIC_FALLBACK_BUDGET = 2000


class _FallbackBudget(Exception):
    """Raised inside the float search when ``INELASTIC_FALLBACK_BUDGET`` is exhausted."""


def _float_search(M, H, v0, system, cap, restitution=None, collapse=False, cap_error=None):
    """Float search; with ``restitution`` (floats, one per contact; ``system`` holds their exact
    binary values) and ``collapse=True`` the collapse of two contacts is decided exactly on the
    replayed exact state (:class:`~impactsym.laws.sequential.collapse._CollapseDetector`), only
    for pairs whose restitutions admit one."""
    fs = _FloatSystem(M, H, v0, cap, restitution)
    F = system.F
    exact_cache: dict[int, tuple] = {}
    #: fallbacks: the exact decisions and comparisons made; budget: what the inelastic budget is
    #: charged, which also counts the exact decisions a state keeps from its parent (the search
    #: switches to exact at the same state as when every contact was decided at every state)
    stats = {"fallbacks": 0, "budget": 0}
    holder: dict = {}

    def exact_state(node):
        g = holder["g"]
        chain = []
        cur = node
        while cur not in exact_cache and g.parent[cur] is not None:
            chain.append(cur)
            cur = g.parent[cur][0]
        if cur not in exact_cache:
            exact_cache[cur] = system.v0
        v = exact_cache[cur]
        for nd in reversed(chain):
            v, _ = system.reflect(v, g.parent[nd][1])
            exact_cache[nd] = v
        return v

    budget = INELASTIC_FALLBACK_BUDGET if restitution is not None else None

    def spend():
        stats["fallbacks"] += 1
        stats["budget"] += 1
        if budget is not None and stats["budget"] > budget:
            raise _FallbackBudget()

    def sign_of(v, i, node):
        wi, bound = fs.w_and_bound(v, i)
        if abs(wi) > bound:
            return (1 if wi > 0 else -1), wi, False
        spend()
        holder["g"].fallback[node] = True
        s = F.sign(system.w(exact_state(node), i))
        return s, wi, True

    def inherit_exact(count):
        # a state's decisions kept from its parent that were made exactly are charged to the
        # budget as if made again (not counted as fallbacks: they were not re-made)
        stats["budget"] += count
        if budget is not None and stats["budget"] > budget:
            raise _FallbackBudget()

    holder["inherit_exact"] = inherit_exact

    def same_exact(node, i, cand):
        spend()
        v, _ = system.reflect(exact_state(node), i)
        return v == exact_state(cand) if F is _Rational else all(
            certified_sign(a - b) == 0 for a, b in zip(v, exact_state(cand)))

    holder["same_exact"] = same_exact

    class _R:
        k = fs.k

        def __call__(self, v, i, wi):
            return fs.reflect(v, i, wi)

    detector = None
    if collapse:
        from .collapse import _CollapseDetector

        detector = _CollapseDetector(system, exact_state, lambda v: tuple(float(F.to_sympy(x)) for x in v),
                                     lambda v: v)
    g, tests = _explore(sign_of, _R(), tuple(float(x) for x in fs.v0), cap, holder, collapse=detector,
                        cap_error=cap_error, affected=_affected(fs, system))
    root_table = _aggregate(g, lambda v: v)
    keys = [key for key in root_table if not (isinstance(key[0], str) and key[0] == "collapse")]
    # merge nearby float outcomes by exact comparison of their replays
    canon: dict = {}
    reps: list = []
    tol = 2 * FLOAT_SAFETY * fs.energy_error + 8 * _EPS * max(1.0, math.sqrt(float(fs.v0 @ fs.M @ fs.v0)))
    exact_of: dict = {}
    for key in keys:
        for r in reps:
            d = np.asarray(key) - np.asarray(r)
            if key == r or math.sqrt(max(float(d @ fs.M @ d), 0.0)) <= tol:
                if key != r:
                    stats["fallbacks"] += 1
                    stats["budget"] += 1
                    for kk in (key, r):
                        if kk not in exact_of:
                            exact_of[kk] = system.replay(root_table[kk][3])[0]
                    if exact_of[key] != exact_of[r] and not (
                            F is _Algebraic and all(certified_sign(a - b) == 0
                                                    for a, b in zip(exact_of[key], exact_of[r]))):
                        continue
                canon[key] = r
                break
        else:
            reps.append(key)
            canon[key] = key
    return g, tests, stats["fallbacks"], root_table, canon, fs
