"""Exact linear algebra: row reduction, null space, solve, rank, row-space membership.

Matrices are lists of rows of field elements (:mod:`impactsym.arithmetic.fields`). The work is
done by

* python-flint ``fmpq_mat`` (``rref``, ``rank``) for :class:`~.fields.RationalField`;
* SymPy's ``DomainMatrix`` over ``QQ`` or a number field ``QQ<...>`` for
  :class:`~.fields.AlgebraicField` data that are algebraic (``sqrt(2)``, ``cos(pi/5)``);
* Gauss–Jordan elimination whose every zero test is a certified sign
  (:func:`~.closed_form.certified_sign`, which raises rather than guess) only for other closed
  forms (``pi``, ``E``), where no exact field is available.

>>> from impactsym.arithmetic.fields import RationalField as Q, AlgebraicField as A
>>> rows = [[Q.num(1), Q.num(2), Q.num(3)], [Q.num(2), Q.num(4), Q.num(7)]]
>>> rref(rows, 3, Q)
([[1, 2, 0], [0, 0, 1]], [0, 2])
>>> nullspace(rows, 3, Q)
[[-2, 1, 0]]
>>> rank([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2]], A), rank([[sp.pi, 1], [1, sp.E]], A)
(1, 2)
"""

from __future__ import annotations

import flint

from . import LazyModule
from .closed_form import tidy
from .fields import AlgebraicField, RationalField, sign_of
from .rational import as_fmpq, to_sympy_matrix, to_sympy_rational

#: SymPy, imported on first use: the rational paths (python-flint) run without it
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["rref", "kernel_basis", "nullspace", "solve_columns", "rank", "independent", "in_row_space",
           "dot", "matvec", "minner", "exact_rank", "ExactLinearAlgebra"]


def _rref_rational(rows, ncols):
    A = flint.fmpq_mat(len(rows), ncols, [x for r in rows for x in r])
    R, r = A.rref()
    flat = R.entries()
    out, piv = [], []
    for i in range(r):
        row = flat[i * ncols:(i + 1) * ncols]
        piv.append(next(j for j, x in enumerate(row) if x != 0))
        out.append(row)
    return out, piv


def _number_field_matrix(rows, ncols):
    """``rows`` as a ``DomainMatrix`` over ``QQ`` or a number field, or ``None`` (not algebraic)."""
    from sympy.polys.matrices import DomainMatrix

    try:
        dM = DomainMatrix.from_list_sympy(len(rows), ncols, [list(r) for r in rows], extension=True)
    except Exception:  # noqa: BLE001 - no number field found: the certified elimination decides
        return None
    if dM.domain.is_ZZ or dM.domain.is_QQ or dM.domain.is_AlgebraicField:
        return dM.to_field()
    return None


def _rref_certified(rows, ncols, F):
    """Gauss–Jordan elimination on closed forms with no number field: every zero test certified."""
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


def rref(rows: list[list], ncols: int, F) -> tuple[list[list], list[int]]:
    """The reduced row echelon form (non-zero rows only) and its pivot columns.

    Parameters
    ----------
    rows : list of lists of field elements, each of length ``ncols``
    ncols : int
    F : RationalField or AlgebraicField

    >>> from impactsym.arithmetic.fields import AlgebraicField as A
    >>> rref([[sp.sqrt(2), 2], [1, sp.sqrt(2)]], 2, A)
    ([[1, sqrt(2)]], [0])
    """
    if not rows or ncols == 0:
        return [], []
    if F is RationalField:
        return _rref_rational(rows, ncols)
    dM = _number_field_matrix(rows, ncols)
    if dM is None:
        return _rref_certified(rows, ncols, F)
    R, piv = dM.rref()
    Rm = R.to_Matrix()
    return [[F.norm(Rm[i, j]) for j in range(ncols)] for i in range(len(piv))], list(piv)


def kernel_basis(R: list[list], piv: list, m: int, F) -> list[list]:
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


def nullspace(rows: list[list], ncols: int, F) -> list[list]:
    """A basis of ``{x : rows · x = 0}`` (one vector per free column of the reduced form)."""
    R, piv = rref(rows, ncols, F)
    return kernel_basis(R, piv, ncols, F)


def solve_columns(cols: list[list], b: list, F):
    """Solve ``[cols] z = b``: ``(z0, null-space basis)``, or ``None`` when inconsistent.

    >>> solve_columns([[RationalField.num(1), RationalField.num(1)]], [RationalField.num(2)] * 2, RationalField)
    ([2], [])
    """
    m = len(cols)
    n = len(b)
    aug = [[cols[j][i] for j in range(m)] + [b[i]] for i in range(n)]
    R, piv = rref(aug, m + 1, F)
    if m in piv:
        return None
    z0 = [F.zero] * m
    for i, p in enumerate(piv):
        z0[p] = R[i][m]
    return z0, kernel_basis(R, piv, m, F)


def rank(vectors: list[list], F) -> int:
    """The rank of a list of vectors (rows)."""
    if not vectors or not vectors[0]:
        return 0
    if F is RationalField:
        return flint.fmpq_mat(len(vectors), len(vectors[0]), [x for r in vectors for x in r]).rank()
    dM = _number_field_matrix(vectors, len(vectors[0]))
    if dM is not None:
        return dM.rank()
    return len(_rref_certified(vectors, len(vectors[0]), F)[1])


