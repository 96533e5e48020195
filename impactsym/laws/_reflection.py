"""The one statement of the single-impact reflection that every law reflects with (private).

Seghete & Murphey, sec. II-A (``CONVENTIONS.md``): with ``w = M⁻¹uᵀ`` and ``s = u w``,

    G_u(e) = I − g w u,   G_u(e) v = v − g (u v) w,   p = −g (u v),   g = (1 + e)/s.

The formula is derived and proved in :mod:`derivations.reflection` (``printed_G``); the float
path of a law evaluates the generated kernels (``impactsym.kernels.reflect`` and
``reflection_map``). Certified and exact code cannot call a float kernel, so it uses the
functions below, which state the formula once with nothing but ``+ − × /``: the same text serves
SymPy, python-flint ``fmpq``, mpmath and plain floats (``tests/test_reflection_primitive.py``
evaluates them against the derivation's expression at random rationals).

Every law that reflects calls these: :mod:`impactsym.laws.reflection` (its exact, rational and
mpmath paths), :mod:`impactsym.laws.two_surface` (its exact iteration) and
:mod:`impactsym.laws.sequential` (its exact and float searches).
"""

from __future__ import annotations

__all__ = ["gain", "reflect_along", "reflect_sparse", "reflection_matrix", "sympy_parts", "fmpq_parts", "mpmath_parts"]


def gain(s, e=1):
    """The factor ``g = (1 + e)/s`` of ``G_u(e) = I − g w u`` (``s = u M⁻¹ uᵀ``), in the
    arithmetic of ``s`` and ``e``.

    >>> gain(4), gain(2.0, 0.5)
    (0.5, 0.75)
    """
    return (1 + e) / s


def reflect_along(v, w, uv, g, norm=None):
    """``(G_u(e) v, p)``: ``v − g (u v) w`` entry by entry and the impulse ``p = −g (u v)``.

    ``v`` and ``w`` are sequences (or column matrices supporting ``v - c * w``) in one
    arithmetic; ``uv = u v``; ``g`` from :func:`gain`; ``norm`` (optional) normalizes each entry.

    >>> reflect_along([1, 0], [1, 0], -1, 2)
    ([3, 0], 2)
    """
    c = g * uv
    if norm is None:
        if isinstance(v, (list, tuple)):
            return [a - c * b for a, b in zip(v, w)], -c
        return v - w * c, -c
    return [norm(a - c * b) for a, b in zip(v, w)], norm(-c)


def reflect_sparse(v, wcol, c, norm=lambda x: x):
    """``v − c w`` for ``w`` given sparsely as ``[(j, w_j), ...]`` (the searches' form); ``c = g (u v)``
    (:func:`gain`). Returns a tuple and the impulse ``−c``.

    >>> reflect_sparse((1, 5), [(0, 1)], -2)
    ((3, 5), 2)
    """
    out = list(v)
    for j, wj in wcol:
        out[j] = norm(v[j] - c * wj)
    return tuple(out), norm(-c)


def reflection_matrix(identity, w, u, g):
    """``G_u(e) = I − g w u`` from ``identity`` (n×n), the column ``w`` and the row ``u`` of one
    matrix type (SymPy, fmpq_mat or mpmath).

    >>> import sympy as sp
    >>> reflection_matrix(sp.eye(2), sp.Matrix([1, 0]), sp.Matrix([[1, 0]]), 2)
    Matrix([
    [-1, 0],
    [ 0, 1]])
    """
    return identity - (w * u) * g


def sympy_parts(M, u):
    """``(w, s)`` with ``w = M⁻¹uᵀ`` (SymPy column, LU solve) and ``s = u w``, exact."""
    w = M.LUsolve(u.T)
    return w, (u * w)[0, 0]


def fmpq_parts(M, u):
    """``(w, s)`` over the rationals with python-flint (``M`` an ``fmpq_mat``, ``u`` a 1×n
    ``fmpq_mat``), O(n³)."""
    w = M.solve(u.transpose())
    return w, (u * w)[0, 0]


def mpmath_parts(M, u):
    """``(w, s)`` with mpmath at the current precision (``M`` an ``mpmath.matrix``, ``u`` an
    ``mpmath.matrix`` column)."""
    import mpmath

    w = mpmath.lu_solve(M, u)
    return w, sum(u[i] * w[i] for i in range(M.rows))
