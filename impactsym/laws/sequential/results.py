"""The results of the sequential resolver: :class:`Outcome` and :class:`SequentialResolution`.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import Any, Iterator

import numpy as np

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule, sympy_instance
sp = LazyModule("sympy", globals(), "sp")


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
    collapse : bool
        ``True`` when the velocity is the limit of an infinite ordering (inelastic collapse of
        two contacts, restitution < 1): then ``order`` is an :class:`InfiniteOrder` (a finite
        prefix, then the two contacts alternating forever), and ``reflections``,
        ``reflections_min`` and ``reflections_max`` are ``None``; ``orderings`` counts the
        infinite orderings (one per prefix) that converge to this velocity. Such an outcome is
        listed on its own even if a finite ordering happened to give the same velocity.
    """

    order: Any
    reflections: int | None
    velocity: Any
    impulse: Any
    orderings: int
    reflections_min: int | None
    reflections_max: int | None
    collapse: bool = False

    @property
    def velocity_float(self) -> list[float]:
        return _floats(self.velocity)


def _floats(v) -> list[float]:
    mpmath = sys.modules.get("mpmath")  # an mpmath matrix exists only once mpmath is loaded
    if mpmath is not None and isinstance(v, mpmath.matrix):
        return [float(v[i]) for i in range(v.rows)]
    if sympy_instance(v, "MatrixBase"):
        return [float(sp.N(x, 17)) for x in v]
    return [float(x) for x in np.asarray(v, dtype=float).reshape(-1)]


@dataclass(frozen=True)
class InfiniteOrder:
    """An infinite ordering: the impacts of ``prefix``, then ``cycle = (X, Y)`` repeated forever
    (``X, Y, X, Y, ...``), the order of an inelastic collapse of contacts ``X`` and ``Y``.

    >>> o = InfiniteOrder((0,), (1, 0))
    >>> o[:6], o.to_json()
    ([0, 1, 0, 1, 0, 1], {'prefix': [0], 'cycle': [1, 0], 'infinite': True})
    """

    prefix: tuple
    cycle: tuple

    def __getitem__(self, i):
        if isinstance(i, slice):
            if i.stop is None or (i.stop < 0) or (i.start is not None and i.start < 0):
                raise IndexError("InfiniteOrder: a slice needs a non-negative stop (the ordering is infinite)")
            return [self[k] for k in range(*i.indices(i.stop))]
        if i < 0:
            raise IndexError("InfiniteOrder: negative index of an infinite ordering")
        if i < len(self.prefix):
            return self.prefix[i]
        return self.cycle[(i - len(self.prefix)) % len(self.cycle)]

    def to_json(self) -> dict:
        return {"prefix": list(self.prefix), "cycle": list(self.cycle), "infinite": True}


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
        exact replays of the float outcomes; see ``selected_float``; in float mode the SymPy
        vectors are made when this is first read, so a float run that reads only
        ``selected_float`` imports no SymPy); with the two-surface
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
        Sign decisions ``H_i v`` made. Float mode: a state re-decides only the contacts whose
        ``w_i`` the reflection that made it can change, and keeps its parent's other decisions
        (not counted here).
    exact_fallbacks : int
        Float mode: decisions made exactly because the float bound straddled zero (a decision a
        state keeps from its parent is not made again and not counted), plus the exact comparisons
        that let such a state be shared in the DAG and that merge nearby float outcomes. 0 in
        exact mode.
    exact : bool
        Whether the outcome velocities are exact.
    backend : str
        ``"rational"``, ``"algebraic"`` or ``"float"``.
    approaching : tuple of bool
        ``H_i v0 < 0`` for each contact (decided exactly or certified).
    witness : sympy.Matrix or tuple of fmpq
        A non-zero valid velocity (``H v ≥ 0``), the certificate that the refusal check passed
        (float mode: a tuple of ``fmpq``, on the floats' exact binary values).
    method : str
        ``"iteration"`` (the DAG search) or ``"two-surface closed form"``
        (:func:`impactsym.laws.two_surface.resolve_two_surfaces`, used for two independent rows).
    bound : int or None
        Two surfaces: the paper's ``N = ⌈S_total/(2S₀)⌉`` (sec. III-C), certified.
    restitution : tuple
        The restitution ``e_i`` of each contact (exact SymPy numbers, or floats in float mode);
        ``(1, ..., 1)`` for the elastic law.
    collapse : bool
        Whether any outcome is an inelastic-collapse limit (``Outcome.collapse``).

    With restitution < 1, ``max_reflections_used`` is the longest *finite* ordering (0 when
    every ordering is infinite).
    """

    outcomes: tuple
    _selected: tuple | None  # None: made from _selected_raw on first access (float mode)
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
    restitution: tuple = ()
    collapse: bool = False
    #: the impulse ``p`` of each selected velocity (``M(v − v0) = Hᵀp``, exact, verified) when ``H``
    #: has full row rank and the velocity is an outcome; empty or ``None`` entries otherwise
    selected_impulses: tuple = ()
    _graph: Any = field(default=None, repr=False, compare=False)
    _orders: Any = field(default=None, repr=False, compare=False)
    #: float mode: ``(field, (a, b, q) triples)`` of the exact selection, turned into SymPy vectors
    #: only when :attr:`selected` is read (the float path reports :attr:`selected_float`)
    _selected_raw: Any = field(default=None, repr=False, compare=False)

    @property
    def selected(self) -> tuple:
        if self._selected is None:
            from .selection import _vel_sympy

            F, raw = self._selected_raw
            self._selected = tuple(_vel_sympy(v, F) for v in raw)
        return self._selected

    @property
    def selected_float(self) -> list[list[float]]:
        if self._selected is None:  # float mode: rounded from the exact triples (SymPy only for a surd)
            from .selection import _float_selection

            F, raw = self._selected_raw
            return [[float(x) for x in _float_selection(v, F)] for v in raw]
        return [_floats(v) for v in self.selected]

    def iter_orderings(self, limit: int | None = None) -> Iterator[tuple[tuple, int]]:
        """Every ordering with the index of its outcome in :attr:`outcomes`, depth first.

        >>> from impactsym.laws.sequential import resolve_sequential
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
        if hasattr(g, "iter_paths"):  # independent groups of contacts: the interleavings
            for count, (path, key) in enumerate(g.iter_paths(), 1):
                yield path, g.outcome_index[key]
                if limit is not None and count >= limit:
                    return
            return
        count = 0
        stack = [(g.root, ())]
        while stack:
            node, path = stack.pop()
            kids = g.children[node]
            if not kids:
                if node in g.collapse:
                    yield InfiniteOrder(path[:-1], g.collapse[node][0]), g.outcome_index[g.terminal_key[node]]
                else:
                    yield path, g.outcome_index[g.terminal_key[node]]
                count += 1
                if limit is not None and count >= limit:
                    return
                continue
            for i, child in reversed(kids):
                stack.append((child, path + (i,)))