def independent(vectors: list[list], F) -> list[int]:
    """Indices of a maximal independent subset (greedy, in order)."""
    keep: list[int] = []
    for i, v in enumerate(vectors):
        if rank([vectors[j] for j in keep] + [v], F) > len(keep):
            keep.append(i)
    return keep


def in_row_space(rows: list[list], target: list, F) -> bool:
    """Whether ``target`` is a linear combination of ``rows`` (equal ranks).

    >>> Q = RationalField
    >>> in_row_space([[Q.num(1), Q.num(1)]], [Q.num(2), Q.num(2)], Q), in_row_space([[Q.num(1), Q.num(1)]], [Q.num(1), Q.num(0)], Q)
    (True, False)
    """
    if all(F.sign(t) == 0 for t in target):
        return True
    return rank([list(r) for r in rows] + [list(target)], F) == rank([list(r) for r in rows], F)


def dot(a, b, F):
    """``Σ a_i b_i`` in ``F``."""
    return F.norm(sum((x * y for x, y in zip(a, b)), F.zero))


def matvec(M, v, F):
    """``M v`` for a list of rows ``M``."""
    return [dot(row, v, F) for row in M]


def minner(M, a, b, F):
    """The kinetic inner product ``aᵀ M b``."""
    return dot(a, matvec(M, b, F), F)


def exact_rank(A) -> int:
    """The rank of a matrix of exact SymPy numbers, decided exactly (no rounding, no ``nsimplify``).

    Rational entries are reduced with python-flint, algebraic entries (``sqrt(2)``, ``cos(pi/5)``
    once SymPy writes it as a surd) in their number field (``DomainMatrix`` over ``QQ<...>``); any
    other entries by Gaussian elimination whose every zero test is
    :func:`impactsym.arithmetic.closed_form.certified_sign` (which raises rather than guess).

    Parameters
    ----------
    A : sympy.Matrix of numbers (no free symbols)

    Returns
    -------
    int

    Raises
    ------
    ValueError
        ``A`` has free symbols.

    Examples
    --------
    A non-singular matrix whose determinant is ``-13*sqrt(2)/10**34`` (``nsimplify`` rounds it to a
    singular one):

    >>> A = sp.Matrix([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2 - sp.Rational(13, 10**34)]])
    >>> exact_rank(A), exact_rank(sp.Matrix([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2]]))
    (2, 1)
    >>> exact_rank(sp.Matrix([[sp.pi, 1], [1, 1 / sp.pi]])), exact_rank(sp.Matrix([[sp.pi, 1], [1, sp.E]]))
    (1, 2)
    """
    A = sp.Matrix(A)
    if A.free_symbols:
        raise ValueError(f"A: exact_rank needs numbers, got the symbols {sorted(map(str, A.free_symbols))}")
    if A.rows == 0 or A.cols == 0:
        return 0
    rows = [[sp.sympify(x) for x in A.row(i)] for i in range(A.rows)]
    if all(x.is_Rational for r in rows for x in r):
        return rank([[RationalField.num(x) for x in r] for r in rows], RationalField)
    return rank(rows, AlgebraicField)


class ExactLinearAlgebra:
    """The few exact operations the multi-contact laws need on whole matrices, in one arithmetic:
    ``"rational"`` (python-flint ``fmpq_mat``) or ``"sympy"`` (exact SymPy matrices, certified signs).

    >>> from impactsym.arithmetic.rational import rational_matrix
    >>> la = ExactLinearAlgebra("rational")
    >>> A = rational_matrix(sp.Matrix([[2, -1], [-1, 2]]))
    >>> la.solve(la.extract(A, [0], [0]), la.column([1]))[0, 0], la.solve(rational_matrix(sp.Matrix([[1, 1], [1, 1]])), la.column([1, 1]))
    (1/2, None)
    """

    def __init__(self, kind: str):
        if kind not in ("rational", "sympy"):
            raise ValueError(f"kind must be 'rational' or 'sympy', got {kind!r}")
        self.kind = kind

    def extract(self, A, rows, cols):
        if self.kind == "sympy":
            return A.extract(list(rows), list(cols))
        return flint.fmpq_mat(len(rows), len(cols), [A[i, j] for i in rows for j in cols])

    def column(self, values):
        if self.kind == "sympy":
            return sp.Matrix(list(values))
        vals = [v if isinstance(v, flint.fmpq) else as_fmpq(v) for v in values]
        return flint.fmpq_mat(len(vals), 1, vals)

    def zeros(self, r, c):
        return sp.zeros(r, c) if self.kind == "sympy" else flint.fmpq_mat(r, c)

    def rows(self, A) -> int:
        return A.rows if self.kind == "sympy" else A.nrows()

    def solve(self, A, b):
        """``A⁻¹ b``, or ``None`` when ``A`` is singular (decided exactly)."""
        n = self.rows(A)
        if n == 0:
            return self.zeros(0, 1)
        if self.kind == "rational":
            if A.rank() < n:
                return None
            return A.solve(b)
        det = sp.simplify(A.det(method="berkowitz"))
        if sign_of(det) == 0:
            return None
        return A.LUsolve(b).applyfunc(tidy)

    def rank(self, A) -> int:
        if self.kind == "rational":
            return A.rank()
        return exact_rank(A)

    def to_sympy(self, X):
        if self.kind == "sympy":
            return X
        if isinstance(X, flint.fmpq_mat):
            return to_sympy_matrix(X)
        return to_sympy_rational(X) if isinstance(X, flint.fmpq) else sp.sympify(X)

