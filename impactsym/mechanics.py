"""Mass matrices, constraint gradients, velocities, and the kinetic metric.

Conventions (``CONVENTIONS.md``): ``M`` symmetric positive definite (checked, exactly for exact
input), gradient rows ``H_i = Dφ_i`` (covectors, never normalized), relative normal velocity
``w = H v`` (approaching when ``w_i < 0``), kinetic metric ``<a, b>_M = aᵀ M b``.

Every checker returns the input converted to its arithmetic (a SymPy matrix on the exact path,
a float64 array on the float path) and raises :class:`~impactsym.errors.ImpactInputError` naming
the argument and the violated condition.

Examples
--------
>>> import sympy as sp
>>> M = check_mass_matrix("11/10,0;0,1")
>>> H = check_gradients("1,0;-1,1", 2)
>>> kinetic_angle_cos(M, H[0, :], H[1, :])
-sqrt(210)/21
>>> m_normal(M, H[0, :]).T
Matrix([[sqrt(110)/11, 0]])
>>> check_mass_matrix("1,2;2,1")
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: mass_matrix: not positive definite (leading principal minor 2 is -3)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .arithmetic import LazyModule
from .errors import ImpactInputError
from .exact import certified_sign

#: SymPy and the number parser, imported on first use: the exact checks of rational input
#: (python-flint) need neither
sp = LazyModule("sympy", globals(), "sp")

__all__ = [
    "check_mass_matrix",
    "check_gradient",
    "check_gradients",
    "check_velocity",
    "kinetic_energy",
    "m_normal",
    "kinetic_angle_cos",
    "kinetic_angle",
    "relative_velocity",
]

#: relative asymmetry tolerated in a float mass matrix (a few ulps of its largest entry)
FLOAT_SYMMETRY_RTOL = 8 * np.finfo(float).eps


def _as(obj: Any, argument: str, exact: bool, vector: bool = False):
    from .numbers import to_exact_matrix, to_float_array

    if exact:
        return to_exact_matrix(obj, argument, vector=vector)
    arr = to_float_array(obj, argument)
    if vector:
        arr = arr.reshape(-1) if arr.ndim == 2 and 1 in arr.shape else arr
        if arr.ndim != 1:
            raise ImpactInputError(argument, f"expected a vector, got shape {arr.shape}")
    return arr


def check_mass_matrix(M: Any, argument: str = "mass_matrix", *, exact: bool | None = None):
    """Check that ``M`` is a square, symmetric, positive definite matrix with finite entries.

    Exact input is decided exactly (Sylvester's criterion on leading principal minors, each sign
    certified); float input by a Cholesky factorization.

    >>> check_mass_matrix([[2, 1], [1, 2]])
    Matrix([
    [2, 1],
    [1, 2]])
    >>> check_mass_matrix([[1.0, 0.0], [0.5, 1.0]])
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: mass_matrix: not symmetric (entry (0, 1) is 0.0 but (1, 0) is 0.5)
    """
    if exact is None:
        from .numbers import is_exact

        exact = is_exact(M)
    A = _as(M, argument, exact)
    shape = A.shape
    if len(shape) != 2 or shape[0] != shape[1] or shape[0] == 0:
        raise ImpactInputError(argument, f"must be a non-empty square matrix, got shape {tuple(shape)}")
    n = shape[0]
    if exact and (_over_rationals(A) or all(x.is_Rational for row in A.tolist() for x in row)):
        return _check_rational_spd(A, argument)
    if exact:
        for i in range(n):
            for j in range(i + 1, n):
                if certified_sign(A[i, j] - A[j, i]) != 0:
                    raise ImpactInputError(
                        argument, f"not symmetric (entry ({i}, {j}) is {A[i, j]} but ({j}, {i}) is {A[j, i]})"
                    )
        # Sylvester's criterion via fraction-free elimination: the k-th leading minor is a pivot product.
        for k in range(1, n + 1):
            minor = A[:k, :k].det(method="bareiss") if k > 1 else A[0, 0]
            minor = sp.nsimplify(minor) if minor.is_Float else minor
            if certified_sign(minor) <= 0:
                raise ImpactInputError(
                    argument, f"not positive definite (leading principal minor {k} is {sp.simplify(minor)})"
                )
        return A
    scale = np.max(np.abs(A))
    asym = np.abs(A - A.T)
    if np.any(asym > FLOAT_SYMMETRY_RTOL * scale):
        i, j = np.unravel_index(np.argmax(asym), asym.shape)
        raise ImpactInputError(argument, f"not symmetric (entry ({i}, {j}) is {float(A[i, j])!r} but ({j}, {i}) is {float(A[j, i])!r})")
    try:
        np.linalg.cholesky(A)
    except np.linalg.LinAlgError:
        raise ImpactInputError(argument, "not positive definite (Cholesky factorization failed)") from None
    return A


def _over_rationals(A) -> bool:
    """Whether the SymPy matrix ``A`` is stored over ``ZZ`` or ``QQ``: every entry is then rational
    (and a zero entry is not stored), known without reading the entries one by one."""
    from .numbers import _rational_domain

    return _rational_domain(A)


def _nonzero_rows(A) -> set:
    """The rows of a SymPy matrix over ``ZZ``/``QQ`` that hold a non-zero entry (its sparse
    ``DomainMatrix`` stores no zero)."""
    return {i for i, row in A._rep.to_sdm().items() if row}


def _rational_rows(A: sp.Matrix) -> list:
    """Rows of a rational SymPy matrix as dicts ``{j: fmpq}`` of the non-zero entries, read from
    its sparse ``DomainMatrix`` when it is over ``ZZ``/``QQ`` (no per-entry SymPy access)."""
    from flint import fmpq

    n, m = A.shape
    rep = getattr(A, "_rep", None)
    rows: list = [dict() for _ in range(n)]
    if rep is not None and hasattr(rep, "to_sdm") and (rep.domain.is_ZZ or rep.domain.is_QQ):
        zz = rep.domain.is_ZZ
        for i, row in rep.to_sdm().items():
            out = rows[i]
            for j, x in row.items():
                out[j] = fmpq(int(x)) if zz else (x if isinstance(x, fmpq) else fmpq(int(x.numerator),
                                                                                  int(x.denominator)))
        return rows
    for i in range(n):
        for j in range(m):
            x = A[i, j]
            if x != 0:
                rows[i][j] = fmpq(int(x.p), int(x.q))
    return rows


def positive_definite_by_fflu(rows: list, n: int) -> bool:
    """``True`` when the symmetric rational matrix with sparse ``rows`` (dicts ``{j: fmpq}``) is
    certainly positive definite by python-flint's fraction-free LU (C): with ``L`` the common
    denominator, the LU of the integer matrix ``L·M`` has no row exchange and every pivot
    positive. Without a row exchange the ``k``-th pivot of fraction-free elimination is the
    ``k``-th leading principal minor of ``L·M`` (Bareiss), which has the sign of ``M``'s, so this
    is Sylvester's criterion. ``False`` means *not decided here* (the elimination then decides
    and words the refusal).

    >>> from flint import fmpq
    >>> positive_definite_by_fflu([{0: fmpq(2), 1: fmpq(1)}, {0: fmpq(1), 1: fmpq(2)}], 2)
    True
    >>> positive_definite_by_fflu([{0: fmpq(1), 1: fmpq(2)}, {0: fmpq(2), 1: fmpq(1)}], 2)
    False
    """
    from flint import fmpz, fmpz_mat

    den = fmpz(1)
    for row in rows:
        for x in row.values():
            den = den.lcm(x.q)
    Z = fmpz_mat(n, n)
    for i, row in enumerate(rows):
        for j, x in row.items():
            Z[i, j] = x.p * (den // x.q)
    try:
        P, _, _, U = Z.fflu()
    except Exception:  # noqa: BLE001 - singular: not decided here
        return False
    return P.is_one() and all(U[i, i] > 0 for i in range(n))


def _check_rational_spd(A: sp.Matrix, argument: str) -> sp.Matrix:
    """Symmetric and positive definite, decided exactly for rational ``A`` (python-flint): a
    dense ``A`` by :func:`positive_definite_by_fflu` (C, fraction-free), otherwise (and to word a
    refusal) by Gaussian elimination without pivoting on the sparse rows, whose k-th pivot is the
    ratio of the k-th to the (k−1)-th leading principal minor (Sylvester's criterion)."""
    n = A.shape[0]
    F = _rational_rows(A)
    bad = first_asymmetric_pair(F)
    if bad is not None:
        i, j = bad
        raise ImpactInputError(argument, f"not symmetric (entry ({i}, {j}) is {A[i, j]} but ({j}, {i}) is {A[j, i]})")
    if n >= 8 and 4 * sum(len(r) for r in F) >= n * n and positive_definite_by_fflu(F, n):
        return A
    symmetric_elimination(F, n, argument)
    return A


def first_asymmetric_pair(rows):
    """``None`` when the matrix of sparse rows (``{column: value}``) is symmetric, else its first
    asymmetric pair ``(i, j)``, ``i < j``.

    >>> first_asymmetric_pair([{0: 1, 1: 2}, {0: 2}]), first_asymmetric_pair([{1: 2}, {}, {0: 1}])
    (None, (0, 1))
    """
    bad = None
    for i, row in enumerate(rows):
        for j, x in row.items():
            if i != j and rows[j].get(i, 0) != x:
                pair = (i, j) if i < j else (j, i)
                if bad is None or pair < bad:
                    bad = pair
    return bad


def symmetric_elimination(rows, n: int, argument: str = "mass_matrix") -> list[dict]:
    """Gaussian elimination without pivoting on the upper triangle of a symmetric rational matrix
    given as sparse rows (``{column: fmpq}``); the trailing block stays symmetric, so only the upper
    triangle is updated. The k-th pivot is the ratio of the k-th to the (k−1)-th leading principal
    minor, so every pivot is positive exactly when the matrix is positive definite (Sylvester's
    criterion). Returns the eliminated upper rows ``U`` (``M = Uᵀ D⁻¹ U``, ``D`` the pivots; zeros
    dropped), or raises naming the first leading principal minor that is not positive.

    >>> from flint import fmpq
    >>> symmetric_elimination([{0: fmpq(2), 1: fmpq(1)}, {0: fmpq(1), 1: fmpq(2)}], 2)
    [{0: 2, 1: 1}, {1: 3/2}]
    >>> symmetric_elimination([{0: fmpq(1), 1: fmpq(2)}, {0: fmpq(2), 1: fmpq(1)}], 2)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: mass_matrix: not positive definite (leading principal minor 2 is -3)
    """
    from flint import fmpq

    zero = fmpq(0)
    U = [{j: x for j, x in row.items() if j >= i} for i, row in enumerate(rows)]
    minor = fmpq(1)
    for k in range(n):
        row = U[k]
        pivot = row.get(k, zero)
        minor *= pivot
        if pivot <= 0:
            raise ImpactInputError(argument, f"not positive definite (leading principal minor {k + 1} is {minor})")
        right = [(j, x) for j, x in row.items() if j > k]
        for j, x in right:
            f = x / pivot
            target = U[j]
            for l, y in right:
                if l >= j:
                    value = target.get(l, zero) - f * y
                    if value == 0:
                        target.pop(l, None)
                    else:
                        target[l] = value
    return U


def check_gradient(u: Any, n: int, argument: str = "gradient", *, exact: bool | None = None):
    """Check one gradient covector of length ``n`` that is not zero; returns a row (1×n) / 1-D array.

    >>> check_gradient("0,0", 2)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: gradient: is the zero covector (a constraint gradient must be non-zero)
    """
    if exact is None:
        from .numbers import is_exact

        exact = is_exact(u)
    g = _as(u, argument, exact, vector=True)
    length = g.rows if exact else g.shape[0]
    if length != n:
        raise ImpactInputError(argument, f"has length {length}, expected {n} (the mass matrix is {n}×{n})")
    if exact:
        zero = not _nonzero_rows(g) if _over_rationals(g) else all(certified_sign(x) == 0 for x in g)
    else:
        zero = not np.any(g)
    if zero:
        raise ImpactInputError(argument, "is the zero covector (a constraint gradient must be non-zero)")
    return g.T if exact else g


def check_gradients(H: Any, n: int, argument: str = "gradients", *, exact: bool | None = None):
    """Check a stack of gradient rows ``H`` (k×n, each row non-zero).

    >>> check_gradients("1,0;0,0", 2)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: gradients: row 1 is the zero covector (a constraint gradient must be non-zero)
    """
    if exact is None:
        from .numbers import is_exact

        exact = is_exact(H)
    A = _as(H, argument, exact)
    if not exact and A.ndim == 1:
        A = A.reshape(1, -1)
    rows, cols = A.shape
    if cols != n:
        raise ImpactInputError(argument, f"has {cols} columns, expected {n} (the mass matrix is {n}×{n})")
    if rows == 0:
        raise ImpactInputError(argument, "has no rows (at least one closed contact is needed)")
    nonzero = _nonzero_rows(A) if exact and _over_rationals(A) else None
    for i in range(rows):
        if nonzero is not None:
            zero = i not in nonzero
        else:
            row = A[i, :]
            zero = all(certified_sign(x) == 0 for x in row) if exact else not np.any(row)
        if zero:
            raise ImpactInputError(argument, f"row {i} is the zero covector (a constraint gradient must be non-zero)")
    return A


def check_velocity(v: Any, n: int, argument: str = "velocity", *, exact: bool | None = None):
    """Check a generalized velocity of length ``n``; returns a column (exact) or 1-D array (float).

    >>> check_velocity("1,2,3", 2)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: velocity: has length 3, expected 2 (the mass matrix is 2×2)
    """
    if exact is None:
        from .numbers import is_exact

        exact = is_exact(v)
    g = _as(v, argument, exact, vector=True)
    length = g.rows if exact else g.shape[0]
    if length != n:
        raise ImpactInputError(argument, f"has length {length}, expected {n} (the mass matrix is {n}×{n})")
    return g


def kinetic_energy(M, v):
    """``T = ½ vᵀ M v`` (exact for exact input).

    >>> kinetic_energy(sp.eye(2), sp.Matrix([1, 1]))
    1
    """
    if isinstance(M, sp.MatrixBase):
        v = sp.Matrix(v)
        return sp.expand((v.T * M * v)[0, 0] / 2)
    v = np.asarray(v, dtype=float)
    return 0.5 * float(v @ np.asarray(M, dtype=float) @ v)


def _row(h, exact: bool = False):
    if exact and not isinstance(h, sp.MatrixBase):
        from .numbers import to_exact_matrix

        h = to_exact_matrix(h, "gradient", vector=True)
    if isinstance(h, sp.MatrixBase):
        return h if h.rows == 1 else h.T
    return np.asarray(h, dtype=float).reshape(-1)


def m_normal(M, h):
    """The M-normal of a constraint (Acary & Taha eq. 39): ``n = M⁻¹hᵀ / √(h M⁻¹ hᵀ)``.

    It is a unit vector in the kinetic metric: ``nᵀ M n = 1``.

    >>> n = m_normal(sp.diag(2, 1), sp.Matrix([[1, 1]]))
    >>> n.T, sp.simplify((n.T * sp.diag(2, 1) * n)[0])
    (Matrix([[sqrt(6)/6, sqrt(6)/3]]), 1)
    """
    if isinstance(M, sp.MatrixBase):
        h = _row(h, exact=True)
        w = M.LUsolve(h.T)
        from .arithmetic.remembered import simplify_remembered

        return simplify_remembered(w / sp.sqrt((h * w)[0, 0]))
    h = _row(h)
    w = np.linalg.solve(np.asarray(M, dtype=float), h)
    return w / np.sqrt(h @ w)


def _rational_forms(M, hi, hj):
    """``(H_i M⁻¹ H_jᵀ, H_i M⁻¹ H_iᵀ, H_j M⁻¹ H_jᵀ)`` as SymPy rationals when every entry is a SymPy
    ``Rational``, by python-flint (the same exact numbers SymPy's ``LUsolve`` gives, without its
    O(n³) SymPy arithmetic); None otherwise, or when ``M`` is singular (SymPy then says so)."""
    from .arithmetic.rational import all_rational, rational_matrix, to_sympy_rational

    if not all_rational(M, hi, hj):
        return None
    Mq, hiq, hjq = rational_matrix(M), rational_matrix(hi.T), rational_matrix(hj.T)
    try:
        wi, wj = Mq.solve(hiq), Mq.solve(hjq)
    except ZeroDivisionError:
        return None
    return tuple(to_sympy_rational((a.transpose() * b)[0, 0]) for a, b in ((hiq, wj), (hiq, wi), (hjq, wj)))


def _solve(M, b):
    """``M⁻¹ b`` exactly: ``b_j / M_jj`` for a diagonal ``M`` (the bodies' masses: what ``LUsolve``
    gives, without its elimination, 10 ms a solve for 14 coordinates), else ``M.LUsolve(b)``."""
    if M.is_diagonal():
        return sp.Matrix([b[j, 0] / M[j, j] for j in range(M.rows)])
    return M.LUsolve(b)


def kinetic_angle_cos(M, hi, hj):
    """``cos θ_ij = H_i M⁻¹ H_jᵀ / √(H_i M⁻¹ H_iᵀ · H_j M⁻¹ H_jᵀ)`` (Acary & Taha eq. 40).

    >>> kinetic_angle_cos(sp.eye(2), sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]]))
    -sqrt(2)/2
    """
    if isinstance(M, sp.MatrixBase):
        hi, hj = _row(hi, exact=True), _row(hj, exact=True)
        rational = _rational_forms(M, hi, hj)
        if rational is not None:
            # a rational over the square root of a rational: SymPy's automatic form (a rational
            # times the square root of a square-free integer) is already what radsimp(simplify(.))
            # returns (tests/test_mechanics.py checks it), without simplify's search
            num, aii, ajj = rational
            return num / sp.sqrt(aii * ajj)
        Minv_hj = _solve(M, hj.T)
        Minv_hi = _solve(M, hi.T)
        num, aii, ajj = (hi * Minv_hj)[0, 0], (hi * Minv_hi)[0, 0], (hj * Minv_hj)[0, 0]
        from .arithmetic.remembered import simplify_remembered

        return sp.radsimp(simplify_remembered(num / sp.sqrt(aii * ajj)))
    Mf = np.asarray(M, dtype=float)
    hi, hj = _row(hi), _row(hj)
    wi, wj = np.linalg.solve(Mf, hi), np.linalg.solve(Mf, hj)
    return float(hi @ wj / np.sqrt((hi @ wi) * (hj @ wj)))


def kinetic_angle(M, hi, hj):
    """The kinetic angle ``θ_ij ∈ [0, π]`` between two constraints (exact: a SymPy ``acos``).

    >>> kinetic_angle(sp.eye(2), sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]]))
    3*pi/4
    """
    c = kinetic_angle_cos(M, hi, hj)
    if isinstance(c, sp.Basic):
        return sp.acos(c)
    return float(np.arccos(np.clip(c, -1.0, 1.0))) if abs(c) <= 1 + 1e-15 else float("nan")


def relative_velocity(H, v):
    """``w = H v``, the relative normal velocities (approaching when ``w_i < 0``).

    >>> relative_velocity(sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, 0])).T
    Matrix([[-1, 1]])
    """
    if isinstance(H, sp.MatrixBase):
        return H * sp.Matrix(v)
    return np.asarray(H, dtype=float) @ np.asarray(v, dtype=float)
