"""One outcome type for every law: :class:`System`, :class:`Outcome` and :class:`Resolution`.

Every law of :mod:`impactsym.lawbook` takes a :class:`System` (``M``, ``H``, ``v⁻``, the
restitution, the names of the contacts and, when it came from a scene, the scene's description)
and returns one :class:`Resolution`. A resolution holds every outcome the law gives (one for most
laws; one per distinct exit velocity for the sequential law; one per end state for Han–Gilmore),
the outcome(s) the law's selection rule picks where it has one, and how to read them
(:attr:`Resolution.uniqueness`):

``"unique"``
    the law gives one post-impact velocity;
``"set-valued"``
    the law gives several outcomes and no rule among them (Han–Gilmore's hypotheses);
``"gap-dependent"``
    the law gives several outcomes, and which one happens depends on the (arbitrarily small)
    gaps between the touching bodies: the sequential law's orderings, the two-surface branches.
    Comparing a simulator against one vector makes sense only for ``"unique"``, or for the
    outcome of given gaps (``impactsym resolve --gaps``).

The JSON form (:meth:`Resolution.as_json`) is the same for every law; its schema is written down
in ``docs/resolution_schema.md`` and tested (``tests/test_resolution_schema.py``).

Examples
--------
SymPy and mpmath are imported where an exact or certified value is handled, never at import:
a float result (a compliant law's) is built and printed without them.

>>> from impactsym.lawbook import resolve
>>> r = resolve("newton", System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0"))
>>> r.uniqueness, r.velocity.T, r.kinetic_energy_after
('unique', Matrix([[-1/3, 2/3, 2/3]]), 1/2)
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from .errors import ImpactInputError, VerificationError

__all__ = ["System", "Outcome", "Resolution", "SCHEMA", "UNIQUENESS", "vector_json", "number_json"]

#: the version of the JSON schema of :meth:`Resolution.as_json` (``docs/resolution_schema.md``)
SCHEMA = "impactsym.resolution/1"

#: the values of :attr:`Resolution.uniqueness`
UNIQUENESS = ("unique", "set-valued", "gap-dependent")


# ----------------------------------------------------------------------------------- numbers
def is_sympy(x, kind: str = "Basic") -> bool:
    """Whether ``x`` is a SymPy object of class ``kind`` (``"Basic"``, ``"MatrixBase"``, …),
    without importing SymPy: when SymPy is not loaded, no object is one.

    >>> import sympy as sp
    >>> is_sympy(sp.Integer(2)), is_sympy(sp.eye(2), "MatrixBase"), is_sympy(2.0)
    (True, True, False)
    """
    sp = sys.modules.get("sympy")
    return sp is not None and isinstance(x, getattr(sp, kind))


def is_mpmath(x, kind: str = "mpf") -> bool:
    """Whether ``x`` is an mpmath object of class ``kind`` (``"mpf"``, ``"matrix"``), without
    importing mpmath."""
    mp = sys.modules.get("mpmath")
    return mp is not None and isinstance(x, getattr(mp, kind))


def _fraction_text(x: Fraction) -> str:
    """SymPy's ``str`` of the rational ``x`` (:func:`impactsym.numbers.exact_str`: integers of any length)."""
    from flint import fmpq

    return str(fmpq(x.numerator, x.denominator))


def _fraction_float(x: Fraction) -> float | None:
    """``float(N(x, 17))`` of the rational ``x``, bit for bit (the JSON float twin), or ``None`` when
    it overflows."""
    from .arithmetic.literals import json_float

    f = json_float(x.numerator, x.denominator)
    return f if math.isfinite(f) else None


def _float(x) -> float | None:
    if isinstance(x, Fraction):
        return _fraction_float(x)
    try:
        if is_sympy(x):
            import sympy as sp

            f = float(sp.N(x, 17))
        else:
            f = float(x)
    except (OverflowError, TypeError):
        return None
    return f if math.isfinite(f) else None


def _text(x, digits: int | None) -> str:
    if isinstance(x, Fraction):
        return _fraction_text(x)
    if is_sympy(x):
        from .numbers import exact_str

        return exact_str(x)
    if is_mpmath(x):
        import mpmath

        return mpmath.nstr(x, digits or 17, strip_zeros=False)
    return repr(float(x))


def _entries(value) -> list:
    if is_sympy(value, "MatrixBase") or isinstance(value, RationalMatrix):
        return list(value)
    if is_mpmath(value, "matrix"):
        return [value[i] for i in range(value.rows)]
    return [x for x in np.asarray(value, dtype=float).reshape(-1)]


