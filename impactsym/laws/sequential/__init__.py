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
* **Read once, sparse** (:mod:`.sparse`). Rational input is read straight into sparse ``fmpq``
  rows and checked there, once (``M`` symmetric positive definite by a sparse symmetric
  elimination, or flint's fraction-free LU for a dense ``M``; the refusal witness by sparse
  elimination of ``H``); outcomes are verified with sparse products. A state stores only the
  entries of ``v`` and ``w = H v`` that differ from ``v0`` and ``w0``; a reflection on contact
  ``i`` updates the support of ``M⁻¹H_iᵀ`` and re-decides only the signs of the contacts whose
  ``w`` it changes; the memo hash is updated with the changed entries. A one-striker cradle of
  ``n`` balls costs ``O(n)`` states of ``O(1)`` work each.
* **Independent groups** (:mod:`.independence`). Contacts with ``H_i M⁻¹ H_jᵀ = 0`` commute and
  never change each other's signs; the connected components of the Gram graph are searched
  apart and their outcomes, ordering counts (shuffle products) and representative orderings
  combined, so the states visited add instead of multiply.
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

Restitution e < 1 and inelastic collapse
----------------------------------------
``restitution=`` (one number, or one per contact) replaces each ``G_{H_i}`` by ``G_{H_i}(e_i)``
(``CONVENTIONS.md``); ``1`` is the elastic law above, on its unchanged code path. With some
``e_i < 1`` two contacts are always iterated (the closed form is elastic), the selection
defaults to the cone reading (the energy sphere holds only for elastic impacts), and an
alternation of two contacts that never ends (inelastic collapse) is decided exactly and
replaced by its limit, the plastic impact of the pair (:mod:`.collapse`, ``Outcome.collapse``,
:class:`InfiniteOrder`). A collapse involving more contacts is refused (``NonTermination``).
See ``docs/sequential_restitution.md``.

How the package is laid out
---------------------------
``common`` (limits; the fields and linear algebra of :mod:`impactsym.arithmetic`), ``sparse``
(the rational input read, checked and verified in sparse form), ``independence`` (independent
groups of contacts), ``witness`` (the refusal test), ``collapse`` (inelastic collapse of two
contacts), ``search`` (the exact DAG search and the verified replay), ``float_search``
(float mode), ``selection`` (steps 4–5), ``bound`` (sec. III-C), ``results`` (the result types)
and ``resolve`` (:func:`resolve_sequential`). Every public name is importable from here.

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

# the private names re-exported below are the ones the tests reach (tests/test_certified_extreme.py)
from .bound import termination_bound
from .collapse import alternation_limit, critical_restitution
from .common import (AUTO_ITERATE_MAX_COUNT, DEFAULT_MAX_REFLECTIONS, FLOAT_SAFETY, MAX_COORDINATES, MAX_STATE_BITS,
                     READINGS,
                     TWO_SURFACE_PATHS, _Algebraic, _Rational)
from .resolve import check_restitutions, resolve_sequential
from .results import InfiniteOrder, Outcome, SequentialResolution
from .search import _ExactSystem, _verified_replay
from .selection import SELECTION_FACE_LIMIT, _select, _verify_selected
from .witness import valid_velocity_witness

__all__ = [
    "resolve_sequential",
    "SequentialResolution",
    "Outcome",
    "InfiniteOrder",
    "critical_restitution",
    "alternation_limit",
    "check_restitutions",
    "valid_velocity_witness",
    "termination_bound",
    "READINGS",
    "DEFAULT_MAX_REFLECTIONS",
    "MAX_STATE_BITS",
    "MAX_COORDINATES",
    "FLOAT_SAFETY",
    "SELECTION_FACE_LIMIT",
    "TWO_SURFACE_PATHS",
    "AUTO_ITERATE_MAX_COUNT",
]
