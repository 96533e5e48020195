"""Rational input read once, checked once and carried as sparse python-flint ``fmpq`` data.

The sequential law's exact rational path never forms a dense ``n×n`` matrix: a 1000-ball cradle
has a million mass-matrix entries but only a thousand non-zero ones. This module

* reads ``M``, ``H`` and ``v0`` straight into sparse ``fmpq`` rows (:func:`read_rational`): SymPy
  matrices over ``ZZ``/``QQ`` through their sparse ``DomainMatrix``, text of plain integers,
  fractions and decimals, and lists of ints/fractions. Anything else (floats, ``sqrt(2)``, an
  exponent literal, text with a syntax error) gives ``None`` and the caller takes the general
  path, which reads it as before and words every error;
* checks ``M`` exactly, as :func:`impactsym.mechanics.check_mass_matrix` does and with the same
  messages: symmetric, and positive definite by Sylvester's criterion, the ``k``-th pivot of
  elimination without pivoting being the ratio of the ``k``-th to the ``(k−1)``-th leading principal
  minor. The elimination is the symmetric one on the sparse upper triangle (``M = Uᵀ D⁻¹ U``,
  ``D = diag U``), so a diagonal or block-diagonal ``M`` costs its number of non-zeros, and the
  factor is kept to solve ``M W_i = H_iᵀ`` by sparse triangular solves;
* finds a null vector of ``H`` by sparse elimination (the refusal witness of
  :func:`~impactsym.laws.sequential.witness.valid_velocity_witness`: the same vector, the one of
  the first free column) and the rank of ``H``;
* verifies an outcome with sparse products (:func:`verify_outcome`): the checks of
  :func:`impactsym.verify.verify_exact` — ``H v⁺ ≥ 0``, kinetic energy, ``M(v⁺ − v0) = Hᵀp``,
  ``p ≥ 0`` — with its messages.

>>> data = read_rational("2,0;0,1", "1,0;-1,1", "-1,-2")
>>> data.n, data.k, data.M[0], data.H[1]
(2, 2, {0: 2}, [(0, -1), (1, 1)])
>>> read_rational("sqrt(2),0;0,1", "1,0", "1,1") is None
True
"""

from __future__ import annotations

import heapq
import re
from fractions import Fraction
from numbers import Integral
from numbers import Rational as _NumRational

import numpy as np
from flint import fmpq, fmpz

from ...errors import ImpactInputError, VerificationError

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule, sympy_instance
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["SparseRational", "read_rational", "verify_outcome", "verify_matrices", "two_surface_data"]

#: an entry the fast reader takes: an integer, a fraction or a decimal (no exponent, no names);
#: anything else is left to :func:`impactsym.numbers.parse_number`
_PLAIN = re.compile(r"[+-]?(?:\d+|\d+\.\d*|\.\d+)(?:/\d+)?")
#: the longest entry read here (the general parser's digit limit is 1000)
_MAX_ENTRY = 1000
_ZERO = fmpq(0)


def _entry(x):
    """One exact rational entry as ``fmpq``, or ``None`` (not a plain exact rational)."""
    if isinstance(x, fmpq):
        return x
    if isinstance(x, bool):
        return None
    if isinstance(x, (int, np.integer, fmpz)):
        return fmpq(int(x))
    if sympy_instance(x, "Rational"):  # Integer too
        return fmpq(int(x.p), int(x.q))
    if sympy_instance(x, "Basic"):
        return None
    if isinstance(x, str):
        s = x.strip()
        if len(s) > _MAX_ENTRY or not _PLAIN.fullmatch(s):
            return None
        num, _, den = s.partition("/")
        if den and int(den) == 0:
            return None
        f = Fraction(num)
        q = fmpq(f.numerator, f.denominator)
        return q / int(den) if den else q
    if isinstance(x, Integral):
        return fmpq(int(x))
    if isinstance(x, _NumRational) and not isinstance(x, (float, np.floating)):
        return fmpq(int(x.numerator), int(x.denominator))
    return None