def vector_json(name: str, value, digits: int | None = None) -> dict:
    """``{name: [strings], name + "_float": [floats]}``; ``None`` gives ``None`` twice.

    Exact entries are SymPy strings, certified ones ``mpmath`` strings to ``digits`` digits,
    floats their ``repr``; a float twin that overflows is ``None`` (strict JSON).

    >>> import sympy as sp
    >>> vector_json("v", sp.Matrix([sp.Rational(1, 3), 2]))
    {'v': ['1/3', '2'], 'v_float': [0.3333333333333333, 2.0]}
    """
    if value is None:
        return {name: None, name + "_float": None}
    items = _entries(value)
    if is_sympy(value, "MatrixBase"):  # exact: rationals without evalf (as matrix_json)
        Rational = sys.modules["sympy"].Rational
        cache: dict = {}
        pairs = [_rational_pair(x, cache) if isinstance(x, Rational) else (_text(x, digits), _float(x))
                 for x in items]
        return {name: [t for t, _ in pairs], name + "_float": [f for _, f in pairs]}
    return {name: [_text(x, digits) for x in items], name + "_float": [_float(x) for x in items]}


def _rational_pair(x, cache: dict) -> tuple:
    """``(_text(x, None), _float(x))`` of a SymPy rational without evalf, memoised on ``(p, q)``:
    :func:`impactsym.numbers.exact_str` prints it as ``str`` does, and
    :func:`impactsym.arithmetic.literals.json_float` is ``float(N(x, 17))`` bit for bit."""
    key = (x.p, x.q)
    got = cache.get(key)
    if got is None:
        from .arithmetic.literals import json_float
        from .numbers import exact_str

        f = json_float(int(x.p), int(x.q))
        got = cache[key] = (exact_str(x), f if np.isfinite(f) else None)
    return got


def matrix_json(name: str, value) -> dict:
    if isinstance(value, RationalMatrix):
        # memoised on the entry: most entries of a scene's M and H are 0 or ±1
        cache: dict = {}

        def pair(x):
            got = cache.get(x)
            if got is None:
                got = cache[x] = (_fraction_text(x), _fraction_float(x))
            return got

        rows, cols = value.shape
        zt, zf = pair(Fraction(0))
        text, floats = [[zt] * cols for _ in range(rows)], [[zf] * cols for _ in range(rows)]
        for (i, j), x in value.nonzeros().items():
            text[i][j], floats[i][j] = pair(x)
        return {name: text, name + "_float": floats}
    if is_sympy(value, "MatrixBase"):
        import sympy as sp

        # exact: most entries of a scene's M and H are 0 or ±1; rationals take the fast path
        cache: dict = {}
        text, floats = [], []
        for r in value.tolist():
            tr, fr = [], []
            for x in r:
                t, f = _rational_pair(x, cache) if isinstance(x, sp.Rational) else (_text(x, None), _float(x))
                tr.append(t)
                fr.append(f)
            text.append(tr)
            floats.append(fr)
        return {name: text, name + "_float": floats}
    rows = np.asarray(value, dtype=float).tolist()  # Python floats: _text is repr, _float x (None if not finite)
    return {name: [[repr(x) for x in r] for r in rows],
            name + "_float": [[x if math.isfinite(x) else None for x in r] for r in rows]}


def number_json(name: str, value, digits: int | None = None) -> dict:
    """``{name: string, name + "_float": float}`` (``None`` twice for ``None``)."""
    if value is None:
        return {name: None, name + "_float": None}
    return {name: _text(value, digits), name + "_float": _float(value)}


