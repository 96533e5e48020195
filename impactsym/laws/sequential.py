"""Simultaneous impacts resolved by sequences of single impacts (Seghete & Murphey, sec. III).

The corner impact ``M``, ``H`` (rows of the closed contacts), ``v0`` is replaced by every sequence
of single elastic impacts ``v ↦ G_{H_i} v`` that nearby trajectories with infinitesimal gaps can
undergo (sec. III-B): every surface the current velocity violates (``H_i v < 0``) opens a branch,
the surface just applied cannot be violated (``H_i G_{H_i} v = −H_i v``), and a branch stops when
its velocity is valid on every closed contact (``H v ≥ 0``). The outcomes, with their orderings
and reflection counts, then feed the selection of sec. III-A, steps 4–5: the feasible set is the
conic hull of the outcomes together with the requirement that the momentum jump ``M(v⁺ − v0)``
lie in ``cone(Hᵀ)``; the trivial solution ``v0`` is projected onto it in the kinetic metric.

How the search is organized
---------------------------
* **A DAG, not a tree.** The legal next surfaces are a function of the velocity alone, so states
  are memoized on ``(velocity, legal surfaces)``; the number of orderings can be exponential while
  the number of states (``states_visited``) stays small (an n-ball cradle with equal masses sorts
  its velocities by adjacent swaps, so its states are the distinct permutations it reaches).
* **Exact by default.** ``G_u`` is rational in ``M``, ``u`` and ``v``: rational data are handled
  with python-flint ``fmpq`` (sparse rows, no matrices formed), algebraic data with SymPy and every
  sign certified by :func:`impactsym.exact.certified_sign`. Outcomes are merged exactly.
* **Float mode** (any float input, or ``exact=False``): velocities are float64. Each sign test
  ``H_i v`` carries an error bound; when the bound straddles zero the sign is re-decided exactly
  from the floats' exact binary values (:func:`impactsym.numbers.float_to_rational`) by replaying
  the ordering in rational arithmetic. ``exact_fallbacks`` counts those decisions. The bound
  (stated, not proven): reflections are isometries of the kinetic metric, so float errors are not
  amplified, and each reflection adds at most ``γ‖v0‖_M`` with ``γ = FLOAT_ERROR_FACTOR · n ·
  κ₂(M) · eps`` (the float path's documented bound, :mod:`impactsym.laws.reflection`); with at
  most ``max_reflections`` reflections on any path, ``|fl(H_i v) − H_i v| ≤ SAFETY · (√(H_i M⁻¹
  H_iᵀ) · max_reflections · γ ‖v0‖_M + 2 n eps Σ_j |H_ij v_j|)``. Two float outcomes closer than
  twice that bound are compared exactly (replayed) and merged only when exactly equal.
* **Refusals.** Before iterating, :func:`valid_velocity_witness` decides exactly whether a
  non-zero ``v`` with ``H v ≥ 0`` exists; if not, no elastic outcome exists and
  :class:`~impactsym.errors.DomainError` is raised. A path longer than ``max_reflections``, or a
  velocity that recurs on its own path (an exact proof of an endless sequence), raises
  :class:`~impactsym.errors.NonTermination` naming the cap.

Selection: two readings of the feasible set
-------------------------------------------
``reading="energy"`` (default): ``cone(outcomes) ∩ {M(v − v0) ∈ cone(Hᵀ)} ∩ {‖v‖_M = ‖v0‖_M}``.
``reading="cone"``: the same without the energy sphere; it admits ``v = 0`` whenever
``−M v0 ∈ cone(Hᵀ)``, and when ``v0`` has a negative kinetic inner product with every outcome
(as in the paper's sec. III-B.3, where the outcomes are near ``−v0``) the projection of ``v0`` onto
the cone is ``0``: all kinetic energy lost. Only the energy reading reproduces sec. III-B.3's
"invariably … either v4a or v4b" (tested in ``tests/test_sequential_paper.py``): on the
energy sphere the feasible set is the arc between the two outcomes, and the point of an arc
nearest ``v0`` is an end point unless the arc contains ``v0``'s direction. When both orderings
take four reflections the two end points are *equally* near ``v0`` (``G_b = G_a⁻¹`` and ``G_a`` is
a kinetic isometry, so ``⟨G_a v0, v0⟩_M = ⟨v0, G_b v0⟩_M``): the projection is not unique and
both are returned; when the lengths differ (3 and 4) one of them is selected.

Two more findings are pinned in the tests: the printed ``G_u = −I`` of sec. III-B.3 is a misprint
for ``diag(−1, 1)`` (the printed ``v4a``, ``v4b`` were computed with the latter), and for three or
more surfaces the branching rule also produces orderings that no small gaps realize
(``tests/test_simulate.py``), sometimes with outcomes that no realizable ordering gives: for balls
of masses 1, 3, 4 against a wall with ``v0 = (−1, −3, 0)`` the rule gives 5 distinct outcomes from
15 orderings, but only 1 ordering is realizable and every small-gap simulation ends at
``(1/7, 5/7, 18/7)``. This resolver implements the paper's rule as stated (all orderings).

The projection is computed exactly by enumerating the faces of the feasible polyhedron: for every
linearly independent set ``T`` of outcomes and ``S`` of contacts, the affine subspace
``span(O_T) ∩ (v0 + span(M⁻¹H_Sᵀ))`` yields its candidate (the kinetic projection of ``v0``; on the
energy sphere, the critical points of ``⟨v, v0⟩_M``, exact in ``Q(√q)``), kept when its
coefficients on ``O_T`` and ``M⁻¹H_Sᵀ`` are ``≥ 0`` (exact signs). The optimum lies in the relative
interior of a face and is found among these candidates. All minimizers are returned (ties).

References
----------
Seghete & Murphey, sec. II-A (``G_u``), sec. III-A (feasible set, algorithm steps 1–5),
sec. III-B (branching, the count ``n(n−1)^{N−1}``, the examples), sec. III-C (termination, two
surfaces only).

Examples
--------
Two balls and a wall, equal masses (sec. III-B.1): both orderings give ``−v0``.

>>> r = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2")
>>> [(o.order, o.reflections, list(o.velocity)) for o in r.outcomes]
[((0, 1, 0, 1), 4, [1, 2])]
>>> r.orderings, list(r.selected[0])
(2, [1, 2])

Three-ball cradle, ``[1, 1, 0] → [0, 1, 1]`` (eq. 4):

>>> list(resolve_sequential("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,1,0").outcomes[0].velocity)
[0, 1, 1]

A ball pinched between two walls has no elastic outcome:

>>> resolve_sequential("1", "1;-1", "1")
Traceback (most recent call last):
...
impactsym.errors.DomainError: gradients: no non-zero velocity v satisfies H v >= 0 (the closed contacts admit no elastic exit velocity)
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any, Iterator

import numpy as np
import sympy as sp
from flint import fmpq, fmpq_mat

from ..errors import DomainError, ImpactInputError, NonTermination
from ..exact import certified_sign
from ..mechanics import check_gradients, check_mass_matrix, check_velocity
from ..numbers import float_to_rational, is_exact
from .reflection import FLOAT_ERROR_FACTOR

__all__ = [
    "resolve_sequential",
    "SequentialResolution",
    "Outcome",
    "valid_velocity_witness",
    "termination_bound",
    "READINGS",
    "DEFAULT_MAX_REFLECTIONS",
    "MAX_STATE_BITS",
    "MAX_COORDINATES",
    "FLOAT_SAFETY",
    "SELECTION_FACE_LIMIT",
    "TWO_SURFACE_PATHS",
]

#: the two readings of the feasible set (see the module docstring)
READINGS = ("energy", "cone")
#: how two independent surfaces are resolved (see ``resolve_sequential(two_surface=...)``)
TWO_SURFACE_PATHS = ("closed-form", "iterate")
#: default cap on the reflections of any one ordering
DEFAULT_MAX_REFLECTIONS = 10_000
#: largest total size (bits of numerators and denominators) of the exact velocities the rational
#: search keeps; beyond it the search raises NonTermination naming this limit (32 MiB)
MAX_STATE_BITS = 1 << 28
#: largest number of coordinates (size of M) the resolver accepts: its exact input checks and
#: linear algebra cost O(n^3) to O(n^4) exact operations (n = 200 takes about 10 s; a 1000-ball
#: cradle would take many minutes), so larger systems are refused up front
MAX_COORDINATES = 200
#: safety factor on the float sign-test bound
FLOAT_SAFETY = 4.0
_EPS = float(np.finfo(float).eps)


# ---------------------------------------------------------------------------------------------
# Arithmetic backends: rational (python-flint), algebraic (SymPy, certified signs)
# ---------------------------------------------------------------------------------------------
class _Rational:
    """Exact rationals with python-flint ``fmpq``."""

    name = "rational"

    @staticmethod
    def num(x) -> fmpq:
        x = sp.Rational(x)
        return fmpq(int(x.p), int(x.q))

    @staticmethod
    def sign(x) -> int:
        return (x > 0) - (x < 0)

    @staticmethod
    def norm(x):
        return x

    @staticmethod
    def to_sympy(x) -> sp.Rational:
        return sp.Rational(int(x.p), int(x.q))

    zero = fmpq(0)
    one = fmpq(1)

    @staticmethod
    def surd_sign(alpha, beta, q) -> int:
        """Sign of ``alpha + beta·√q`` (``q ≥ 0``), exactly."""
        sa, sb = _Rational.sign(alpha), _Rational.sign(beta) if q != 0 else 0
        if sb == 0:
            return sa
        if sa == 0 or sa == sb:
            return sb
        # opposite signs: compare alpha² with beta² q
        d = alpha * alpha - beta * beta * q
        return sa * _Rational.sign(d)


class _Algebraic:
    """Exact SymPy numbers; every sign certified."""

    name = "algebraic"

    @staticmethod
    def num(x):
        return sp.sympify(x)

    @staticmethod
    def sign(x) -> int:
        return certified_sign(x)

    @staticmethod
    def norm(x):
        return sp.radsimp(sp.expand(x))

    @staticmethod
    def to_sympy(x):
        return x

    zero = sp.Integer(0)
    one = sp.Integer(1)

    @staticmethod
    def surd_sign(alpha, beta, q) -> int:
        return certified_sign(alpha + beta * sp.sqrt(q))


def _all_rational(*mats) -> bool:
    return all(x.is_Rational for m in mats for x in m)


# ---------------------------------------------------------------------------------------------
# Exact linear algebra on lists (works for fmpq and SymPy numbers)
# ---------------------------------------------------------------------------------------------
def _rref(rows: list[list], ncols: int, F) -> tuple[list[list], list[int]]:
    A = [list(r) for r in rows]
    pivots: list[int] = []
    r = 0
    for c in range(ncols):
        piv = next((i for i in range(r, len(A)) if F.sign(A[i][c]) != 0), None)
        if piv is None:
            continue
        A[r], A[piv] = A[piv], A[r]
        inv = F.one / A[r][c]
        A[r] = [F.norm(x * inv) for x in A[r]]
        for i in range(len(A)):
            if i != r and F.sign(A[i][c]) != 0:
                f = A[i][c]
                A[i] = [F.norm(a - f * b) for a, b in zip(A[i], A[r])]
        pivots.append(c)
        r += 1
        if r == len(A):
            break
    return A[:r], pivots


def _kernel_basis(R: list[list], piv: list, m: int, F) -> list[list]:
    """A basis of the solutions of the homogeneous system whose reduced row echelon form is
    ``R`` with pivot columns ``piv``, over the first ``m`` columns: one vector per free column."""
    basis = []
    for f in (c for c in range(m) if c not in piv):
        x = [F.zero] * m
        x[f] = F.one
        for i, p in enumerate(piv):
            x[p] = F.norm(-R[i][f])
        basis.append(x)
    return basis


def _nullspace(rows: list[list], ncols: int, F) -> list[list]:
    R, piv = _rref(rows, ncols, F)
    return _kernel_basis(R, piv, ncols, F)


def _solve_columns(cols: list[list], b: list, F):
    """Solve ``[cols] z = b``: ``(z0, nullspace basis)`` or ``None`` when inconsistent."""
    m = len(cols)
    n = len(b)
    aug = [[cols[j][i] for j in range(m)] + [b[i]] for i in range(n)]
    R, piv = _rref(aug, m + 1, F)
    if m in piv:
        return None
    z0 = [F.zero] * m
    for i, p in enumerate(piv):
        z0[p] = R[i][m]
    return z0, _kernel_basis(R, piv, m, F)


def _rank(vectors: list[list], F) -> int:
    if not vectors:
        return 0
    return len(_rref(vectors, len(vectors[0]), F)[1])


def _independent(vectors: list[list], F) -> list[int]:
    """Indices of a maximal independent subset (greedy, in order)."""
    keep: list[int] = []
    for i, v in enumerate(vectors):
        if _rank([vectors[j] for j in keep] + [v], F) > len(keep):
            keep.append(i)
    return keep


def _dot(a, b, F):
    return F.norm(sum((x * y for x, y in zip(a, b)), F.zero))


def _matvec(M, v, F):
    return [_dot(row, v, F) for row in M]


def _minner(M, a, b, F):
    return _dot(a, _matvec(M, b, F), F)


# ---------------------------------------------------------------------------------------------
# Refusal: is any non-zero velocity valid?
# ---------------------------------------------------------------------------------------------
def valid_velocity_witness(gradients, *, exact: bool | None = None):
    """A non-zero ``v`` with ``H v ≥ 0`` (exact), or ``None`` when none exists.

    Decided exactly: if ``rank H < n`` a null vector of ``H`` is a witness; otherwise the cone
    ``{v : H v ≥ 0}`` is pointed and is non-zero exactly when it has an extreme ray, which spans
    the null space of ``n − 1`` linearly independent rows of ``H``; every such subset is tried.
    Float input is decided on the floats' exact binary values.

    Parameters
    ----------
    gradients : matrix-like (k×n), the gradient rows ``H``

    Returns
    -------
    sympy.Matrix (n×1) or None

    Examples
    --------
    >>> valid_velocity_witness("1,0;-1,1").T
    Matrix([[0, 1]])
    >>> valid_velocity_witness("1;-1") is None
    True
    >>> valid_velocity_witness("1,0;0,1;-1,-1") is None
    True
    """
    H = gradients
    if not isinstance(H, sp.MatrixBase) or not is_exact(H):
        from ..numbers import to_exact_matrix

        H = to_exact_matrix(H, "gradients")
    k, n = H.shape
    F = _Rational if _all_rational(H) else _Algebraic
    rows = [[F.num(H[i, j]) for j in range(n)] for i in range(k)]
    null = _nullspace(rows, n, F)
    if null:
        return sp.Matrix([F.to_sympy(x) for x in null[0]])
    for subset in itertools.combinations(range(k), n - 1):
        sub = [rows[i] for i in subset]
        ns = _nullspace(sub, n, F) if sub else [[F.one if j == 0 else F.zero for j in range(n)]] if n == 1 else None
        if ns is None or len(ns) != 1:
            continue
        r = ns[0]
        signs = {F.sign(_dot(row, r, F)) for row in rows}
        if signs <= {0, 1}:
            return sp.Matrix([F.to_sympy(x) for x in r])
        if signs <= {0, -1}:
            return sp.Matrix([F.to_sympy(-x) for x in r])
    return None


# ---------------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Outcome:
    """One distinct exit velocity of the sequential resolution.

    Attributes
    ----------
    order : tuple of int
        A representative ordering (surface indices, rows of ``H``): the shortest, then the
        lexicographically first, of the orderings that give this velocity.
    reflections : int
        ``len(order)``.
    velocity : sympy.Matrix (exact) or numpy.ndarray (float mode)
    impulse : sympy.Matrix or numpy.ndarray (k,)
        ``p`` of ``M(v⁺ − v0) = Hᵀp`` accumulated along ``order`` (every entry ``≥ 0``).
    orderings : int
        How many orderings give this velocity.
    reflections_min, reflections_max : int
        Shortest and longest of those orderings.
    """

    order: tuple
    reflections: int
    velocity: Any
    impulse: Any
    orderings: int
    reflections_min: int
    reflections_max: int

    @property
    def velocity_float(self) -> list[float]:
        return _floats(self.velocity)


def _floats(v) -> list[float]:
    import mpmath

    if isinstance(v, mpmath.matrix):
        return [float(v[i]) for i in range(v.rows)]
    if isinstance(v, sp.MatrixBase):
        return [float(sp.N(x, 17)) for x in v]
    return [float(x) for x in np.asarray(v, dtype=float).reshape(-1)]


@dataclass
class SequentialResolution:
    """Everything the sequential resolver found.

    Attributes
    ----------
    outcomes : tuple of Outcome
        The distinct exit velocities (merged exactly), sorted by representative ordering.
    selected : tuple
        The minimizers of ``‖v − v0‖_M`` over the feasible set of ``reading`` (usually one;
        ties are all listed). Exact (SymPy) in exact mode and in float mode (computed from the
        exact replays of the float outcomes; see ``selected_float``); with the two-surface
        closed form it is the selected outcome itself (exact, certified ``mpmath.matrix`` or
        float, like the outcome). Empty when ``select=False``, or as ``selection_note`` says.
    reading : str
        ``"energy"`` or ``"cone"``.
    orderings : int
        Number of orderings (root-to-exit paths), counted on the DAG.
    max_reflections_used : int
        Length of the longest ordering.
    states_visited : int
        Distinct states (velocity, legal surfaces) of the DAG.
    sign_tests : int
        Sign decisions ``H_i v`` made.
    exact_fallbacks : int
        Float mode: decisions re-made exactly because the float bound straddled zero, plus the
        exact comparisons that let such a state be shared in the DAG and that merge nearby float
        outcomes. 0 in exact mode.
    exact : bool
        Whether the outcome velocities are exact.
    backend : str
        ``"rational"``, ``"algebraic"`` or ``"float"``.
    approaching : tuple of bool
        ``H_i v0 < 0`` for each contact (decided exactly or certified).
    witness : sympy.Matrix
        A non-zero valid velocity (``H v ≥ 0``), the certificate that the refusal check passed.
    method : str
        ``"iteration"`` (the DAG search) or ``"two-surface closed form"``
        (:func:`impactsym.laws.two_surface.resolve_two_surfaces`, used for two independent rows).
    bound : int or None
        Two surfaces: the paper's ``N = ⌈S_total/(2S₀)⌉`` (sec. III-C), certified.
    """

    outcomes: tuple
    selected: tuple
    reading: str
    orderings: int
    max_reflections_used: int
    states_visited: int
    sign_tests: int
    exact_fallbacks: int
    exact: bool
    backend: str
    approaching: tuple
    witness: Any
    method: str = "iteration"
    bound: int | None = None
    #: why ``selected`` is empty although ``select=True`` (``None`` otherwise)
    selection_note: str | None = None
    _graph: Any = field(default=None, repr=False, compare=False)
    _orders: Any = field(default=None, repr=False, compare=False)

    @property
    def selected_float(self) -> list[list[float]]:
        return [_floats(v) for v in self.selected]

    def iter_orderings(self, limit: int | None = None) -> Iterator[tuple[tuple, int]]:
        """Every ordering with the index of its outcome in :attr:`outcomes`, depth first.

        >>> r = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2")
        >>> list(r.iter_orderings())
        [((0, 1, 0, 1), 0), ((1, 0, 1, 0), 0)]
        """
        if self._graph is None:  # two-surface closed form: one ordering per first surface
            for count, (order, idx) in enumerate(self._orders, 1):
                yield (tuple(order) if isinstance(order, tuple) else order), idx
                if limit is not None and count >= limit:
                    return
            return
        g = self._graph
        count = 0
        stack = [(g.root, ())]
        while stack:
            node, path = stack.pop()
            kids = g.children[node]
            if not kids:
                yield path, g.outcome_index[g.terminal_key[node]]
                count += 1
                if limit is not None and count >= limit:
                    return
                continue
            for i, child in reversed(kids):
                stack.append((child, path + (i,)))


# ---------------------------------------------------------------------------------------------
# The search
# ---------------------------------------------------------------------------------------------
class _Graph:
    def __init__(self):
        self.vel: list = []
        self.legal: list = []
        self.children: list = []
        self.parent: list = []
        self.fallback: list = []
        self.index: dict = {}
        self.root = 0
        self.terminal_key: dict = {}
        self.outcome_index: dict = {}


class _ExactSystem:
    """Exact data of ``M``, ``H``, ``v0`` in one backend, in sparse form."""

    def __init__(self, M: sp.Matrix, H: sp.Matrix, v0: sp.Matrix):
        self.F = F = _Rational if _all_rational(M, H, v0) else _Algebraic
        self.n, self.k = M.shape[0], H.shape[0]
        n, k = self.n, self.k
        self.M = [[F.num(M[i, j]) for j in range(n)] for i in range(n)]
        self.H = [[F.num(H[i, j]) for j in range(n)] for i in range(k)]
        self.v0 = tuple(F.num(x) for x in v0)
        if F is _Rational:
            Wm = fmpq_mat(self.M).solve(fmpq_mat([list(col) for col in zip(*self.H)]) if k else fmpq_mat(n, 0))
            self.W = [[Wm[j, i] for j in range(n)] for i in range(k)]
        else:
            Ws = M.LUsolve(H.T)
            self.W = [[F.norm(Ws[j, i]) for j in range(n)] for i in range(k)]
        self.s = [_dot(self.H[i], self.W[i], F) for i in range(k)]
        self.coef = [F.norm(2 / s) if F is _Algebraic else fmpq(2) / s for s in self.s]
        self.rows = [[(j, h) for j, h in enumerate(r) if F.sign(h) != 0] for r in self.H]
        self.wcols = [[(j, w) for j, w in enumerate(c) if F.sign(w) != 0] for c in self.W]
        #: column i of the Gram matrix H M^-1 H^T, sparse: how w = H v changes when surface i acts
        self.gcols = [[(j, a) for j in range(k) if F.sign(a := self.w(self.W[i], j)) != 0] for i in range(k)]

    def w(self, v, i):
        F = self.F
        return F.norm(sum((h * v[j] for j, h in self.rows[i]), F.zero))

    def reflect(self, v, i, wi=None):
        F = self.F
        if wi is None:
            wi = self.w(v, i)
        c = self.coef[i] * wi
        out = list(v)
        for j, wj in self.wcols[i]:
            out[j] = F.norm(v[j] - c * wj)
        return tuple(out), F.norm(-c)

    def replay(self, order):
        v = self.v0
        p = [self.F.zero] * self.k
        for i in order:
            v, pi = self.reflect(v, i)
            p[i] = self.F.norm(p[i] + pi)
        return v, p


def _state_bits_error(states):
    return NonTermination(
        f"max_reflections: the exact states of the search exceed MAX_STATE_BITS={MAX_STATE_BITS} bits "
        f"after {states} states (the rationals grow with every reflection); lower max_reflections, give "
        "floats, or use the two-surface closed form")


def _cycle_error(cap):
    return NonTermination(
        f"max_reflections: a velocity recurred on its own ordering, so that ordering never ends "
        f"(the sequence of single impacts cycles; cap {cap})")


def _cap_error(cap):
    return NonTermination(
        f"max_reflections: an ordering needs more than {cap} reflections (the configured cap "
        f"max_reflections={cap}); raise the cap or use the two-surface closed form")


def _postorder(g):
    order = []
    seen = set()
    stack = [(g.root, False)]
    while stack:
        node, done = stack.pop()
        if done:
            order.append(node)
            continue
        if node in seen:
            continue
        seen.add(node)
        stack.append((node, True))
        for _, child in g.children[node]:
            if child not in seen:
                stack.append((child, False))
    return order


def _aggregate(g, key_of):
    """Per node and outcome: ordering count, shortest and longest length, and a pointer to the
    representative ordering (shortest, then lexicographically first: among equally short ones
    the smallest first surface, then the child's representative). Returns the root's table as
    ``{outcome key: [count, min_len, max_len, rep_order]}``."""
    post = _postorder(g)
    terminals = {key_of(g.vel[nd]) for nd in post if not g.children[nd]}
    if len(terminals) == 1:  # one outcome (the cradles): plain lists instead of per-node dicts
        (key,) = terminals
        cnt = [0] * len(g.vel)
        lo = [0] * len(g.vel)
        hi = [0] * len(g.vel)
        nxt: list = [None] * len(g.vel)
        for node in post:
            kids = g.children[node]
            if not kids:
                g.terminal_key[node] = key
                cnt[node] = 1
                continue
            c, l, h, p = 0, None, 0, None
            for i, child in kids:
                c += cnt[child]
                if hi[child] + 1 > h:
                    h = hi[child] + 1
                if l is None or (lo[child] + 1, i) < (l, p[0]):
                    l, p = lo[child] + 1, (i, child)
            cnt[node], lo[node], hi[node], nxt[node] = c, l, h, p
        rep = []
        node = g.root
        while nxt[node] is not None:
            i, node = nxt[node]
            rep.append(i)
        return {key: [cnt[g.root], lo[g.root], hi[g.root], tuple(rep)]}
    table: dict[int, dict] = {}
    best: dict[int, dict] = {}
    ids: dict = {}
    keys: list = []
    for node in post:
        kids = g.children[node]
        if not kids:
            key = key_of(g.vel[node])
            g.terminal_key[node] = key
            oid = ids.setdefault(key, len(ids))
            if oid == len(keys):
                keys.append(key)
            table[node] = {oid: [1, 0, 0]}
            best[node] = {oid: None}
            continue
        acc: dict = {}
        ptr: dict = {}
        for i, child in kids:
            for oid, (cnt, lo, hi) in table[child].items():
                a = acc.get(oid)
                if a is None:
                    acc[oid] = [cnt, lo + 1, hi + 1]
                    ptr[oid] = (lo + 1, i, child)
                else:
                    a[0] += cnt
                    if hi + 1 > a[2]:
                        a[2] = hi + 1
                    if lo + 1 < a[1]:
                        a[1] = lo + 1
                    if (lo + 1, i) < ptr[oid][:2]:
                        ptr[oid] = (lo + 1, i, child)
        table[node] = acc
        best[node] = ptr
    out = {}
    for oid, (cnt, lo, hi) in table[g.root].items():
        rep = []
        node = g.root
        while best[node][oid] is not None:
            _, i, node = best[node][oid]
            rep.append(i)
        out[keys[oid]] = [cnt, lo, hi, tuple(rep)]
    return out


def _coordinates(mass_matrix):
    """The number of rows of ``mass_matrix`` read without converting it (``None`` if unknown)."""
    if isinstance(mass_matrix, str):
        return mass_matrix.count(";") + 1
    shape = getattr(mass_matrix, "shape", None)
    if shape is not None and len(shape) >= 1:
        return int(shape[0])
    if isinstance(mass_matrix, (list, tuple)):
        return len(mass_matrix)
    return None


def _check_inputs(mass_matrix, gradients, velocity, exact):
    if exact is None:
        exact = is_exact(mass_matrix, gradients, velocity)
    M = check_mass_matrix(mass_matrix, exact=exact)
    n = M.shape[0]
    H = check_gradients(gradients, n, exact=exact)
    v = check_velocity(velocity, n, exact=exact)
    return exact, M, H, v


def resolve_sequential(mass_matrix, gradients, velocity, *, reading: str = "energy",
                       max_reflections: int = DEFAULT_MAX_REFLECTIONS, exact: bool | None = None,
                       select: bool = True, two_surface: str = "closed-form") -> SequentialResolution:
    """Every impact ordering of a corner impact, its outcomes, and the selected solution.

    Parameters
    ----------
    mass_matrix : matrix-like (n×n), symmetric positive definite
    gradients : matrix-like (k×n), gradient rows ``H_i`` of the closed contacts, any k ≥ 1
    velocity : vector-like (n,), pre-impact velocity ``v0``
    reading : ``"energy"`` (default) or ``"cone"``
        The feasible set of the selection: conic hull of the outcomes with the momentum-cone
        requirement, intersected with the energy sphere (``"energy"``) or not (``"cone"``).
    max_reflections : int
        Cap on the reflections of any one ordering; exceeding it raises ``NonTermination``.
    exact : bool, optional
        Force the exact (``True``) or float (``False``) path; default: exact iff every input is.
    select : bool
        Compute the selection (steps 4–5). ``False`` skips it (``selected`` is empty).
    two_surface : ``"closed-form"`` (default) or ``"iterate"``
        With exactly two linearly independent rows, ``"closed-form"`` takes every branch from
        :func:`impactsym.laws.two_surface.resolve_two_surfaces` in O(1), whatever the count (the
        reflection cap does not apply: nothing is iterated); ``"iterate"`` forces the search,
        and is refused up front (``NonTermination``) when the certified count of a branch
        exceeds ``max_reflections``. With the closed form the energy reading selects the
        outcome(s) with the largest ``⟨o, v0⟩_M`` (exact, or certified Arb comparison of
        certified outcomes; see :func:`_two_surface_path`); the cone reading of certified
        outcomes is skipped in exact mode (``selected`` empty, ``selection_note`` says why) and
        refused in float mode (``DomainError``): a float run never succeeds with an empty
        selection.

    Returns
    -------
    SequentialResolution

    Raises
    ------
    ImpactInputError
        Bad shapes, a mass matrix that is not SPD, a zero gradient row, a bad ``reading`` or cap,
        more than ``MAX_COORDINATES`` coordinates (refused before any exact work).
    DomainError
        No non-zero velocity is valid for all closed contacts (no elastic outcome exists).
    NonTermination
        An ordering exceeds ``max_reflections`` or provably never ends, or the exact states of
        the search exceed ``MAX_STATE_BITS``.
    VerificationError
        An exact outcome failed its check before return (a bug; never returned).

    Examples
    --------
    ``M = diag(11/10, 1)``, both contacts approaching: two outcomes (sec. III-B.3). The two
    orderings of length 4 apply a kinetic rotation and its inverse, so both outcomes are equally
    near ``v0``: the energy reading selects both (a tie); the plain cone selects ``0``.

    >>> r = resolve_sequential("11/10,0;0,1", "1,0;-1,1", "-1,-2")
    >>> [(o.order, list(o.velocity)) for o in r.outcomes]
    [((0, 1, 0, 1), [173/147, 278/147]), ((1, 0, 1, 0), [359/441, 922/441])]
    >>> r.selected == tuple(o.velocity for o in r.outcomes)
    True
    >>> list(resolve_sequential("11/10,0;0,1", "1,0;-1,1", "-1,-2", reading="cone").selected[0])
    [0, 0]

    Float mode counts its exact fallbacks (here the grazing contact 2–3 of the cradle):

    >>> r = resolve_sequential(np.eye(3), [[-1.0, 1, 0], [0, -1, 1]], [1.0, 0, 0], two_surface="iterate")
    >>> r.outcomes[0].velocity, r.exact, r.exact_fallbacks > 0
    (array([0., 0., 1.]), False, True)

    References
    ----------
    Seghete & Murphey, sec. III-A (algorithm steps 1–5), sec. III-B (branching), eq. 4.
    """
    if reading not in READINGS:
        raise ImpactInputError("reading", f"must be one of {', '.join(READINGS)}, got {reading!r}")
    if isinstance(max_reflections, bool) or not isinstance(max_reflections, (int, np.integer)) or max_reflections < 1:
        raise ImpactInputError("max_reflections", f"must be a positive integer, got {max_reflections!r}")
    cap = int(max_reflections)
    if two_surface not in TWO_SURFACE_PATHS:
        raise ImpactInputError("two_surface", f"must be one of {', '.join(TWO_SURFACE_PATHS)}, got {two_surface!r}")
    size = _coordinates(mass_matrix)
    if size is not None and size > MAX_COORDINATES:
        raise ImpactInputError(
            "mass_matrix", f"has {size} coordinates, more than the sequential law's limit MAX_COORDINATES="
            f"{MAX_COORDINATES} (its exact checks and linear algebra cost O(n^3) or more exact operations)")
    exact, M, H, v0 = _check_inputs(mass_matrix, gradients, velocity, exact)
    if exact:
        Mx, Hx, vx = M, H, v0
    else:
        Mx = sp.Matrix([[float_to_rational(x) for x in row] for row in M])
        Hx = sp.Matrix([[float_to_rational(x) for x in row] for row in H])
        vx = sp.Matrix([float_to_rational(x) for x in v0])
    witness = valid_velocity_witness(Hx)
    if witness is None:
        raise DomainError("gradients: no non-zero velocity v satisfies H v >= 0 "
                          "(the closed contacts admit no elastic exit velocity)")
    system = _ExactSystem(Mx, Hx, vx)
    F = system.F
    if system.k == 2 and _rank(system.H, F) == 2:
        if two_surface == "closed-form":
            return _two_surface_path(M, H, v0, system, exact, reading, select, witness)
        # iterating: refuse up front when a branch needs more than the cap (its exact states grow
        # linearly, so reaching the cap would cost memory quadratic in it)
        from .two_surface import branch_counts

        counts = branch_counts(Mx, Hx, vx)
        if counts and max(counts.values()) > cap:
            raise NonTermination(
                f"max_reflections: the ordering starting with surface {max(counts, key=counts.get)} needs "
                f"{max(counts.values())} reflections (certified count of the two-surface closed form), more "
                f"than the cap max_reflections={cap}; raise the cap or use the two-surface closed form")
    if exact:
        # a state is (v, w = H v); w is updated with the Gram matrix H M^-1 H^T, not recomputed
        if F is _Rational:
            def sign_of(state, i, node):
                wi = state[1][i]
                return (wi > 0) - (wi < 0), wi
        else:
            def sign_of(state, i, node):
                wi = state[1][i]
                return F.sign(wi), wi

        if F is _Rational:
            def key_of(state):
                return tuple([(x.p, x.q) for x in state[0]])
        else:
            def key_of(state):
                return state[0]
        if F is _Rational:
            g, tests = _explore_rational(system, cap)
        else:
            w0 = tuple(system.w(system.v0, i) for i in range(system.k))
            g, tests = _explore(sign_of, _Reflector(system), (system.v0, w0), cap, {}, key_of)
            g.vel = [state[0] for state in g.vel]
        root_table = _aggregate(g, lambda v: v)
        fallbacks = 0
        keys = list(root_table)
        merged = _merge_exact_keys(keys, F)
    else:
        g, tests, fallbacks, root_table, merged, float_sys = _float_search(M, H, v0, system, cap)
    approaching = tuple(F.sign(system.w(system.v0, i)) < 0 for i in range(system.k))
    # Merge outcome keys that are the same velocity (exact comparison), aggregate stats.
    groups: dict = {}
    for key in root_table:
        canon = merged[key]
        cnt, lo, hi, rep = root_table[key]
        if canon not in groups:
            groups[canon] = [cnt, lo, hi, rep]
        else:
            a = groups[canon]
            a[0] += cnt
            a[1] = min(a[1], lo)
            a[2] = max(a[2], hi)
            if (len(rep), rep) < (len(a[3]), a[3]):
                a[3] = rep
    items = sorted(groups.items(), key=lambda kv: (len(kv[1][3]), kv[1][3]))
    g.outcome_index = {}
    for idx, (canon, _) in enumerate(items):
        for key, c in merged.items():
            if c == canon:
                g.outcome_index[key] = idx
    outcomes = []
    exact_outcomes = []
    for canon, (cnt, lo, hi, rep) in items:
        v_ex, p_ex = _verified_replay(system, rep)
        exact_outcomes.append((v_ex, p_ex))
        if exact:
            vel = sp.Matrix([F.to_sympy(x) for x in v_ex])
            imp = sp.Matrix([F.to_sympy(x) for x in p_ex])
        else:
            vel = np.array(canon, dtype=float)
            imp = float_sys.impulse(rep)
        outcomes.append(Outcome(rep, len(rep), vel, imp, cnt, lo, hi))
    total = sum(o.orderings for o in outcomes)
    longest = max(o.reflections_max for o in outcomes)
    if longest > cap:
        raise _cap_error(cap)
    selected: tuple = ()
    if select:
        selected = _select(system, [v for v, _ in exact_outcomes], [p for _, p in exact_outcomes], reading)
        _verify_selected(system, selected, reading)
    return SequentialResolution(tuple(outcomes), selected, reading, total, longest, len(g.vel), tests,
                                fallbacks, exact, F.name if exact else "float", approaching, witness, _graph=g)


def _two_surface_path(M, H, v0, system, exact, reading, select, witness):
    """Outcomes of two independent surfaces from the O(1) closed form, merged exactly.

    The selection (energy reading) needs no face enumeration: the feasible set lies on the arc
    of the energy sphere between the two outcomes ``o_1``, ``o_2`` (it is the whole arc when
    ``v0 ∈ span(M⁻¹Hᵀ)``, only its end points otherwise), ``v0``'s direction is not on the arc
    (``v0`` is invalid, the arc is valid), and ``⟨v, v0⟩_M`` restricted to such an arc is largest
    at an end point. So the selection is the outcome(s) with the largest ``⟨o_i, v0⟩_M``: an exact
    comparison, or a certified one (Arb) for certified outcomes. When both branches have the same
    even count the two values are equal exactly (``o_2 = R⁻¹v0`` for ``o_1 = Rv0``, ``R`` a
    kinetic isometry), and both are selected."""
    from .two_surface import resolve_two_surfaces

    F = system.F
    ts = resolve_two_surfaces(M, H, v0)
    groups: list = []  # [velocity, [orders], impulse, exact, two-surface outcome]
    for o in ts.outcomes:
        # (reflections, first surface, order): a closed-form order may be too long for len()
        first = -1 if o.first is None else o.first
        order = (o.reflections, first, tuple(o.order) if o.reflections <= 10_000 else o.order)
        for grp in groups:
            if o.exact and grp[3] and all(certified_sign(a - b) == 0 for a, b in zip(o.velocity, grp[0])):
                grp[1].append(order)
                break
            if not exact and not o.exact and grp[3] is False and np.array_equal(o.velocity, grp[0]):
                grp[1].append(order)
                break
        else:
            groups.append([o.velocity, [order], o.impulse, o.exact, o])
    outcomes = []
    orders = []
    for grp in groups:
        grp[1] = sorted(grp[1], key=lambda t: t[:2])  # the iteration's order: shortest, then first surface
    groups.sort(key=lambda grp: grp[1][0][:2])
    for idx, (vel, ords, imp, _, _) in enumerate(groups):
        lens = [t[0] for t in ords]
        outcomes.append(Outcome(ords[0][2], lens[0], vel, imp, len(ords), min(lens), max(lens)))
        orders.extend((t[2], idx) for t in ords)
    selected: tuple = ()
    note = None
    all_exact = all(g[3] for g in groups)
    short = max(o.reflections for o in outcomes) <= 10_000
    if select and reading == "energy" and (exact or not short):
        selected = _select_two_surface(system, groups, exact)
    elif select and (all_exact or not exact):
        if exact:
            exact_outs = [tuple(F.num(x) for x in o.velocity) for o in outcomes]
        elif short:  # float input: replay short orderings exactly (an exact selection)
            exact_outs = [system.replay(o.order)[0] for o in outcomes]
        else:
            raise DomainError(
                f"select: the {reading} reading needs the exact outcomes, but the orderings take "
                f"{max(o.reflections for o in outcomes)} reflections (more than 10000 are not replayed "
                "exactly); use reading='energy' or select=False")
        selected = _select(system, exact_outs, None, reading)
    elif select:
        note = (f"the {reading} reading needs exact outcomes; these are certified digits "
                "(use reading='energy')")
    approaching = tuple(F.sign(system.w(system.v0, i)) < 0 for i in range(system.k))
    res = SequentialResolution(tuple(outcomes), selected, reading, len(orders),
                               max(o.reflections_max for o in outcomes), 0, 2, 0, exact and all_exact,
                               (F.name if exact else "float"), approaching, witness,
                               method="two-surface closed form", bound=ts.bound, _orders=orders)
    res.selection_note = note
    return res


def _select_two_surface(system, groups, exact):
    """The energy-reading selection of the two-surface closed form (see :func:`_two_surface_path`):
    the outcome(s) maximizing ``⟨o, v0⟩_M``, compared exactly or with certified Arb balls."""
    F = system.F
    if len(groups) == 1:
        return (groups[0][0],)
    (va, _, _, ea, oa), (vb, _, _, eb, ob) = groups
    # equal even counts: o_b = R^-1 v0 and o_a = R v0 with R a kinetic isometry, an exact tie
    if oa.reflections == ob.reflections and oa.reflections % 2 == 0:
        return (va, vb)
    if ea and eb and exact:
        val = [_minner(system.M, [F.num(x) for x in vel], list(system.v0), F) for vel in (va, vb)]
        c = F.sign(F.norm(val[0] - val[1]))
    else:
        c = _certified_compare_balls(system, oa, ob)
    return (va,) if c > 0 else (vb,) if c < 0 else (va, vb)


def _certified_compare_balls(system, oa, ob) -> int:
    """Sign of ``⟨o_a − o_b, v0⟩_M`` from the outcomes' Arb balls (exact outcomes are enclosed);
    raises :class:`~impactsym.errors.UndecidableSign` when the balls cannot separate it."""
    from flint import ctx

    from ..errors import UndecidableSign
    from ..verify import enclose

    precs = [o._prec for o in (oa, ob) if getattr(o, "_balls", None) is not None]
    prec = max(precs) if precs else 128
    with ctx.workprec(prec):
        Mb = [[enclose(x, prec) for x in row] for row in system.M]
        vb0 = [enclose(x, prec) for x in system.v0]
        Mv0 = [sum((a * b for a, b in zip(row, vb0)), enclose(0, prec)) for row in Mb]

        def balls(o):
            if getattr(o, "_balls", None) is not None:
                return list(o._balls)
            return [enclose(x, prec) for x in o.velocity]

        diff = sum(((a - b) * m for a, b, m in zip(balls(oa), balls(ob), Mv0)), enclose(0, prec))
        s = 1 if diff > 0 else -1 if diff < 0 else None
    if s is None:
        raise UndecidableSign("selection: <o_1 - o_2, v0>_M could not be separated from 0 by the certified "
                              f"outcomes at {prec} bits (a possible tie between the two outcomes)")
    return s


def _verified_replay(system, order):
    """The exact outcome of ``order`` and its impulse, verified before it is used or returned:
    every reflection acts on an approached surface (``H_i v < 0``: the count is consistent with
    the order), and :func:`impactsym.verify.verify_exact` (``H v⁺ ≥ 0``, energy, momentum, ``p ≥ 0``)."""
    from ..errors import VerificationError
    from ..verify import verify_exact

    F = system.F
    v = system.v0
    p = [F.zero] * system.k
    for step, i in enumerate(order):
        wi = system.w(v, i)
        if F.sign(wi) >= 0:
            raise VerificationError("sequential", f"ordering {tuple(order)[:20]}: reflection {step + 1} acts on "
                                                  f"surface {i}, which is not approached (H_{i + 1} v = {wi})")
        v, pi = system.reflect(v, i, wi)
        p[i] = F.norm(p[i] + pi)
    verify_exact("sequential", system.M, system.H, list(system.v0), list(v), p)
    return v, p


def _verify_selected(system, selected, reading):
    """A rational selected velocity is checked exactly: valid, on the energy sphere (energy
    reading) and with its momentum jump in the row space of ``Hᵀ``. (Its impulse sign is part
    of the selection's own exact feasibility test.)"""
    from ..verify import verify_exact

    for vel in selected:
        if all(x.is_Rational for x in vel):
            verify_exact("sequential (selection)", system.M, system.H, list(system.v0),
                         [system.F.num(x) if system.F is _Rational else x for x in vel], None,
                         energy_ratio=1 if reading == "energy" else None)


def _rational_key(v):
    """A hashable key of an fmpq vector (hashing fmpq itself goes through ``Fraction``, slowly)."""
    return tuple((x.p, x.q) for x in v)


class _Reflector:
    def __init__(self, system):
        self.system = system
        self.k = system.k

    def __call__(self, state, i, wi):
        v, w = state
        sysm = self.system
        F = sysm.F
        c = sysm.coef[i] * wi
        if F is _Rational:  # no normalization needed: fmpq is canonical
            out = list(v)
            for j, wj in sysm.wcols[i]:
                out[j] = v[j] - c * wj
            wn = list(w)
            for j, a in sysm.gcols[i]:
                wn[j] = w[j] - c * a
            return (tuple(out), tuple(wn)), -c
        out = list(v)
        for j, wj in sysm.wcols[i]:
            out[j] = F.norm(v[j] - c * wj)
        wn = list(w)
        for j, a in sysm.gcols[i]:
            wn[j] = F.norm(w[j] - c * a)
        return (tuple(out), tuple(wn)), F.norm(-c)


def _merge_exact_keys(keys, F):
    """Map each outcome key to a canonical key; rational keys are canonical, algebraic ones are
    compared pairwise with certified signs."""
    if F is _Rational:
        return {k: k for k in keys}
    canon: dict = {}
    reps: list = []
    for key in keys:
        for r in reps:
            if all(certified_sign(a - b) == 0 for a, b in zip(key, r)):
                canon[key] = r
                break
        else:
            reps.append(key)
            canon[key] = key
    return canon


# ---------------------------------------------------------------------------------------------
# Float mode
# ---------------------------------------------------------------------------------------------
class _FloatSystem:
    def __init__(self, M, H, v0, cap):
        self.M = np.asarray(M, dtype=float)
        self.H = np.asarray(H, dtype=float)
        self.v0 = np.asarray(v0, dtype=float)
        self.n, self.k = self.M.shape[0], self.H.shape[0]
        W = np.linalg.solve(self.M, self.H.T)
        self.W = W.T.copy()
        self.s = np.einsum("ij,ij->i", self.H, self.W)
        self.coef = 2.0 / self.s
        kappa = float(np.linalg.cond(self.M))
        gamma = FLOAT_ERROR_FACTOR * self.n * kappa * _EPS
        vnorm = math.sqrt(max(float(self.v0 @ self.M @ self.v0), 0.0))
        #: bound on ‖v_float − v_exact‖_M after any ordering of at most `cap` reflections
        self.energy_error = cap * gamma * vnorm
        self.rows = [[(j, float(h)) for j, h in enumerate(r) if h != 0.0] for r in self.H]
        self.wcols = [[(j, float(w)) for j, w in enumerate(c) if w != 0.0] for c in self.W]
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
        c = self.coef[i] * wi
        out = list(v)
        for j, wj in self.wcols[i]:
            out[j] = v[j] - c * wj
        return tuple(out), -c

    def impulse(self, order):
        v = tuple(float(x) for x in self.v0)
        p = np.zeros(self.k)
        for i in order:
            wi, _ = self.w_and_bound(v, i)
            v, pi = self.reflect(v, i, wi)
            p[i] += pi
        return p


def _float_search(M, H, v0, system, cap):
    fs = _FloatSystem(M, H, v0, cap)
    F = system.F
    exact_cache: dict[int, tuple] = {}
    stats = {"fallbacks": 0}
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

    def sign_of(v, i, node):
        wi, bound = fs.w_and_bound(v, i)
        if abs(wi) > bound:
            return (1 if wi > 0 else -1), wi
        stats["fallbacks"] += 1
        holder["g"].fallback[node] = True
        s = F.sign(system.w(exact_state(node), i))
        return s, wi

    def same_exact(node, i, cand):
        stats["fallbacks"] += 1
        v, _ = system.reflect(exact_state(node), i)
        return v == exact_state(cand) if F is _Rational else all(
            certified_sign(a - b) == 0 for a, b in zip(v, exact_state(cand)))

    holder["same_exact"] = same_exact

    class _R:
        k = fs.k

        def __call__(self, v, i, wi):
            return fs.reflect(v, i, wi)

    g, tests = _explore(sign_of, _R(), tuple(float(x) for x in fs.v0), cap, holder)
    root_table = _aggregate(g, lambda v: v)
    keys = list(root_table)
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


def _explore(sign_of, reflect, v0, cap, holder, key_of=lambda v: v):
    """Depth-first construction of the DAG of states, memoized on the velocity.

    ``sign_of(v, i, node) -> (sign, w_i)``; the graph is published in ``holder["g"]`` so that
    ``sign_of`` can replay a node's ordering exactly (float mode)."""
    g = _Graph()
    holder["g"] = g
    counters = {"tests": 0}

    def new_node(v, parent):
        idx = len(g.vel)
        g.vel.append(v)
        g.parent.append(parent)
        g.fallback.append(False)
        g.children.append([])
        legal = []
        ws = {}
        for i in range(reflect.k):
            counters["tests"] += 1
            s, wi = sign_of(v, i, idx)
            if s < 0:
                legal.append(i)
                ws[i] = wi
        g.legal.append((tuple(legal), ws))
        return idx

    root = new_node(v0, None)
    g.index[key_of(v0)] = [root]
    state = {root: 1}
    stack = [(root, iter(g.legal[root][0]))]
    while stack:
        node, it = stack[-1]
        i = next(it, None)
        if i is None:
            stack.pop()
            state[node] = 2
            continue
        child_v, _ = reflect(g.vel[node], i, g.legal[node][1][i])
        child = None
        ckey = key_of(child_v)
        for cand in g.index.get(ckey, ()):
            if not g.fallback[cand]:
                child = cand
                break
            # a node whose signs were decided exactly is shared only with the same exact state
            same_exact = holder.get("same_exact")
            if same_exact is not None and same_exact(node, i, cand):
                child = cand
                break
        if child is None:
            if len(stack) > cap:
                raise _cap_error(cap)
            child = new_node(child_v, (node, i))
            g.index.setdefault(ckey, []).append(child)
            g.children[node].append((i, child))
            state[child] = 1
            stack.append((child, iter(g.legal[child][0])))
        else:
            if state.get(child) == 1:
                raise _cycle_error(cap)
            g.children[node].append((i, child))
    g.root = root
    return g, counters["tests"]


def _explore_rational(system, cap):
    """:func:`_explore` specialized to rational data (the hot path of the benchmarks): states are
    ``(v, w = H v)`` tuples of ``fmpq``, ``w`` is updated through the Gram matrix, the memo key is
    the tuple of numerators and denominators of ``v`` (hashing ``fmpq`` goes through ``Fraction``)."""
    k = system.k
    coef, wcols, gcols = system.coef, system.wcols, system.gcols
    g = _Graph()
    vel, legal_of, children, parent = g.vel, g.legal, g.children, g.parent
    ws_of = []
    index = {}
    tests = 0
    v0 = system.v0
    w0 = tuple(system.w(v0, i) for i in range(k))

    def new_node(v, w, par):
        nonlocal tests
        idx = len(vel)
        vel.append(v)
        ws_of.append(w)
        parent.append(par)
        children.append([])
        tests += k
        legal_of.append(tuple(i for i in range(k) if w[i] < 0))
        return idx

    root = new_node(v0, w0, None)
    index[tuple([(x.p, x.q) for x in v0])] = root
    stored = 0  # bits of the exact velocities kept (the numbers of a long ordering grow linearly)
    state = {root: 1}
    stack = [(root, iter(legal_of[root]))]
    while stack:
        node, it = stack[-1]
        i = next(it, None)
        if i is None:
            stack.pop()
            state[node] = 2
            continue
        v, w = vel[node], ws_of[node]
        c = coef[i] * w[i]
        out = list(v)
        for j, wj in wcols[i]:
            out[j] = v[j] - c * wj
        key = tuple([(x.p, x.q) for x in out])
        child = index.get(key)
        if child is None:
            if len(stack) > cap:
                raise _cap_error(cap)
            stored += sum(p.bit_length() + q.bit_length() for p, q in key)
            if stored > MAX_STATE_BITS:
                raise _state_bits_error(len(vel))
            wn = list(w)
            for j, a in gcols[i]:
                wn[j] = w[j] - c * a
            child = new_node(tuple(out), tuple(wn), (node, i))
            index[key] = child
            children[node].append((i, child))
            state[child] = 1
            stack.append((child, iter(legal_of[child])))
        else:
            if state[child] == 1:
                raise _cycle_error(cap)
            children[node].append((i, child))
    g.fallback = [False] * len(vel)
    g.root = root
    return g, tests


# ---------------------------------------------------------------------------------------------
# Selection (steps 4-5)
# ---------------------------------------------------------------------------------------------
#: largest number of (outcome subset, contact subset) faces the selection enumerates
SELECTION_FACE_LIMIT = 200_000


def _select(system, outcomes, impulses, reading):
    """Minimizers of ‖v − v0‖_M over the feasible set (see the module docstring).

    Values are kept as ``(a, b, q)`` meaning ``a + b√q`` and compared exactly; a face's candidate
    is tested for feasibility only when its value can beat (or tie) the best found so far, and the
    outcomes themselves (feasible by construction) seed the search.
    """
    F = system.F
    n = system.n
    v0 = list(system.v0)
    M = system.M
    O = [list(o) for o in outcomes]
    if reading == "energy" and len(O) == 1:
        # cone(o) ∩ sphere = {o}; o satisfies the momentum requirement by construction
        return (sp.Matrix([F.to_sympy(x) for x in O[0]]),)
    Wc = system.W
    r2 = _minner(M, v0, v0, F)
    zero = [F.zero] * n
    best_val = None
    best: list = []  # velocities (alpha, beta, q)

    def value_of(o):
        if reading == "cone":
            d = [F.norm(a - b) for a, b in zip(o, v0)]
            return (_minner(M, d, d, F), F.zero, F.zero)
        return (_minner(M, o, v0, F), F.zero, F.zero)

    def offer(vel, val):
        nonlocal best_val, best
        if best_val is None:
            best_val, best = val, [vel]
            return
        c = _cmp_values(val, best_val, F)
        if reading == "cone":
            c = -c
        if c > 0:
            best_val, best = val, [vel]
        elif c == 0 and not any(_same_surd(vel, b, F) for b in best):
            best.append(vel)

    for o in O:
        offer((o, zero, F.zero), value_of(o))
    all_O = _independent_subsets(O, n, F)
    all_S = _independent_subsets(Wc, n, F)
    cand_O = _distinct_spans(all_O, O, n, F)
    cand_S = _distinct_spans(all_S, Wc, n, F)
    if len(cand_O) * len(cand_S) > SELECTION_FACE_LIMIT:
        raise DomainError(
            f"selection: {len(cand_O) * len(cand_S)} faces of the feasible set exceed SELECTION_FACE_LIMIT="
            f"{SELECTION_FACE_LIMIT} ({len(O)} outcomes, {len(Wc)} contacts); call with select=False")
    face_cache: set = set()
    full_row_rank = _rank(system.H, F) == system.k
    if full_row_rank:
        gram = [[_dot(hi, wj, F) for wj in Wc] for hi in system.H]  # H M^-1 H^T

        def gram_solve(rhs):
            return _solve_columns([[gram[i][j] for i in range(system.k)] for j in range(system.k)], rhs, F)[0]
    for T in cand_O:
        OT = [O[j] for j in T]
        for S in cand_S:
            cols = OT + [[F.norm(-x) for x in Wc[i]] for i in S]
            if not cols:
                continue
            sol = _solve_columns(cols, v0, F)
            if sol is None:
                continue
            z0, N = sol
            t = len(T)
            c0 = _combo(OT, z0[:t], n, F)
            U = [_combo(OT, y[:t], n, F) for y in N]
            U = [U[j] for j in _independent(U, F)]
            key = _affine_key(c0, U, F)
            if key in face_cache:
                continue
            face_cache.add(key)
            for vel, val in _face_candidates(M, v0, r2, c0, U, reading, F):
                c = _cmp_values(val, best_val, F)
                if reading == "cone":
                    c = -c
                if c < 0 or (c == 0 and any(_same_surd(vel, b, F) for b in best)):
                    continue
                vel = _fold_surd(vel, F)
                alpha, beta, q = vel
                # necessary and cheap: every point of cone(O) is valid (H v >= 0)
                if any(F.surd_sign(_dot(h, alpha, F), _dot(h, beta, F), q) < 0 for h in system.H):
                    continue
                da = [F.norm(a - b) for a, b in zip(alpha, v0)]
                if full_row_rank:  # the impulse is unique: p = (H M^-1 H^T)^-1 H (v - v0) >= 0
                    pa = gram_solve([_dot(h, da, F) for h in system.H])
                    pb = gram_solve([_dot(h, beta, F) for h in system.H])
                    if any(F.surd_sign(x, y, q) < 0 for x, y in zip(pa, pb)):
                        continue
                elif not _in_cone(Wc, all_S, da, beta, q, F):
                    continue
                if not _in_cone(O, all_O, alpha, beta, q, F):
                    continue
                offer(vel, val)
    return tuple(_vel_sympy(v, F) for v in best)


def _affine_key(c0, U, F):
    """A canonical key of the affine subspace c0 + span(U)."""
    n = len(c0)
    if U:
        R, piv = _rref(U, n, F)
        c = list(c0)
        for row, p in zip(R, piv):
            f = c[p]
            if F.sign(f) != 0:
                c = [F.norm(x - f * y) for x, y in zip(c, row)]
        return tuple(tuple(r) for r in R), tuple(c)
    return (), tuple(c0)


def _cmp_values(x, y, F) -> int:
    """Exact sign of ``(a1 + b1√q1) − (a2 + b2√q2)``."""
    a1, b1, q1 = x
    a2, b2, q2 = y
    if F is _Algebraic:
        return certified_sign(a1 + b1 * sp.sqrt(q1) - a2 - b2 * sp.sqrt(q2))
    if F.sign(b2) == 0 or F.sign(q2) == 0:
        return F.surd_sign(a1 - a2, b1, q1)
    if F.sign(b1) == 0 or F.sign(q1) == 0:
        return -F.surd_sign(a2 - a1, b2, q2)
    if q1 == q2:
        return F.surd_sign(a1 - a2, b1 - b2, q1)
    # A = (a1 - a2) + b1√q1 against C = b2√q2
    sA = F.surd_sign(a1 - a2, b1, q1)
    sC = F.sign(b2)
    if sA != sC:
        return (sA > sC) - (sA < sC)
    A2 = ((a1 - a2) * (a1 - a2) + b1 * b1 * q1, 2 * (a1 - a2) * b1, q1)
    d = F.surd_sign(A2[0] - b2 * b2 * q2, A2[1], A2[2])
    return sA * d


def _same_surd(u, w, F) -> bool:
    (a1, b1, q1), (a2, b2, q2) = u, w
    return all(_cmp_values((x1, y1, q1), (x2, y2, q2), F) == 0 for x1, y1, x2, y2 in zip(a1, b1, a2, b2))


def _combo(vectors, coeffs, n, F):
    out = [F.zero] * n
    for vec, c in zip(vectors, coeffs):
        if F.sign(c) == 0:
            continue
        out = [F.norm(o + c * x) for o, x in zip(out, vec)]
    return out


def _independent_subsets(vectors, n, F):
    """All subsets (as sorted tuples) of linearly independent vectors of size ≤ n, empty included."""
    out = [()]
    frontier = [()]
    for size in range(1, min(n, len(vectors)) + 1):
        nxt = []
        for base in frontier:
            start = base[-1] + 1 if base else 0
            for j in range(start, len(vectors)):
                T = base + (j,)
                if _rank([vectors[i] for i in T], F) == len(T):
                    nxt.append(T)
        out.extend(nxt)
        frontier = nxt
    return out


def _project(M, U, x, F):
    """Kinetic (M-orthogonal) projection of x onto span(U), and the coefficients."""
    if not U:
        return [F.zero] * len(x)
    MU = [_matvec(M, u, F) for u in U]
    G = [[_dot(u, mv, F) for mv in MU] for u in U]
    rhs = [_dot(mv, x, F) for mv in MU]
    sol = _solve_columns([[G[i][j] for i in range(len(U))] for j in range(len(U))], rhs, F)
    coeff = sol[0]
    return _combo(U, coeff, len(x), F)


def _face_candidates(M, v0, r2, c0, U, reading, F):
    """Candidates on the affine subspace c0 + span(U): (velocity as (alpha, beta, q), value)."""
    n = len(v0)
    zero = [F.zero] * n
    if reading == "cone":
        d = [F.norm(a - b) for a, b in zip(v0, c0)]
        v = [F.norm(a + b) for a, b in zip(c0, _project(M, U, d, F))]
        diff = [F.norm(a - b) for a, b in zip(v, v0)]
        yield (v, zero, F.zero), (_minner(M, diff, diff, F), F.zero, F.zero)
        return
    c = [F.norm(a - b) for a, b in zip(c0, _project(M, U, c0, F))]
    R = F.norm(r2 - _minner(M, c, c, F))
    sR = F.sign(R)
    if sR < 0:
        return
    fc = _minner(M, c, v0, F)
    if not U or sR == 0:
        if sR == 0:
            yield (c, zero, F.zero), (fc, F.zero, F.zero)
        return
    gvec = _project(M, U, v0, F)
    gg = _minner(M, gvec, gvec, F)
    dirs = []
    if F.sign(gg) != 0:
        dirs = [(gvec, gg, 1)] + ([(gvec, gg, -1)] if len(U) == 1 else [])
    else:
        e = U[0]
        ee = _minner(M, e, e, F)
        dirs = [(e, ee, 1), (e, ee, -1)]
    for d, dd, sgn in dirs:
        q = F.norm(R / dd)
        beta = [F.norm(sgn * x) for x in d]
        fb = _minner(M, beta, v0, F)
        yield (c, beta, q), (fc, fb, q)


def _distinct_spans(subsets, vectors, n, F):
    """One representative subset per distinct linear span (subsets are independent)."""
    seen = set()
    out = []
    for T in subsets:
        key = _rref([vectors[j] for j in T], n, F)[0] if T else []
        key = tuple(tuple(r) for r in key)
        if key not in seen:
            seen.add(key)
            out.append(T)
    return out


def _fold_surd(vel, F):
    """Fold ``β√q`` into ``α`` when ``√q`` lies in the field (rational square, or any algebraic
    backend, where SymPy carries the root)."""
    alpha, beta, q = vel
    if F.sign(q) == 0 or all(F.sign(b) == 0 for b in beta):
        return alpha, [F.zero] * len(alpha), F.zero
    if F is _Algebraic:
        root = sp.sqrt(q)
        return [F.norm(a + b * root) for a, b in zip(alpha, beta)], [F.zero] * len(alpha), F.zero
    p, d = int(q.p), int(q.q)
    rp, rd = math.isqrt(p), math.isqrt(d)
    if rp * rp == p and rd * rd == d:
        root = fmpq(rp, rd)
        return [a + b * root for a, b in zip(alpha, beta)], [F.zero] * len(alpha), F.zero
    return vel


def _in_cone(gens, subsets, alpha, beta, q, F) -> bool:
    """Exactly: is ``α + β√q`` (``√q`` irrational or ``β = 0``) a non-negative combination of
    ``gens``? A float NNLS proposes a support that is then verified exactly; otherwise every
    independent subset is tried (Carathéodory)."""
    n = len(alpha)
    if all(F.surd_sign(a, b, q) == 0 for a, b in zip(alpha, beta)):
        return True
    if not gens:
        return False

    def check(T):
        vecs = [gens[j] for j in T]
        sa = _solve_columns(vecs, alpha, F)
        sb = _solve_columns(vecs, beta, F)
        if sa is None or sb is None or sa[1]:
            return False
        return all(F.surd_sign(a, b, q) >= 0 for a, b in zip(sa[0], sb[0]))

    try:
        from scipy.optimize import nnls

        G = np.array([[float(F.to_sympy(g[i])) for g in gens] for i in range(n)], dtype=float)
        tf = math.sqrt(float(F.to_sympy(q))) if F.sign(q) > 0 else 0.0
        target = np.array([float(F.to_sympy(a)) + float(F.to_sympy(b)) * tf for a, b in zip(alpha, beta)])
        coef, _ = nnls(G, target)
        support = [j for j in np.argsort(-coef) if coef[j] > 1e-12 * max(1.0, coef.max())]
        T = [support[i] for i in _independent([gens[j] for j in support], F)]
        if T and check(sorted(T)):
            return True
    except Exception:  # the float proposal is only a shortcut; the exact LP decides
        pass
    return _in_cone_lp(gens, alpha, beta, q, F)


def _in_cone_lp(gens, alpha, beta, q, F) -> bool:
    """Exact LP (SymPy's rational simplex). ``β = 0``: is ``{a ≥ 0 : G a = α}`` non-empty?
    Otherwise the feasible ``t`` of ``{a ≥ 0 : G a − β t = α}`` form an interval
    ``[t_lo, t_hi]`` (a projection of a polyhedron), found by two rational LPs; then
    ``t_lo ≤ √q ≤ t_hi`` is decided exactly."""
    from sympy.solvers.simplex import InfeasibleLPError, UnboundedLPError, linprog

    n, m = len(alpha), len(gens)
    G = sp.Matrix([[F.to_sympy(g[i]) for g in gens] for i in range(n)])
    a = sp.Matrix([F.to_sympy(x) for x in alpha])
    if all(F.sign(b) == 0 for b in beta) or F.sign(q) == 0:
        try:
            linprog(sp.zeros(1, m), sp.zeros(1, m), sp.Matrix([1]), A_eq=G, b_eq=a)
            return True
        except InfeasibleLPError:
            return False
    b = sp.Matrix([F.to_sympy(x) for x in beta])
    A_eq = G.row_join(-b)
    root = sp.sqrt(F.to_sympy(q))
    c = sp.zeros(1, m + 1)
    c[m] = 1
    try:
        lo = linprog(c, sp.zeros(1, m + 1), sp.Matrix([1]), A_eq=A_eq, b_eq=a, bounds={m: (None, None)})[0]
    except InfeasibleLPError:
        return False
    except UnboundedLPError:
        lo = None
    try:
        hi = -linprog(-c, sp.zeros(1, m + 1), sp.Matrix([1]), A_eq=A_eq, b_eq=a, bounds={m: (None, None)})[0]
    except UnboundedLPError:
        hi = None
    if lo is not None and certified_sign(root - lo) < 0:
        return False
    if hi is not None and certified_sign(hi - root) < 0:
        return False
    return True


def _vel_sympy(vel, F):
    alpha, beta, q = vel
    root = sp.sqrt(F.to_sympy(q))
    return sp.Matrix([sp.radsimp(F.to_sympy(a) + F.to_sympy(b) * root) for a, b in zip(alpha, beta)])


# ---------------------------------------------------------------------------------------------
# Sec. III-C's bound for two surfaces
# ---------------------------------------------------------------------------------------------
def termination_bound(mass_matrix, gradients):
    """The paper's bound ``N = ⌈S_total / (2 S_0)⌉`` for two surfaces (sec. III-C), exactly.

    ``S_0`` is the valid lune of the kinetic sphere, whose dihedral angle is ``π − θ`` (``θ`` the
    kinetic angle between the contacts), so ``S_total / (2 S_0) = π / (π − θ)`` in any dimension.
    The ceiling is certified (:func:`impactsym.exact.certified_sign`).

    Returns
    -------
    int

    Examples
    --------
    >>> termination_bound("1,0;0,1", "1,0;-1,1"), termination_bound("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1")
    (4, 3)
    """
    from .two_surface import _Data, _certified_bound, _sign

    M = check_mass_matrix(mass_matrix, exact=True)
    H = check_gradients(gradients, M.shape[0], exact=True)
    if H.rows != 2:
        raise ImpactInputError("gradients", f"the bound of sec. III-C is for exactly two surfaces, got {H.rows}")
    # pi/(pi - theta) = pi/beta with beta = atan2(sqrt(Delta), -g): certified with Arb balls (the
    # two-surface law's bound), exact ties (beta = pi/K) decided exactly
    if _all_rational(M, H):
        Mq = fmpq_mat([[_Rational.num(x) for x in M.row(i)] for i in range(M.rows)])
        Hq = fmpq_mat([[_Rational.num(x) for x in H.row(i)] for i in range(2)])
        gram = Hq * Mq.solve(Hq.transpose())
    else:
        gram = (H * M.LUsolve(H.T)).applyfunc(sp.radsimp)
    d = _Data(gram[0, 0], gram[1, 1], gram[0, 1], gram[0, 0], gram[1, 1])
    if _sign(d.D) == 0:
        raise DomainError("gradients: the two surfaces are parallel (kinetic angle 0 or pi): the wedge is "
                          "degenerate, no bound")
    return _certified_bound(d, {})