def _sympy_rows(A):
    """Sparse rows of a SymPy matrix over ``ZZ`` or ``QQ`` (its ``DomainMatrix``), or ``None``."""
    rep = getattr(A, "_rep", None)
    if rep is None or not hasattr(rep, "to_sdm"):
        return None
    dom = rep.domain
    if not (dom.is_ZZ or dom.is_QQ):
        return None
    rows = [dict() for _ in range(A.rows)]
    for i, row in rep.to_sdm().items():
        out = rows[i]
        for j, x in row.items():
            if dom.is_ZZ:
                out[j] = fmpq(int(x))
            else:
                out[j] = x if isinstance(x, fmpq) else fmpq(int(x.numerator), int(x.denominator))
    return A.rows, A.cols, rows


def _matrix_rows(obj):
    """``(rows, cols, sparse rows)`` of an exact rational matrix-like, or ``None``."""
    if sympy_instance(obj, "MatrixBase"):
        return _sympy_rows(obj)
    if isinstance(obj, str):
        if not obj.strip():
            return None
        table = [r.split(",") for r in obj.split(";")]
    elif isinstance(obj, np.ndarray):
        if obj.ndim != 2 or not (obj.dtype == object or np.issubdtype(obj.dtype, np.integer)):
            return None
        table = obj.tolist()
    elif isinstance(obj, (list, tuple)) and obj and all(isinstance(r, (list, tuple)) for r in obj):
        table = obj
    else:
        return None
    cols = len(table[0])
    out = []
    for r in table:
        if len(r) != cols:
            return None
        row = {}
        for j, x in enumerate(r):
            q = _entry(x)
            if q is None:
                return None
            if q != 0:
                row[j] = q
        out.append(row)
    return len(table), cols, out


def _vector(obj):
    """An exact rational vector as a list of ``fmpq``, or ``None``."""
    if sympy_instance(obj, "MatrixBase"):
        got = _sympy_rows(obj)
        if got is None or 1 not in got[:2]:
            return None
        rows, cols, data = got
        if cols == 1:
            return [data[i].get(0, _ZERO) for i in range(rows)]
        return [data[0].get(j, _ZERO) for j in range(cols)]
    if isinstance(obj, str):
        if ";" in obj or not obj.strip():
            return None
        entries = obj.split(",")
    elif isinstance(obj, np.ndarray):
        if not (obj.dtype == object or np.issubdtype(obj.dtype, np.integer)):
            return None
        if obj.ndim == 2 and 1 in obj.shape:
            obj = obj.reshape(-1)
        if obj.ndim != 1:
            return None
        entries = obj.tolist()
    elif isinstance(obj, (list, tuple)):
        entries = obj
        if entries and all(isinstance(r, (list, tuple)) and len(r) == 1 for r in entries):
            entries = [r[0] for r in entries]
    else:
        return None
    out = []
    for x in entries:
        q = _entry(x)
        if q is None:
            return None
        out.append(q)
    return out