# ------------------------------------------------------------------------------------ system
class RationalMatrix:
    """An exact rational matrix without SymPy: the entries are ``Fraction``; a vector is a column.

    What the command line builds from plain input (``"1,1/2;0.5,2"``) for a law that computes in
    floats (the compliant and LZB laws), so that the request imports no SymPy: the system is still
    checked exactly (python-flint) and printed exactly (``"1/2"``, as SymPy prints it, with the same
    float twins). ``np.asarray(A, dtype=float)`` gives each entry's nearest float, as a SymPy
    matrix of the same rationals does; ``list(A)`` its entries row by row, as SymPy's.

    >>> from fractions import Fraction as Q
    >>> A = RationalMatrix([[Q(2), Q(1, 3)], [Q(1, 3), Q(1)]])
    >>> A.shape, A[0, 1], list(A)[1:3], A
    ((2, 2), Fraction(1, 3), [Fraction(1, 3), Fraction(1, 3)], RationalMatrix([['2', '1/3'], ['1/3', '1']]))
    >>> import numpy as np
    >>> np.asarray(RationalMatrix.column([Q(1, 3), Q(-1)]), dtype=float).tolist()
    [[0.3333333333333333], [-1.0]]
    """

    __slots__ = ("_rows", "_nz")

    def __init__(self, rows):
        self._rows = [[Fraction(x) for x in r] for r in rows]
        self._nz = None
        if not self._rows or len({len(r) for r in self._rows}) != 1 or not self._rows[0]:
            raise ValueError("RationalMatrix: rows of one non-zero length, at least one")

    @classmethod
    def column(cls, entries) -> "RationalMatrix":
        return cls([[x] for x in entries])

    @classmethod
    def from_entries(cls, shape: tuple[int, int], entries: dict) -> "RationalMatrix":
        """The matrix of ``shape`` whose nonzero entries are ``entries`` (``{(i, j): value}``, each
        an ``int`` or a ``Fraction``); every other entry is 0 (one shared ``Fraction``: a
        1000-ball scene's ``M`` is a million entries, almost all zero).

        >>> RationalMatrix.from_entries((2, 3), {(0, 0): 1, (1, 2): Fraction(-1, 2)})
        RationalMatrix([['1', '0', '0'], ['0', '0', '-1/2']])
        """
        n, m = shape
        if n < 1 or m < 1:
            raise ValueError("RationalMatrix: rows of one non-zero length, at least one")
        zero = Fraction(0)
        rows = [[zero] * m for _ in range(n)]
        nz = {}
        for (i, j), x in sorted(entries.items()):
            rows[i][j] = Fraction(x)
            if x:
                nz[i, j] = rows[i][j]
        out = cls.__new__(cls)
        out._rows, out._nz = rows, nz
        return out

    def nonzeros(self) -> dict:
        """``{(i, j): entry}`` of the non-zero entries, row by row (each row's columns in order):
        what the float path reads of a large sparse scene (its ``M`` is diagonal).

        >>> RationalMatrix([[0, 2], [Fraction(1, 3), 0]]).nonzeros()
        {(0, 1): Fraction(2, 1), (1, 0): Fraction(1, 3)}
        """
        if self._nz is None:
            self._nz = {(i, j): x for i, r in enumerate(self._rows) for j, x in enumerate(r) if x}
        return self._nz

    @property
    def shape(self) -> tuple[int, int]:
        return len(self._rows), len(self._rows[0])

    @property
    def rows(self) -> int:
        return len(self._rows)

    @property
    def cols(self) -> int:
        return len(self._rows[0])

    def tolist(self) -> list[list[Fraction]]:
        return [list(r) for r in self._rows]

    def __getitem__(self, ij):
        i, j = ij
        return self._rows[i][j]

    def __iter__(self):
        return (x for r in self._rows for x in r)

    def __len__(self) -> int:
        return self.rows * self.cols

    def __array__(self, dtype=None, copy=None):
        import numpy

        if dtype is None or numpy.dtype(dtype) == numpy.dtype(object):
            return numpy.array(self.tolist(), dtype=object)
        return numpy.array([[float(x) for x in r] for r in self._rows], dtype=dtype)

    def json_floats(self) -> list[list[float]]:
        """Each entry's ``float(N(x, 17))`` (the JSON float twin; what SymPy's ``evalf(17)`` gives)."""
        from .arithmetic.literals import json_float

        return [[json_float(x.numerator, x.denominator) for x in r] for r in self._rows]

    def __eq__(self, other) -> bool:
        return isinstance(other, RationalMatrix) and self._rows == other._rows

    __hash__ = None

    def __repr__(self) -> str:
        return f"RationalMatrix({[[_fraction_text(x) for x in r] for r in self._rows]!r})"


