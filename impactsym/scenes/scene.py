"""The :class:`Scene`: an impact reduced to what it needs (``M``, ``H``, ``v⁻``), with the names of
its coordinates and closed contacts and, optionally, one restitution coefficient per contact.

Examples
--------
>>> import sympy as sp
>>> sc = Scene(sp.eye(2), sp.Matrix([[-1, 1]]), sp.Matrix([1, 0]), ["x1", "x2"], ["1-2"], [True],
...            restitution=["9/10"])
>>> sc.restitution, sc.exact, sc.relative_velocity()
([9/10], True, Matrix([[-1]]))
>>> Scene(sp.eye(2), sp.Matrix([[-1, 1]]), sp.Matrix([1, 0]), contacts=["1-2"], restitution=["3/2"])
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: restitution: entry 1 (contact 1-2) must lie in [0, 1], got 3/2
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

# SymPy is imported on first use: a float scene (and its checks) runs without it (issue 15)
from ..arithmetic import LazyModule, sympy_instance

sp = LazyModule("sympy", globals(), "sp")

__all__ = ["Scene", "check_restitution"]


@dataclass
class Scene:
    """An impact scene, reduced to the closed contacts.

    Attributes
    ----------
    M : mass matrix (n×n)
    H : gradient rows of the closed contacts (k×n), in the order of ``contacts``
    v : pre-impact generalized velocity (n×1)
    coordinates : names of the n generalized coordinates
    contacts : names of the k closed contacts (``"1-2"``, ``"wall@0-1"``, ...)
    approaching : for each closed contact, whether ``H_i v < 0`` (decided exactly for exact input)
    meta : free-form description (paper, equation, parameters)
    restitution : ``None`` (the scene states none), or one coefficient per closed contact, in the
        order of ``contacts``: exact (SymPy) numbers for exact input (text such as ``"9/10"`` is read
        exactly), floats on the float path; each checked to lie in ``[0, 1]`` when the scene is made
        (:func:`check_restitution`).
    """

    M: object
    H: object
    v: object
    coordinates: list = field(default_factory=list)
    contacts: list = field(default_factory=list)
    approaching: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)
    restitution: list | None = None

    def __post_init__(self):
        if self.restitution is not None:
            self.restitution = check_restitution(self.restitution, self.k, self.contacts)

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def k(self) -> int:
        return self.H.shape[0]

    @property
    def exact(self) -> bool:
        """Whether ``M``, ``H`` and ``v`` are exact: SymPy matrices, or
        :class:`~impactsym.resolution.RationalMatrix` (the rational builders'; else float arrays)."""
        from ..resolution import RationalMatrix

        return sympy_instance(self.M, "MatrixBase") or isinstance(self.M, RationalMatrix)

    def relative_velocity(self):
        """``w = H v`` (approaching when ``w_i < 0``)."""
        from ..resolution import RationalMatrix

        if isinstance(self.H, RationalMatrix):
            return RationalMatrix.column(sum((self.H[i, j] * self.v[j, 0] for j in range(self.n)), Fraction(0))
                                         for i in range(self.k))
        return self.H * self.v if sympy_instance(self.H, "MatrixBase") else self.H @ self.v


def check_restitution(values, k: int, contacts=(), argument: str = "restitution") -> list:
    """One restitution coefficient per closed contact, each in ``[0, 1]`` (decided exactly for
    exact input).

    Parameters
    ----------
    values : sequence of ``k`` numbers (int, ``Fraction``, SymPy number, exact text such as
        ``"9/10"`` or ``"1.1"``, or float)
    k : the number of closed contacts
    contacts : their names (used in messages)

    Returns
    -------
    list
        SymPy numbers for exact entries, floats for float entries.

    Raises
    ------
    ImpactInputError
        Wrong length, an entry that is not a finite real number, or outside ``[0, 1]``.

    Examples
    --------
    >>> check_restitution(["1", "0.9"], 2)
    [1, 9/10]
    >>> check_restitution([1], 2, ["1-2", "2-3"])
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: restitution: has 1 entries, expected 2 (one per closed contact: 1-2, 2-3)
    """
    from ..errors import ImpactInputError
    from ..exact import certified_sign
    from ..numbers import parse_number

    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ImpactInputError(argument, f"must be a sequence of numbers (one per closed contact), got {values!r}")
    vals = list(values)
    names = list(contacts) if len(contacts) == k else [str(i + 1) for i in range(k)]
    if len(vals) != k:
        raise ImpactInputError(argument, f"has {len(vals)} entries, expected {k} (one per closed contact: "
                                         f"{', '.join(names)})")
    out = []
    for i, e in enumerate(vals):
        where = f"entry {i + 1} (contact {names[i]})"
        if isinstance(e, bool):
            raise ImpactInputError(argument, f"{where} must be a number, got {e!r}")
        if isinstance(e, (float, np.floating)):
            x = float(e)
            if not math.isfinite(x):
                raise ImpactInputError(argument, f"{where} must be a finite real number, got {x}")
            inside = 0.0 <= x <= 1.0
        else:
            try:
                x = parse_number(e, argument)
            except ImpactInputError as exc:
                raise ImpactInputError(argument, f"{where}: {exc.condition}") from None
            inside = certified_sign(x) >= 0 and certified_sign(x - 1) <= 0
        if not inside:
            raise ImpactInputError(argument, f"{where} must lie in [0, 1], got {x}")
        out.append(x)
    return out


#: leaves a copy shares: immutable, and never changed in place
_SHARED = (str, bytes, int, float, complex, bool, type(None), Fraction, range)


def copy_scene(scene: Scene) -> Scene:
    """A deep copy of ``scene`` (what ``copy.deepcopy`` gives: every list, dict and mutable matrix
    its own, shared objects shared once), without rebuilding the immutable leaves: SymPy numbers and
    expressions, strings, ints and Fractions are shared, as they cannot change. A cached scene is
    handed out this way to every caller (issue 15: ``copy.deepcopy`` rebuilt every SymPy entry of
    ``M``, ``H``, ``v`` and the meta through ``__reduce_ex__``)."""
    import copy
    import sys

    memo: dict = {}
    basic = sp.Basic if "sympy" in sys.modules else None  # no SymPy object before SymPy is loaded

    def dup(x):
        if isinstance(x, _SHARED):
            return x
        got = memo.get(id(x))
        if got is not None:
            return got[1]
        t = type(x)
        if t is list:
            out = []
            memo[id(x)] = (x, out)
            out.extend(dup(y) for y in x)
        elif t is dict:
            out = {}
            memo[id(x)] = (x, out)
            for k, y in x.items():
                out[dup(k)] = dup(y)
        elif t is tuple:
            out = tuple(dup(y) for y in x)
            memo[id(x)] = (x, out)
        elif basic is not None and isinstance(x, basic):  # immutable (an ImmutableMatrix too)
            out = x
        elif basic is not None and sympy_instance(x, "MatrixBase"):  # a mutable SymPy matrix: its own entries
            out = x.copy()
            memo[id(x)] = (x, out)
        elif isinstance(x, np.ndarray) and x.dtype != object:
            out = x.copy()
            memo[id(x)] = (x, out)
        else:
            out = copy.deepcopy(x, {})
            memo[id(x)] = (x, out)
        return out

    new = copy.copy(scene)  # the dataclass's fields, without __post_init__ (restitution is checked)
    for name, value in vars(scene).items():
        setattr(new, name, dup(value))
    return new