class SparseRational:
    """``M``, ``H``, ``v0`` exact and sparse, checked: ``M`` symmetric positive definite (its
    sparse factor kept), every row of ``H`` non-zero, the shapes consistent.

    Attributes
    ----------
    n, k : int
    M : list of dict
        Row ``i`` of ``M``: ``{j: M_ij}`` over the non-zero entries (symmetric).
    H : list of list
        Row ``i`` of ``H``: ``[(j, H_ij), ...]`` over the non-zero entries, ``j`` increasing.
    v0 : tuple of fmpq
    """

    def __init__(self, n, k, M, H, v0):
        self.n, self.k, self.M, self.H, self.v0 = n, k, M, H, tuple(v0)
        self._echelon = None
        self._check_M()

    def _check_M(self):
        """Symmetric positive definite, decided exactly. A dense ``M`` (at least a quarter of its
        entries non-zero) is decided by python-flint's fraction-free LU of the integer matrix
        ``L·M`` (``L`` the common denominator): without a row exchange its ``k``-th pivot is the
        ``k``-th leading principal minor of ``L·M``, of the sign of ``M``'s (Bareiss); ``M⁻¹H_iᵀ``
        then comes from ``fmpq_mat.solve``. A sparse ``M`` is factored as below. A matrix that
        fails is refused with the message of the elimination (:meth:`_factor`)."""
        n = self.n
        nnz = sum(len(r) for r in self.M)
        self.dense = None
        if n >= 8 and 4 * nnz >= n * n and self._symmetric() is None:
            from flint import fmpq_mat

            from ...mechanics import positive_definite_by_fflu

            Mq = fmpq_mat(n, n)
            for i, row in enumerate(self.M):
                for j, x in row.items():
                    Mq[i, j] = x
            ok = positive_definite_by_fflu(self.M, n)
            if ok:
                self.dense = Mq
                return
        self._factor()

    # ----------------------------------------------------------------- M = U^T D^-1 U
    def _factor(self):
        """Symmetric elimination without pivoting on the upper triangle (Sylvester's criterion).

        Raises the messages of :func:`impactsym.mechanics.check_mass_matrix`."""
        n, M = self.n, self.M
        bad = self._symmetric()
        if bad is not None:
            i, j = bad
            raise ImpactInputError("mass_matrix", f"not symmetric (entry ({i}, {j}) is {M[i].get(j, _ZERO)} but "
                                                  f"({j}, {i}) is {M[j].get(i, _ZERO)})")
        from ...mechanics import symmetric_elimination

        U = symmetric_elimination(M, n, "mass_matrix")
        self.U = U
        cols = [[] for _ in range(n)]
        for i, row in enumerate(U):
            for j, x in row.items():
                if j > i:
                    cols[j].append((i, x))
        self.Ucols = cols

    def _symmetric(self):
        """``None`` when ``M`` is symmetric, else the first asymmetric pair ``(i, j)``, ``i < j``."""
        from ...mechanics import first_asymmetric_pair

        return first_asymmetric_pair(self.M)

    def solve_rows(self, rows):
        """``M⁻¹H_iᵀ`` for sparse rows ``H_i`` (``[(j, x), ...]``), each sparse."""
        if self.dense is None:
            return [self.solve(r) for r in rows]
        from flint import fmpq_mat

        n = self.n
        B = fmpq_mat(n, len(rows))
        for c, r in enumerate(rows):
            for j, x in r:
                B[j, c] = x
        X = self.dense.solve(B)
        flat = X.entries()
        m = len(rows)
        return [[(j, flat[j * m + c]) for j in range(n) if flat[j * m + c] != 0] for c in range(m)]

    def solve(self, rhs):
        """``M⁻¹ b`` for a sparse ``b`` (``[(j, b_j), ...]``), sparse: ``[(j, x_j), ...]`` with
        ``j`` increasing. Forward ``Uᵀ y = b``, then back ``U x = D y`` (``D = diag U``), each
        touching only the entries they reach.

        >>> SparseRational(2, 1, [{0: fmpq(2), 1: fmpq(1)}, {0: fmpq(1), 1: fmpq(1)}], [[(0, fmpq(1))]],
        ...                [fmpq(0)] * 2).solve([(0, fmpq(1))])
        [(0, 1), (1, -1)]
        """
        if self.dense is not None:
            return self.solve_rows([rhs])[0]
        U, Ucols = self.U, self.Ucols
        r = {}
        for j, b in rhs:
            r[j] = r.get(j, _ZERO) + b
        heap = list(r)
        heapq.heapify(heap)
        t = {}
        while heap:
            kk = heapq.heappop(heap)
            rk = r.pop(kk, None)
            if rk is None or rk == 0:
                continue
            row = U[kk]
            yk = rk / row[kk]
            t[kk] = rk  # (D y)_k = U_kk y_k = r_k
            for l, x in row.items():
                if l > kk:
                    if l not in r:
                        heapq.heappush(heap, l)
                        r[l] = -x * yk
                    else:
                        r[l] -= x * yk
        heap = [-j for j in t]
        heapq.heapify(heap)
        x = {}
        while heap:
            kk = -heapq.heappop(heap)
            rk = t.pop(kk, None)
            if rk is None or rk == 0:
                continue
            xk = rk / U[kk][kk]
            x[kk] = xk
            for i, u in Ucols[kk]:
                if i not in t:
                    heapq.heappush(heap, -i)
                    t[i] = -u * xk
                else:
                    t[i] -= u * xk
        return sorted(x.items())

    # ----------------------------------------------------------------- H
    def echelon(self):
        """Row echelon form of ``H`` by sparse elimination, the leftmost non-zero column pivoting:
        ``{pivot column: row as dict}`` (every entry at or right of the pivot). Its pivot columns
        are those of the reduced row echelon form."""
        if self._echelon is not None:
            return self._echelon
        active = {i: dict(r) for i, r in enumerate(self.H) if r}
        incol: dict = {}
        for i, r in active.items():
            for j in r:
                incol.setdefault(j, set()).add(i)
        pivots = {}
        for c in range(self.n):
            rows = [i for i in incol.get(c, ()) if i in active]
            if not rows:
                continue
            p = min(rows, key=lambda i: (len(active[i]), i))
            prow = active.pop(p)
            for j in prow:
                incol[j].discard(p)
            pivots[c] = prow
            a = prow[c]
            for i in rows:
                if i == p:
                    continue
                r = active[i]
                f = r[c] / a
                for j, y in prow.items():
                    nv = r.get(j, _ZERO) - f * y
                    if nv == 0:
                        if j in r:
                            del r[j]
                            incol[j].discard(i)
                    else:
                        if j not in r:
                            incol.setdefault(j, set()).add(i)
                        r[j] = nv
                if not r:
                    del active[i]
        self._echelon = pivots
        return pivots

    def rank(self) -> int:
        return len(self.echelon())

    def null_vector(self):
        """The null vector of ``H`` of its first free column (``x_f = 1``, the other free entries
        0), or ``None`` when ``H`` has full column rank: the first vector of
        :func:`impactsym.arithmetic.linalg.nullspace`."""
        piv = self.echelon()
        f = next((c for c in range(self.n) if c not in piv), None)
        if f is None:
            return None
        x = {f: fmpq(1)}
        for c in sorted((c for c in piv if c < f), reverse=True):
            row = piv[c]
            acc = _ZERO
            for j, y in row.items():
                if j != c:
                    xj = x.get(j)
                    if xj is not None:
                        acc += y * xj
            if acc != 0:
                x[c] = -acc / row[c]
        return [x.get(j, _ZERO) for j in range(self.n)]

    # ----------------------------------------------------------------- products
    def mul_M(self, vec: dict) -> dict:
        """``M x`` for a sparse ``x`` (``{j: x_j}``), sparse (symmetric ``M``: rows as columns);
        a dense ``M`` multiplies in flint (``fmpq_mat``)."""
        if self.dense is not None and vec:
            from flint import fmpq_mat

            x = fmpq_mat(self.n, 1)
            for j, xj in vec.items():
                x[j, 0] = xj
            col = (self.dense * x).entries()
            return {i: y for i, y in enumerate(col) if y != 0}
        out: dict = {}
        M = self.M
        for j, xj in vec.items():
            for i, m in M[j].items():
                out[i] = out.get(i, _ZERO) + m * xj
        return out

    def row_dot(self, i, v) -> fmpq:
        """``H_i v`` for a dense ``v``."""
        acc = _ZERO
        for j, h in self.H[i]:
            acc += h * v[j]
        return acc

    def to_sympy(self):
        """``(M, H, v0)`` as dense SymPy matrices (for the parts of the law that need them)."""
        n, k = self.n, self.k
        q = lambda x: sp.Rational(int(x.p), int(x.q))  # noqa: E731
        M = sp.zeros(n, n)
        for i, row in enumerate(self.M):
            for j, x in row.items():
                M[i, j] = q(x)
        H = sp.zeros(k, n)
        for i, row in enumerate(self.H):
            for j, x in row:
                H[i, j] = q(x)
        return M, H, sp.Matrix([q(x) for x in self.v0])