@dataclass
class System:
    """What every law takes: the mass matrix, the gradient rows of the closed contacts, the
    pre-impact velocity and the restitution.

    Attributes
    ----------
    M, H, v : exact SymPy matrices (``v`` a column) or float64 arrays
    restitution : None (each law's default, elastic), one number, or one per contact
    contacts : the contacts' names, one per row of ``H`` (default ``"1"``, ``"2"``, …)
    scene : the scene's description (a dict with at least ``"name"``) or None
    exact : whether ``M``, ``H``, ``v`` are exact
    """

    M: Any
    H: Any
    v: Any
    restitution: Any = None
    contacts: list = field(default_factory=list)
    scene: dict | None = None
    exact: bool = True
    coordinates: list = field(default_factory=list)
    #: the Scene object the system came from (balls on a line: its geometry serves ``--gaps``)
    source: Any = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        if not self.contacts:
            self.contacts = [str(i + 1) for i in range(self.k)]

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def k(self) -> int:
        return self.H.shape[0]

    @classmethod
    def from_matrices(cls, M, H, v, restitution=None, **kw) -> "System":
        """A system from matrices (``"a,b;c,d"`` text, nested lists, SymPy or NumPy), checked:
        ``M`` symmetric positive definite, ``H`` with non-zero rows, shapes that agree.

        >>> System.from_matrices("2,0;0,1", "-1,1", "1,0").H
        Matrix([[-1, 1]])
        """
        from .mechanics import check_gradients, check_mass_matrix, check_velocity
        from .numbers import is_exact

        exact = is_exact(M, H, v)
        Mx = check_mass_matrix(M, exact=exact)
        Hx = check_gradients(H, Mx.shape[0], exact=exact)
        vx = check_velocity(v, Mx.shape[0], exact=exact)
        return cls(Mx, Hx, vx, restitution, exact=exact, **kw)

    @classmethod
    def from_rationals(cls, M, H, v, restitution=None, **kw) -> "System":
        """A system from rational entries (nested lists of ``Fraction``, as
        :func:`impactsym.arithmetic.literals.plain_matrix` reads them), checked exactly in
        python-flint without SymPy: ``M`` square, symmetric and positive definite (Sylvester's
        criterion), ``H`` with ``n`` columns and no zero row, ``v`` of length ``n``. ``restitution``:
        None, a ``Fraction``, or a list of them. A violated condition raises
        :class:`~impactsym.errors.ImpactInputError` (the command line then lets
        :meth:`from_matrices` word it, as it always has). ``M`` and ``H`` may also be
        :class:`RationalMatrix` (taken as they are); ``kw`` (``contacts``, ``scene``,
        ``coordinates``, ``source``) go to the system as :meth:`from_scene` gives them.

        >>> from fractions import Fraction as Q
        >>> s = System.from_rationals([[Q(2), Q(0)], [Q(0), Q(1)]], [[Q(-1), Q(1)]], [Q(1), Q(0)])
        >>> s.n, s.k, s.exact, s.as_json()["velocity"]
        (2, 1, True, ['1', '0'])
        >>> System.from_rationals([[Q(1), Q(2)], [Q(2), Q(1)]], [[Q(1), Q(0)]], [Q(1), Q(0)])
        Traceback (most recent call last):
        ...
        impactsym.errors.ImpactInputError: mass_matrix: not positive definite (leading principal minor 2 is -3)
        """
        from flint import fmpq

        from .mechanics import first_asymmetric_pair, positive_definite_by_fflu, symmetric_elimination

        Mx = M if isinstance(M, RationalMatrix) else RationalMatrix(M)
        Hx = H if isinstance(H, RationalMatrix) else RationalMatrix(H)
        vx = RationalMatrix.column(v)
        n = Mx.rows
        if Mx.cols != n:
            raise ImpactInputError("mass_matrix", f"must be a non-empty square matrix, got shape {Mx.shape}")
        rows = [{} for _ in range(n)]
        for (i, j), x in Mx.nonzeros().items():
            rows[i][j] = fmpq(x.numerator, x.denominator)
        bad = first_asymmetric_pair(rows)
        if bad is not None:
            i, j = bad
            raise ImpactInputError("mass_matrix", f"not symmetric (entry ({i}, {j}) is "
                                   f"{_fraction_text(Mx[i, j])} but ({j}, {i}) is {_fraction_text(Mx[j, i])})")
        if not (n >= 8 and 4 * sum(len(r) for r in rows) >= n * n and positive_definite_by_fflu(rows, n)):
            symmetric_elimination(rows, n, "mass_matrix")  # as check_mass_matrix: fflu first when dense
        if Hx.cols != n:
            raise ImpactInputError("gradients", f"has {Hx.cols} columns, expected {n} (the mass matrix is {n}×{n})")
        nonzero_rows = {i for i, _ in Hx.nonzeros()}
        for i in range(Hx.rows):
            if i not in nonzero_rows:
                raise ImpactInputError("gradients", f"row {i} is the zero covector (a constraint gradient must be "
                                                    "non-zero)")
        if vx.rows != n:
            raise ImpactInputError("velocity", f"has length {vx.rows}, expected {n} (the mass matrix is {n}×{n})")
        if isinstance(restitution, (list, tuple)):
            restitution = [Fraction(x) for x in restitution]
        elif restitution is not None:
            restitution = Fraction(restitution)
        return cls(Mx, Hx, vx, restitution, exact=True, **kw)

    @property
    def rational(self) -> bool:
        """Whether ``M``, ``H``, ``v`` are :class:`RationalMatrix` (exact, held without SymPy)."""
        return isinstance(self.M, RationalMatrix)

    @classmethod
    def from_scene(cls, scene, restitution=None, *, description: dict | None = None) -> "System":
        """A system from an :class:`impactsym.scenes.Scene` (its per-contact restitution, if it
        has one, unless ``restitution`` is given)."""
        from .numbers import is_exact

        if restitution is None:
            restitution = getattr(scene, "restitution", None)
        exact = is_exact(scene.M, scene.H, scene.v)
        return cls(scene.M, scene.H, scene.v, restitution, contacts=list(scene.contacts),
                   scene=description, exact=exact, coordinates=list(scene.coordinates), source=scene)

    def restitution_scalar(self, law: str, *, default=1):
        """The one restitution of a law that takes a single coefficient; per-contact values that
        differ are refused, naming the law."""
        e = self.restitution
        if e is None:
            if self.rational:
                return Fraction(default)
            return _integer(default) if self.exact else float(default)
        if isinstance(e, (list, tuple)):
            import sympy as sp

            from .numbers import exact_str

            vals = list(e)
            if len(vals) != self.k:
                raise ImpactInputError("restitution", f"has {len(vals)} entries, expected one per contact ({self.k})")
            if any(sp.sympify(x) != sp.sympify(vals[0]) for x in vals[1:]):
                raise ImpactInputError("restitution", f"--law {law} takes one restitution for every contact; "
                                       f"the per-contact values {[exact_str(x) for x in vals]} differ")
            return vals[0]
        return e

    def restitution_vector(self, default=1) -> list:
        """One restitution per contact."""
        e = self.restitution
        if e is None:
            e = Fraction(default) if self.rational else _integer(default) if self.exact else float(default)
        if isinstance(e, (list, tuple)):
            if len(e) != self.k:
                raise ImpactInputError("restitution", f"has {len(e)} entries, expected one per contact ({self.k})")
            return list(e)
        return [e] * self.k

    # ------------------------------------------------------------------ resolutions, remembered
    def resolution_memo(self) -> dict | None:
        """The laws' resolutions of this system, remembered (:func:`impactsym.lawbook.resolve_all`:
        ``impactsym check`` resolves the system it checks, often one resolved already), keyed by
        the law and its options; ``None`` (nothing remembered) for a system too large to key or
        with an entry that cannot be keyed.

        The memo belongs to the system's content: ``M``, ``H``, ``v``, the restitution, the
        contacts, the coordinates, whether it is exact, the scene's description and its source
        object. Any of them changed (reassigned, or a matrix changed in place), the memo starts
        empty. A copy or a pickle of the system starts empty.

        >>> s = System.from_matrices("1,0;0,1", "-1,1", "1,0")
        >>> memo = s.resolution_memo(); memo["key"] = "value"; s.resolution_memo()
        {'key': 'value'}
        >>> s.restitution = "1/2"; s.resolution_memo()
        {}
        """
        content = self._content()
        if content is None:
            return None
        held = self.__dict__.get("_memo")
        if held is None or held[0] != content:
            held = self.__dict__["_memo"] = (content, {})
        return held[1]

    #: the most matrix entries a system may have for its resolutions to be remembered (its content
    #: is its key, compared at every look-up)
    MEMO_ENTRIES = 10_000

    def _content(self):
        if sum(np.size(x) if isinstance(x, np.ndarray) else len(x) for x in (self.M, self.H, self.v)) \
                > self.MEMO_ENTRIES:
            return None
        parts = (_frozen(self.M), _frozen(self.H), _frozen(self.v), _frozen(self.restitution),
                 _frozen(self.contacts), _frozen(self.coordinates), _frozen(self.exact), _frozen(self.scene))
        if any(p is _UNKEYED for p in parts):
            return None
        return parts + (_Same(self.source),)

    def __getstate__(self):
        state = dict(self.__dict__)
        state.pop("_memo", None)
        return state

    def as_json(self) -> dict:
        out = {}
        out.update(matrix_json("mass_matrix", self.M))
        out.update(matrix_json("gradients", self.H))
        out.update(vector_json("velocity", self.v))
        e = self.restitution
        if e is None:
            out.update({"restitution": None, "restitution_float": None})
        elif isinstance(e, (list, tuple)):
            out.update(vector_json("restitution", RationalMatrix.column(e) if self.rational else
                                   _sympy_column(e) if self.exact else list(e)))
        else:
            out.update(number_json("restitution", e))
        out["contacts"] = list(self.contacts)
        out["coordinates"] = list(self.coordinates)
        return out


#: what :func:`_frozen` gives for a value it cannot key
_UNKEYED = object()


def _frozen(x):
    """A hashable key of ``x``'s content (SymPy, rational and NumPy matrices, numbers, text, and
    lists, tuples and dicts of them), every number with its type (``1``, ``1.0``, ``True`` and
    ``Float(1)`` are four keys; a float by its bits), or :data:`_UNKEYED`.

    >>> import sympy as sp
    >>> _frozen(sp.Matrix([[1, sp.sqrt(2)]])) == _frozen(sp.Matrix([[1, sp.sqrt(2)]])), _frozen([1, {"a": "2"}])
    (True, ('list', (('int', 1), ('dict', (('a', ('str', '2')),)))))
    >>> len({_frozen(1), _frozen(1.0), _frozen(True), _frozen(sp.Float(1)), _frozen(sp.Integer(1))})
    5
    """
    t = type(x)
    if x is None:
        return None
    if t is float:
        return ("float", x.hex())
    if t in (str, int, bool, Fraction):
        return (t.__name__, x)
    if isinstance(x, RationalMatrix):
        return ("rational", x.shape, tuple(map(tuple, x._rows)))
    if isinstance(x, np.ndarray):
        return ("array", x.shape, x.dtype.str, x.tobytes())
    if is_sympy(x, "MatrixBase"):
        return ("sympy", x.shape, tuple((type(e).__name__, e) for e in x))
    if is_sympy(x):
        return (type(x).__name__, x)
    if t in (list, tuple):
        items = tuple(_frozen(y) for y in x)
        return _UNKEYED if any(y is _UNKEYED for y in items) else (t.__name__, items)
    if t is dict:
        items = tuple((k, _frozen(y)) for k, y in x.items())
        if any(y is _UNKEYED for _, y in items) or not all(type(k) is str for k, _ in items):
            return _UNKEYED
        return ("dict", items)
    return _UNKEYED