def read_rational(mass_matrix, gradients, velocity):
    """``SparseRational`` of the input when every entry is a plain exact rational and the shapes
    agree, else ``None`` (the caller's general path then reads the input and words any error).

    A mass matrix that is not symmetric or not positive definite, or a zero row of ``H``, raises
    :class:`~impactsym.errors.ImpactInputError` with the messages of :mod:`impactsym.mechanics`.

    >>> read_rational("1,2;2,1", "1,0", "1,0")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: mass_matrix: not positive definite (leading principal minor 2 is -3)
    """
    Mg = _matrix_rows(mass_matrix)
    if Mg is None:
        return None
    n, cols, M = Mg
    if n != cols or n == 0:
        return None
    Hg = _matrix_rows(gradients)
    v = _vector(velocity)
    if Hg is None or v is None:
        return None
    k, hcols, Hd = Hg
    if hcols != n or k == 0 or len(v) != n:
        return None
    data = SparseRational.__new__(SparseRational)
    data.n, data.k, data.M, data.v0 = n, k, M, tuple(v)
    data._echelon = None
    data._check_M()
    for i, r in enumerate(Hd):
        if not r:
            raise ImpactInputError("gradients",
                                   f"row {i} is the zero covector (a constraint gradient must be non-zero)")
    data.H = [sorted(r.items()) for r in Hd]
    return data