class _Same:
    """An object compared by identity (a system's source scene: held, never compared by content)."""

    __slots__ = ("obj",)

    def __init__(self, obj):
        self.obj = obj

    def __eq__(self, other):
        return isinstance(other, _Same) and other.obj is self.obj

    def __hash__(self):
        return id(self.obj)


def _integer(n: int):
    import sympy as sp

    return sp.Integer(n)


def _sympy_column(values):
    import sympy as sp

    return sp.Matrix(list(values))


# ----------------------------------------------------------------------------------- outcome
@dataclass
class Outcome:
    """One post-impact state of a law.

    Attributes
    ----------
    velocity : ``v⁺`` (SymPy column when exact, ``mpmath.matrix`` when certified, float array)
    impulses : ``p`` with ``M(v⁺ − v⁻) = Hᵀp`` (same form), or None when the law gives none
    order : the order of single impacts (0-based contact indices, rows of ``H``) where the law
        has one; stages of simultaneous impacts are tuples (Han–Gilmore); None otherwise
    orderings : how many orderings give this outcome (sequential), else None
    valid : whether the law's conditions hold (``H v⁺ ≥ 0`` on the closed contacts, ``p ≥ 0``, …)
    violations : the violated conditions (dicts with ``condition``, ``message``, ``contact``)
    digits : certified significant digits (None when exact or float)
    details : law-specific data of this outcome (JSON-ready)
    """

    velocity: Any
    impulses: Any = None
    order: Any = None
    orderings: int | None = None
    valid: bool = True
    violations: list = field(default_factory=list)
    digits: int | None = None
    details: dict = field(default_factory=dict)


def _exactness(value) -> str:
    if value is None:  # no outcome velocity (a law without a real solution, reported with --allow-invalid)
        return "none"
    if is_sympy(value, "MatrixBase"):
        return "exact"
    if is_mpmath(value, "matrix"):
        return "certified"
    return "float"


# -------------------------------------------------------------------------------- resolution
@dataclass
class Resolution:
    """What every law returns.

    Attributes
    ----------
    law : the law's name (``impactsym.lawbook.LAWS`` key)
    system : the :class:`System` it resolved
    outcomes : every outcome of the law (at least one)
    selected : the outcome(s) the law's selection rule picks (Seghete & Murphey's projection;
        not necessarily among ``outcomes``), empty where the law has no rule or a single outcome
    uniqueness : ``"unique"``, ``"set-valued"`` or ``"gap-dependent"`` (module docstring)
    notes : what the law did (method, choices, refusals of parts)
    details : law-specific data (JSON-ready dict)
    raw : the law's own result object (``SequentialResolution``, ``ClassicalResult``, …)
    """

    law: str
    system: System
    outcomes: list
    selected: list = field(default_factory=list)
    uniqueness: str = "unique"
    notes: list = field(default_factory=list)
    details: dict = field(default_factory=dict)
    raw: Any = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        if not self.outcomes:
            raise VerificationError(self.law, "a resolution without any outcome")
        if self.uniqueness not in UNIQUENESS:
            raise VerificationError(self.law, f"uniqueness {self.uniqueness!r} is not one of {UNIQUENESS}")
        #: momentum residuals computed by the check, reused by the JSON (:meth:`_residual`)
        self._residuals: dict = {}
        for o in list(self.outcomes) + list(self.selected):
            self._check_momentum(o)

    # --------------------------------------------------------------- the answer in one place
    @property
    def answer(self) -> Outcome | None:
        """The one outcome to compare against: the single selected outcome, or the single
        outcome (or the first of several with the same velocity: ``uniqueness == "unique"``); None
        when the law gives several and no (single) selection."""
        if len(self.selected) == 1:
            return self.selected[0]
        if len(self.outcomes) == 1 or self.uniqueness == "unique":
            return self.outcomes[0]
        return None

    @property
    def velocity(self):
        a = self.answer
        return None if a is None else a.velocity

    @property
    def impulses(self):
        a = self.answer
        return None if a is None else a.impulses

    @property
    def exactness(self) -> str:
        """``"exact"``, ``"certified"`` or ``"float"`` (the weakest over the outcomes)."""
        kinds = {_exactness(o.velocity) for o in self.outcomes}
        for k in ("float", "certified", "exact"):
            if k in kinds:
                return k
        return "exact" if self.system.exact else "float"

    @property
    def exact(self) -> bool:
        return self.exactness == "exact"

    @property
    def digits(self) -> int | None:
        ds = [o.digits for o in self.outcomes if o.digits is not None]
        return min(ds) if ds else None

    @property
    def valid(self) -> bool:
        a = self.answer
        return all(o.valid for o in self.outcomes) if a is None else a.valid

    @property
    def violations(self) -> list:
        a = self.answer
        return list(a.violations) if a is not None else [v for o in self.outcomes for v in o.violations]

    # ------------------------------------------------------------------------ mechanics
    def kinetic_energy(self, velocity):
        """``½ vᵀ M v`` in the velocity's own arithmetic (exact, mpmath or float)."""
        M = self.system.M
        if velocity is None:
            return None
        if isinstance(velocity, RationalMatrix):  # exact, without SymPy
            vs, Mr = list(velocity), M.tolist()
            return sum((vs[i] * Mr[i][j] * vs[j] for i in range(len(vs)) for j in range(len(vs))), Fraction(0)) / 2
        if is_sympy(velocity, "MatrixBase"):
            import sympy as sp

            Mx = M if isinstance(M, sp.MatrixBase) else sp.Matrix(M)
            return sp.expand((velocity.T * Mx * velocity)[0, 0] / 2)
        if is_mpmath(velocity, "matrix"):
            import mpmath
            import sympy as sp

            # certified velocities: T is not itself certified, so it is given as a float, computed
            # at 60 working digits inside this block (no mpmath value leaves the context)
            n = velocity.rows
            with mpmath.workdps(60):
                Mm = mpmath.matrix([[mpmath.mpf(str(sp.N(M[i, j], 70))) if isinstance(M, sp.MatrixBase)
                                     else mpmath.mpf(float(M[i, j])) for j in range(n)] for i in range(n)])
                return float((velocity.T * Mm * velocity)[0, 0] / 2)
        v = np.asarray(velocity, dtype=float).reshape(-1)
        return 0.5 * float(v @ np.asarray(M, dtype=float) @ v)

    @property
    def kinetic_energy_before(self):
        return self.kinetic_energy(self.system.v)

    @property
    def kinetic_energy_after(self):
        v = self.velocity
        return None if v is None else self.kinetic_energy(v)

    def momentum_residual(self, outcome: Outcome):
        """``M(v⁺ − v⁻) − Hᵀp`` (zero for every law; exact for exact outcomes), or None when the
        outcome carries no impulses."""
        if outcome.impulses is None or outcome.velocity is None:
            return None
        M, H, v = self.system.M, self.system.H, self.system.v
        vp, p = outcome.velocity, outcome.impulses
        if is_sympy(vp, "MatrixBase") and is_sympy(M, "MatrixBase"):
            import sympy as sp

            return sp.expand(M * (vp - v) - H.T * sp.Matrix(p))
        if is_mpmath(vp, "matrix"):
            return None  # the certified laws verify their balls themselves (impactsym.verify)
        Mf, Hf = np.asarray(M.tolist() if is_sympy(M, "MatrixBase") else M, dtype=float), \
            np.asarray(H.tolist() if is_sympy(H, "MatrixBase") else H, dtype=float)
        vf = np.asarray([float(x) for x in _entries(v)])
        return Mf @ (np.asarray(vp, dtype=float).reshape(-1) - vf) - Hf.T @ np.asarray(p, dtype=float).reshape(-1)

    def _residual(self, o: Outcome):
        """:meth:`momentum_residual` of ``o``, computed once: the check's residual is the JSON's
        (held with the very objects it was computed from, and used only while they are still
        ``o``'s velocity and impulses and the system's ``M``, ``H``, ``v``)."""
        s = self.system
        used = (o.velocity, o.impulses, s.M, s.H, s.v)
        key = tuple(map(id, used))
        memo = self.__dict__.setdefault("_residuals", {})
        got = memo.get(key)
        if got is not None and all(a is b for a, b in zip(got[0], used)):
            return got[1]
        r = self.momentum_residual(o)
        memo[key] = (used, r)
        return r

    def _check_momentum(self, o: Outcome) -> None:
        if is_sympy(o.velocity, "MatrixBase") and is_sympy(self.system.M, "MatrixBase") and o.impulses is not None:
            r = self._residual(o)
            if not all(_proved_zero(x) for x in r):
                raise VerificationError(self.law, f"momentum balance M(v+ - v-) = H^T p fails by {list(r)}")

    # ---------------------------------------------------------------------------- JSON
    def outcome_json(self, o: Outcome) -> dict:
        return _fresh(self._outcome_json(o, {}))

    def _outcome_json(self, o: Outcome, memo: dict) -> dict:
        """:meth:`outcome_json`, once per outcome in one :meth:`as_json` (``memo``: the answer is
        also among the outcomes or the selected ones); the caller copies what it keeps."""
        got = memo.get(id(o))
        if got is not None and got[0] is o:
            return got[1]
        d = {"exactness": _exactness(o.velocity), "digits": o.digits}
        d.update(vector_json("velocity", o.velocity, o.digits))
        d.update(vector_json("impulses", o.impulses, o.digits))
        d.update(number_json("kinetic_energy_after", self.kinetic_energy(o.velocity), o.digits))
        d.update(vector_json("momentum_residual", self._residual(o)))
        d["order"] = o.order
        d["orderings"] = o.orderings
        d["valid"] = o.valid
        d["violations"] = o.violations
        d["details"] = o.details
        memo[id(o)] = (o, d)
        return d

    def as_json(self) -> dict:
        """The one JSON schema of every law (``docs/resolution_schema.md``).

        Each outcome is written once (the answer is also an outcome or the selected one, and its
        velocity, impulses and ``T⁺`` are the top level's); every dict and list of the result is
        its own, as if each were written afresh."""
        return self._as_json(True)

    def _as_json(self, with_system: bool) -> dict:
        """:meth:`as_json`, without its ``scene`` and ``system`` keys when ``with_system`` is false
        (the other keys in the same order): for a writer that gives the system once for several
        laws (:func:`impactsym.suite.solve_case`) and would discard them."""
        answer = self.answer
        memo: dict = {}
        out = {"schema": SCHEMA, "law": self.law}
        if with_system:
            out["scene"] = self.system.scene
            out["system"] = self.system.as_json()
        out.update({"exact": self.exact, "exactness": self.exactness, "digits": self.digits,
                    "uniqueness": self.uniqueness})
        out.update(number_json("kinetic_energy_before", self.kinetic_energy_before))
        if answer is None:
            out["answer"] = None
            out.update({"velocity": None, "velocity_float": None, "impulses": None, "impulses_float": None,
                        "kinetic_energy_after": None, "kinetic_energy_after_float": None})
        else:
            a = self._outcome_json(answer, memo)
            out["answer"] = _fresh(a)
            for key in ("velocity", "velocity_float", "impulses", "impulses_float", "kinetic_energy_after",
                        "kinetic_energy_after_float"):
                out[key] = list(a[key]) if isinstance(a[key], list) else a[key]
        out["valid"] = self.valid
        out["violations"] = self.violations
        out["outcomes"] = [_fresh(self._outcome_json(o, memo)) for o in self.outcomes]
        out["selected"] = [_fresh(self._outcome_json(o, memo)) for o in self.selected]
        out["notes"] = list(self.notes)
        out["details"] = dict(self.details)
        return out