def read_floats(mass_matrix, gradients, velocity):
    """``SparseRational`` of checked float arrays at their exact binary values (the float path's
    exact twin, read from the non-zero entries only, each distinct float converted once), or
    ``None`` when ``M`` fails the exact check (a float ``M`` positive definite only up to
    rounding): the caller then keeps the dense form.

    >>> data = read_floats(np.eye(2), np.array([[1.0, 0.0], [-1.0, 0.1]]), np.array([-1.0, -2.0]))
    >>> data.H[1], data.v0
    ([(0, -1), (1, 3602879701896397/36028797018963968)], (-1, -2))
    """
    cache: dict = {}

    def q(x):
        x = float(x)
        got = cache.get(x)
        if got is None:
            f = Fraction(x)
            got = cache[x] = fmpq(f.numerator, f.denominator)
        return got

    M, H, v = (np.asarray(a, dtype=float) for a in (mass_matrix, gradients, velocity))
    n, k = M.shape[0], H.shape[0]
    Mrows: list = [{} for _ in range(n)]
    for i, j in zip(*np.nonzero(M)):
        Mrows[i][int(j)] = q(M[i, j])
    Hrows: list = [[] for _ in range(k)]
    for i, j in zip(*np.nonzero(H)):  # row-major: j increasing within a row
        Hrows[i].append((int(j), q(H[i, j])))
    try:
        return SparseRational(n, k, Mrows, Hrows, [q(x) for x in v.reshape(-1)])
    except ImpactInputError:
        return None


def verify_outcome(law, data: SparseRational, v, p, *, energy="equal") -> None:
    """The checks of :func:`impactsym.verify.verify_exact` on sparse data, with its messages:
    ``H_i v⁺ ≥ 0`` on every contact, the kinetic energy (``energy="equal"``: ``v⁺ᵀMv⁺ = v0ᵀMv0``;
    ``"at_most"``: ``≤``; ``None``: not checked), ``M(v⁺ − v0) = Hᵀp`` entry by entry and
    ``p ≥ 0``. Raises :class:`~impactsym.errors.VerificationError`.

    >>> data = read_rational("1,0;0,1", "1,0;-1,1", "-1,-2")
    >>> verify_outcome("demo", data, [fmpq(1), fmpq(2)], [fmpq(6), fmpq(4)])
    >>> verify_outcome("demo", data, [fmpq(1), fmpq(0)], [fmpq(2), fmpq(0)])
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: demo: verification of the outcome failed: H_2 v+ = -1 < 0 on a closed contact (a bug in impactsym; the outcome was not returned)
    """
    v0 = data.v0
    for i in range(data.k):
        w = data.row_dot(i, v)
        if w < 0:
            raise VerificationError(law, f"H_{i + 1} v+ = {w} < 0 on a closed contact")
    d = {j: a - b for j, (a, b) in enumerate(zip(v, v0)) if a != b}
    if energy is not None:
        # v+^T M v+ - v0^T M v0 = d^T M (v+ + v0)
        Md = data.mul_M(d)
        delta = sum((m * (v[j] + v0[j]) for j, m in Md.items()), _ZERO)
        if (energy == "equal" and delta != 0) or (energy == "at_most" and delta > 0):
            Tp = sum((m * v[j] for j, m in data.mul_M({j: x for j, x in enumerate(v) if x != 0}).items()), _ZERO)
            Tm = sum((m * v0[j] for j, m in data.mul_M({j: x for j, x in enumerate(v0) if x != 0}).items()), _ZERO)
            if energy == "equal":
                raise VerificationError(law, f"kinetic energy: v+^T M v+ = {Tp}, expected 1 * v^T M v = {Tm}")
            raise VerificationError(law, f"kinetic energy: v+^T M v+ = {Tp} > 1 * v^T M v = {Tm}")
    else:
        Md = data.mul_M(d)
    for i, h in enumerate(data.H):
        pi = p[i]
        if pi != 0:
            for j, x in h:
                Md[j] = Md.get(j, _ZERO) - x * pi
    bad = [j for j, r in Md.items() if r != 0]
    if bad:
        j = min(bad)
        raise VerificationError(law, f"momentum: (M(v+ - v) - H^T p)_{j + 1} = {Md[j]} != 0")
    for i in range(data.k):
        if p[i] < 0:
            raise VerificationError(law, f"impulse p_{i + 1} = {p[i]} < 0")