def _fresh(d: dict) -> dict:
    """A copy of an outcome's JSON as :meth:`Resolution.outcome_json` has always returned it: its
    own dict, lists of numbers, ``violations`` list and ``details`` dict (the entries shared)."""
    out = dict(d)
    for key in ("velocity", "velocity_float", "impulses", "impulses_float", "momentum_residual",
                "momentum_residual_float", "violations"):
        if out[key] is not None:
            out[key] = list(out[key])
    out["details"] = dict(out["details"])
    return out


def _proved_zero(x) -> bool:
    """Whether the exact number ``x`` is proved to be 0: it is the literal 0; or, each radicand's
    rational content taken out of its root (``sqrt(10*sqrt(2) + 150)`` is
    ``sqrt(10)*sqrt(sqrt(2) + 15)``, SymPy's own evaluation) and expanded, it is 0 (both steps
    identities: a few milliseconds where ``simplify`` takes a tenth of a second on the nested
    radicals of the pool). Not 0 when ``evalf`` certifies a non-zero value; else
    ``simplify(x) == 0`` decides, as it always has.

    >>> import sympy as sp
    >>> r = sp.sqrt(10*sp.sqrt(2) + 150) - sp.sqrt(2)*sp.sqrt(5*sp.sqrt(2) + 75)
    >>> _proved_zero(r), _proved_zero(r + sp.sqrt(2) - 1), _proved_zero(sp.Integer(0))
    (True, False, True)
    """
    import sympy as sp

    if x == 0:
        return True
    roots = x.replace(lambda z: z.is_Pow and z.base.is_Add and z.exp.is_Rational and not z.exp.is_Integer,
                      lambda z: sp.Pow(sp.factor_terms(z.base), z.exp))
    if sp.expand(roots) == 0:
        return True
    try:  # certified non-zero (evalf to full accuracy, strict): simplify could not make it 0 either
        value = x.evalf(15, strict=True)
        if value.is_Number and value != 0:
            return False
    except Exception:  # not evaluated to full accuracy (it may be 0): simplify decides
        pass
    return sp.simplify(x) == 0