def verify_matrices(law, Mq, Hq, vq, vplus, p) -> None:
    """The checks of :func:`impactsym.verify.verify_exact` (energy conserved) for exact rational
    data given as ``fmpq_mat`` (``M`` n×n, ``H`` k×n, columns ``v``, ``v⁺``, ``p``), with its
    messages, every product in flint: ``H v⁺ ≥ 0``, ``v⁺ᵀMv⁺ = vᵀMv``, ``M(v⁺ − v) = Hᵀp``,
    ``p ≥ 0``.

    >>> from flint import fmpq_mat
    >>> I, H = fmpq_mat([[1, 0], [0, 1]]), fmpq_mat([[1, 0], [-1, 1]])
    >>> verify_matrices("demo", I, H, fmpq_mat([[-1], [-2]]), fmpq_mat([[1], [2]]), fmpq_mat([[6], [4]]))
    >>> verify_matrices("demo", I, H, fmpq_mat([[-1], [-2]]), fmpq_mat([[1], [2]]), fmpq_mat([[6], [5]]))
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: demo: verification of the outcome failed: momentum: (M(v+ - v) - H^T p)_1 = 1 != 0 (a bug in impactsym; the outcome was not returned)
    """
    w = (Hq * vplus).entries()
    for i, x in enumerate(w):
        if x < 0:
            raise VerificationError(law, f"H_{i + 1} v+ = {x} < 0 on a closed contact")
    Tp = (vplus.transpose() * Mq * vplus)[0, 0]
    Tm = (vq.transpose() * Mq * vq)[0, 0]
    if Tp != Tm:
        raise VerificationError(law, f"kinetic energy: v+^T M v+ = {Tp}, expected 1 * v^T M v = {Tm}")
    r = (Mq * (vplus - vq) - Hq.transpose() * p).entries()
    for j, x in enumerate(r):
        if x != 0:
            raise VerificationError(law, f"momentum: (M(v+ - v) - H^T p)_{j + 1} = {x} != 0")
    for i, x in enumerate(p.entries()):
        if x < 0:
            raise VerificationError(law, f"impulse p_{i + 1} = {x} < 0")


def two_surface_data(data: SparseRational, wcols=None):
    """Checked rational data of two contacts as the ``fmpq_mat`` tuple ``(W, gram, c, vq, Mq, Hq)``
    that :func:`impactsym.laws.two_surface._resolve` takes (``W = M⁻¹Hᵀ``, ``gram = H W``,
    ``c = H v``): the two-surface law then reads and checks nothing again. ``wcols``: the columns
    of ``W`` when the caller has them (sparse), else solved here."""
    from flint import fmpq_mat

    n = data.n
    if wcols is None:
        wcols = data.solve_rows(data.H)
    W = fmpq_mat(n, 2)
    for c in range(2):
        for j, x in wcols[c]:
            W[j, c] = x
    Hq = fmpq_mat(2, n)
    for i in range(2):
        for j, x in data.H[i]:
            Hq[i, j] = x
    gram = Hq * W
    vq = fmpq_mat(n, 1, list(data.v0))
    c = Hq * vq
    if data.dense is not None:
        Mq = data.dense
    else:
        Mq = fmpq_mat(n, n)
        for i, row in enumerate(data.M):
            for j, x in row.items():
                Mq[i, j] = x
    return W, gram, c, vq, Mq, Hq
