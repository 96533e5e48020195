"""Scene builders: balls on a line or in the plane (and fixed walls), reduced to ``M``, ``H`` and ``v⁻``.

A builder keeps only what the impact needs: the contacts that are closed at the impact instant
(decided exactly for exact input, within a stated tolerance for float input) and the bodies that
take part in one of them. Canonical scenes of the papers are in :mod:`impactsym.models`; the file
format that feeds these builders is :mod:`impactsym.scenes.fileformat`.
"""

from __future__ import annotations

from fractions import Fraction

from ..arithmetic import LazyModule, sympy_instance
from ..resolution import RationalMatrix
from .scene import Scene

# SymPy is imported on first use: a float scene (and its checks) runs without it (issue 15)
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["balls_on_line", "balls_in_plane", "full_velocity", "FLOAT_GAP_RTOL"]


# ---------------------------------------------------------------------------------------------
# Builders: balls on a line, balls in the plane
# ---------------------------------------------------------------------------------------------
#: float scenes: a gap g counts as closed when |g| ≤ FLOAT_GAP_RTOL · L, L the scene's length scale
#: (the largest of 1, |positions| and radii); g < −FLOAT_GAP_RTOL · L is an overlap (refused)
FLOAT_GAP_RTOL = 1e-9


def _is_float_input(*objs) -> bool:
    from ..numbers import is_exact

    return not is_exact(*objs)


def _numbers(values, argument: str, exact: bool, *, length: int | None = None):
    from ..errors import ImpactInputError
    from ..numbers import to_exact

    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ImpactInputError(argument, f"must be a sequence of numbers, got {values!r}")
    vals = list(values)
    if length is not None and len(vals) != length:
        raise ImpactInputError(argument, f"has {len(vals)} entries, expected {length} (one per ball)")
    out = []
    for x in vals:
        if exact:
            out.append(to_exact(x, argument))
        else:
            try:
                xf = float(sp.sympify(x)) if (isinstance(x, str) or sympy_instance(x, "Basic")) else float(x)
            except (TypeError, ValueError, sp.SympifyError):
                raise ImpactInputError(argument, f"entry {x!r} is not a number") from None
            import math

            if not math.isfinite(xf):
                raise ImpactInputError(argument, f"entry {xf} is not finite")
            out.append(xf)
    return out


def _sign(x, exact: bool) -> int:
    if isinstance(x, (int, Fraction)):  # exact by construction (the rational builders' numbers)
        return (x > 0) - (x < 0)
    from ..exact import certified_sign

    if exact:
        return certified_sign(x)
    return (x > 0) - (x < 0)


def _fractions(values, argument: str, *, length: int | None = None) -> list:
    """The rational builders' numbers: each an ``int`` or a ``Fraction`` (kept as ``Fraction``)."""
    from ..errors import ImpactInputError

    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ImpactInputError(argument, f"must be a sequence of numbers, got {values!r}")
    vals = list(values)
    if length is not None and len(vals) != length:
        raise ImpactInputError(argument, f"has {len(vals)} entries, expected {length} (one per ball)")
    for x in vals:
        if isinstance(x, bool) or not isinstance(x, (int, Fraction)):
            raise ImpactInputError(argument, f"entry {x!r} is not an int or a Fraction (rational=True)")
    return [Fraction(x) for x in vals]


def _fmpq(x):
    """A rational (SymPy ``Rational`` or ``Fraction``) as flint ``fmpq``."""
    from flint import fmpq

    if isinstance(x, Fraction):
        return fmpq(x.numerator, x.denominator)
    return fmpq(int(x.p), int(x.q))


def _classify_gap(gap, scale, exact: bool, tol, what: str, balls=(), wall=None):
    """0 closed, 1 open; raises on overlap.

    The error carries ``balls`` (0-based indices of the balls at fault) and ``wall`` (0-based
    index of the wall, or None), so that a caller reading a scene file can name the key at fault.
    """
    from ..errors import ImpactInputError

    if exact:
        s = _sign(gap, True)
    else:
        t = FLOAT_GAP_RTOL * scale if tol is None else tol
        s = 0 if abs(gap) <= t else (1 if gap > 0 else -1)
    if s < 0:
        exc = ImpactInputError("positions", f"{what} overlap (gap {gap} < 0)")
        exc.balls, exc.wall = tuple(balls), wall
        raise exc
    return s


def _positive(vals, argument, exact, *, allow_zero=False):
    from ..errors import ImpactInputError

    for i, m in enumerate(vals):
        s = _sign(m, exact)
        if s < 0 or (s == 0 and not allow_zero):
            cond = "non-negative" if allow_zero else "positive"
            raise ImpactInputError(argument, f"entry {i + 1} must be {cond}, got {m}")


def _approaching_exact(H, v, exact: bool, nonzeros=None):
    """Whether each contact is approaching (``(H v)_i < 0``), decided exactly.

    ``nonzeros`` (optional): per row, the columns of its nonzero entries; only those are read
    (a zero entry adds nothing to the sum, so the verdicts are those of the sum over every column).
    A row whose entries and velocities are all rational is summed in flint ``fmpq`` (exact);
    otherwise the SymPy sum's sign is certified (:func:`impactsym.exact.certified_sign`).
    """
    from ..exact import certified_sign

    if nonzeros is None:
        nonzeros = [range(H.shape[1])] * H.shape[0]
    if isinstance(H, RationalMatrix):  # Fractions: summed in fmpq, exact
        from flint import fmpq

        vq = [_fmpq(x) for x in v]
        return [sum((_fmpq(H[i, j]) * vq[j] for j in nonzeros[i]), fmpq(0)) < 0 for i in range(H.shape[0])]
    vq = None
    if exact and all(sympy_instance(x, "Rational") for x in v):
        from flint import fmpq

        vq = [fmpq(int(x.p), int(x.q)) for x in v]
    out = []
    for i in range(H.shape[0]):
        if exact:
            row = [(H[i, j], j) for j in nonzeros[i]]
            if vq is not None and all(sympy_instance(h, "Rational") for h, _ in row):
                w = fmpq(0)
                for h, j in row:
                    w += fmpq(int(h.p), int(h.q)) * vq[j]
                out.append(w < 0)
            else:
                w = sum((h * v[j] for h, j in row), sp.Integer(0))
                out.append(certified_sign(w) < 0)
        else:  # decided on the floats' exact binary values (fmpq), never on rounding noise
            from ..arithmetic import as_fmpq
            from flint import fmpq

            w = sum((as_fmpq(H[i, j]) * as_fmpq(v[j]) for j in nonzeros[i]), fmpq(0))
            out.append(w < 0)
    return out


def _exact_matrix(shape, entries):
    """The SymPy matrix of ``shape`` with the given nonzero ``entries`` ({(i, j): value}), equal
    (same entries, same domain) to ``sp.Matrix`` of the dense rows, without building them: for
    rational entries ``sp.zeros`` then the nonzeros set one by one (a 1000 × 1000 ``sp.Matrix`` of
    dense rows takes seconds, ``sp.diag`` of 1000 entries more); other entries take the dense path."""
    if all((isinstance(x, int) or sympy_instance(x, "Rational")) for x in entries.values()):
        A = sp.zeros(*shape)
        for (i, j), x in entries.items():
            if x != 0:
                A[i, j] = x
        return A
    rows = [[0] * shape[1] for _ in range(shape[0])]
    for (i, j), x in entries.items():
        rows[i][j] = x
    return sp.Matrix(shape[0], shape[1], [x for r in rows for x in r])


def _assemble(masses, velocities, dim, contacts, exact, coords_of, meta, rational=False):
    """Reduce to the involved bodies: M, H, v and the bookkeeping for :func:`full_velocity`.

    H is built from its nonzeros (a contact touches one or two balls), never as dense rows.
    ``rational``: ``M``, ``H``, ``v`` as :class:`~impactsym.resolution.RationalMatrix` (the entries
    are ``Fraction``), the same entries as the SymPy matrices of the exact path.
    """
    import numpy as np

    from ..errors import ImpactInputError

    if not contacts:
        raise ImpactInputError("positions", "no contact is closed (every gap is positive): there is no impact")
    involved = sorted({b for c in contacts for b, _ in c[1] if b is not None})
    slot = {b: i for i, b in enumerate(involved)}
    n = dim * len(involved)
    hent = {}  # (row, column) -> value, in the order the dense rows would fill them
    for r, (_, entries) in enumerate(contacts):
        for b, g in entries:
            if b is None:
                continue
            for d in range(dim):
                key = (r, dim * slot[b] + d)
                hent[key] = hent.get(key, 0) + g[d]
    nonzeros = [[] for _ in contacts]
    for (r, c) in hent:
        nonzeros[r].append(c)
    mdiag = [masses[b] for b in involved for _ in range(dim)]
    vel = [velocities[b][d] if dim > 1 else velocities[b] for b in involved for d in range(dim)]
    if rational:
        M = RationalMatrix.from_entries((n, n), {(i, i): x for i, x in enumerate(mdiag)})
        H = RationalMatrix.from_entries((len(contacts), n), hent)
        v = RationalMatrix.column(vel)
    elif exact:
        M = _exact_matrix((n, n), {(i, i): x for i, x in enumerate(mdiag)})
        H = _exact_matrix((len(contacts), n), hent)
        v = sp.Matrix(vel)
    else:
        M = np.diag(np.asarray(mdiag, dtype=float))
        H = np.zeros((len(contacts), n), dtype=float)
        for (r, c), x in hent.items():
            H[r, c] = x
        v = np.asarray(vel, dtype=float)
    names = [c[0] for c in contacts]
    meta = dict(meta)
    meta.update({"bodies": [b + 1 for b in involved], "dim": dim,
                 "uninvolved": [b + 1 for b in range(len(masses)) if b not in slot],
                 "all_velocities": velocities, "exact": exact})
    scene = Scene(M, H, v, coords_of(involved), names, _approaching_exact(H, v, exact, nonzeros), meta)
    return scene


def balls_on_line(masses, radii, positions, velocities, walls=(), *, gap_tolerance=None,
                  rational: bool = False) -> Scene:
    """Balls on a line (and fixed walls), reduced to the contacts closed at the impact instant.

    Coordinates are the centres ``x_b`` of the *involved* balls (those in a closed contact); a
    ball in no closed contact stays out of ``M`` and ``H`` (the impact does not change its
    velocity; :func:`full_velocity` puts it back). Contacts, with ``φ ≥ 0`` admissible:

    * ball ``i`` left of ball ``j`` (adjacent or not): ``φ = x_j − x_i − r_i − r_j``, row ``[…, −1, …, +1, …]``;
    * ball right of a wall at ``w``: ``φ = x − r − w`` (row ``+1``); left of it: ``φ = w − x − r`` (row ``−1``).

    A contact is closed when its gap is zero: decided exactly for exact input; for float input
    when ``|gap| ≤ gap_tolerance`` (default ``FLOAT_GAP_RTOL`` times the scene's length scale).

    Parameters
    ----------
    masses, radii, positions, velocities : sequences, one entry per ball (masses > 0, radii ≥ 0)
    walls : sequence of wall positions (fixed, infinite mass)
    gap_tolerance : float, optional (float input only)
    rational : bool
        Every number an ``int`` or a ``Fraction``, and ``M``, ``H``, ``v`` returned as
        :class:`~impactsym.resolution.RationalMatrix` (exact, without SymPy: what the float path
        of the command line reads a built-in line scene with, issue 15). The contacts, their
        order and the entries are those of the exact (SymPy) path; every decision is exact
        (``Fraction`` and flint ``fmpq`` comparisons).

    Returns
    -------
    Scene
        ``contacts`` are named ``"i-j"`` and ``"wall@w-i"`` (balls numbered from 1), ``meta``
        records the involved and uninvolved balls.

    Raises
    ------
    ImpactInputError
        Mismatched lengths, non-positive masses, negative radii, overlaps (negative gaps), a
        ball centred on a wall, no closed contact.

    Examples
    --------
    >>> sc = balls_on_line([1, 1, 1, 1], [1, 1, 1, 1], [0, 2, 4, 9], [1, 0, 0, -1])
    >>> sc.H, sc.contacts, sc.approaching, sc.meta["uninvolved"]
    (Matrix([
    [-1,  1, 0],
    [ 0, -1, 1]]), ['1-2', '2-3'], [True, False], [4])
    >>> balls_on_line([1, 1], [1, 1], [0, "3/2"], [1, 0])
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: positions: balls 1 and 2 overlap (gap -1/2 < 0)
    >>> from fractions import Fraction
    >>> sc = balls_on_line([1, Fraction(1, 2)], [1, 1], [1, 3], [1, 0], [0], rational=True)
    >>> sc.M, sc.H, sc.contacts, sc.approaching
    (RationalMatrix([['1', '0'], ['0', '1/2']]), RationalMatrix([['-1', '1'], ['1', '0']]), ['1-2', 'wall@0-1'], [True, False])
    """
    from ..errors import ImpactInputError

    fractions = rational
    exact = fractions or not _is_float_input(masses, radii, positions, velocities, list(walls))
    nb = len(masses) if hasattr(masses, "__len__") else None
    if not nb:
        raise ImpactInputError("masses", "at least one ball is needed")
    numbers = (lambda vals, arg, _exact, length=None: _fractions(vals, arg, length=length)) if fractions else _numbers
    m = numbers(masses, "masses", exact, length=nb)
    r = numbers(radii, "radii", exact, length=nb)
    x = numbers(positions, "positions", exact, length=nb)
    v = numbers(velocities, "velocities", exact, length=nb)
    w = numbers(walls, "walls", exact) if len(walls) else []
    _positive(m, "masses", exact)
    _positive(r, "radii", exact, allow_zero=True)
    scale = max([1.0] + [abs(float(t)) for t in x + r + w])
    rational = fractions or (exact and all(sympy_instance(t, "Rational") for t in x + r + w))
    if rational:
        xq, rq, wq = ([_fmpq(t) for t in seq] for seq in (x, r, w))
        contacts = _line_pairs_sorted(x, r, xq, rq, scale)
    else:
        contacts = _line_pairs_all(x, r, exact, scale, gap_tolerance)
    for wi, wall in enumerate(w):
        for b in range(nb):
            if rational:  # exact: the signs of fmpq differences
                side = (xq[b] > wq[wi]) - (xq[b] < wq[wi])
                if side != 0:
                    gq = (xq[b] - rq[b] - wq[wi]) if side > 0 else (wq[wi] - xq[b] - rq[b])
                    if gq > 0:
                        continue
            else:
                side = _sign(x[b] - wall, exact)
            if side == 0:
                exc = ImpactInputError("positions", f"ball {b + 1} is centred on the wall at {wall}")
                exc.balls, exc.wall = (b,), wi
                raise exc
            gap = (x[b] - r[b] - wall) if side > 0 else (wall - x[b] - r[b])
            if _classify_gap(gap, scale, exact, gap_tolerance, f"ball {b + 1} and the wall at {wall}", (b,), wi) == 0:
                contacts.append((f"wall@{wall}-{b + 1}", [(b, (side,)), (None, None)]))
    contacts = _dedupe(contacts)
    return _assemble(m, v, 1, contacts, exact, lambda inv: [f"x{b + 1}" for b in inv],
                     {"builder": "balls_on_line", "walls": w, "masses": m, "radii": r, "positions": x}, fractions)


def _line_pairs_all(x, r, exact, scale, gap_tolerance):
    """The closed ball–ball contacts on a line, every pair tested (irrational or float input)."""
    contacts = []
    nb = len(x)
    for i in range(nb):
        for j in range(i + 1, nb):
            lo, hi = (i, j) if _sign(x[j] - x[i], exact) >= 0 else (j, i)
            gap = x[hi] - x[lo] - r[lo] - r[hi]
            if _classify_gap(gap, scale, exact, gap_tolerance, f"balls {i + 1} and {j + 1}", (i, j)) == 0:
                contacts.append((f"{i + 1}-{j + 1}", [(lo, (-1,)), (hi, (1,))]))
    return contacts


def _line_pairs_sorted(x, r, xq, rq, scale):
    """The closed ball–ball contacts on a line for rational input, in O(n log n + contacts).

    Sorted by ``(position, index)``, the gap of balls ``p < q`` (sorted places) is the sum of the
    consecutive gaps between them plus twice the radii of the balls strictly between them. So no
    pair overlaps when no consecutive pair does, and ``p, q`` touch exactly when every consecutive
    gap from ``p`` to ``q`` is zero and every ball strictly between has radius zero. Comparisons are
    exact (flint ``fmpq``). The contacts, their names and order, and the error of an overlap (the
    first overlapping pair ``i < j``) are those of :func:`_line_pairs_all`.
    """
    nb = len(x)
    order = sorted(range(nb), key=lambda b: (xq[b], b))
    cgap = [xq[order[k + 1]] - xq[order[k]] - rq[order[k]] - rq[order[k + 1]] for k in range(nb - 1)]
    if any(g < 0 for g in cgap):  # some pair overlaps: find and report the first, as every-pair does
        for i in range(nb):
            for j in range(i + 1, nb):
                lo, hi = (i, j) if xq[j] >= xq[i] else (j, i)
                if xq[hi] - xq[lo] - rq[lo] - rq[hi] < 0:
                    gap = x[hi] - x[lo] - r[lo] - r[hi]
                    _classify_gap(gap, scale, True, None, f"balls {i + 1} and {j + 1}", (i, j))
        raise AssertionError("a negative consecutive gap implies an overlapping pair")  # pragma: no cover
    pairs = []
    for p in range(nb - 1):
        q = p + 1
        while q < nb and cgap[q - 1] == 0:
            lo, hi = order[p], order[q]
            pairs.append((min(lo, hi), max(lo, hi), lo, hi))
            if rq[hi] != 0:
                break
            q += 1
    pairs.sort()
    return [(f"{i + 1}-{j + 1}", [(lo, (-1,)), (hi, (1,))]) for i, j, lo, hi in pairs]


def _dedupe(contacts):
    seen = set()
    out = []
    for c in contacts:
        if c[0] not in seen:
            seen.add(c[0])
            out.append(c)
    return out


def balls_in_plane(masses, radii, positions, velocities, walls=(), *, gap_tolerance=None) -> Scene:
    """Balls in the plane (frictionless, no spin) and fixed walls, reduced to the contacts closed
    at the impact.

    Coordinates ``(x_b, y_b)`` of the involved balls. Contact ``i–j`` (``i < j``):
    ``φ = ‖G_j − G_i‖ − r_i − r_j``; at contact ``‖G_j − G_i‖ = r_i + r_j``, so its gradient row is
    ``−nᵀ`` on ball ``i`` and ``+nᵀ`` on ball ``j`` with ``n = (G_j − G_i)/(r_i + r_j)``, rational for
    rational input. Closedness is decided exactly (``certified_sign`` of ``‖G_j − G_i‖ − r_i − r_j``);
    float input uses the tolerance ``FLOAT_GAP_RTOL`` as in :func:`balls_on_line`.

    A wall is the half-plane ``{G : n̂·(G − P) ≥ 0}`` of a point ``P`` and a normal ``n`` pointing
    into the free side. The normal need not have unit length: it is divided by its exact length,
    ``n̂ = n / √(n·n)`` (rational when ``n·n`` is the square of a rational, e.g. ``(3, 4) → (3/5, 4/5)``;
    otherwise a square root, kept exact). Contact ``wallJ-b`` (wall ``J`` and ball ``b``, both
    numbered from 1): ``φ = n̂·(G_b − P) − r_b``, gradient row ``n̂ᵀ`` on ball ``b``. A ball with
    ``φ < 0`` (overlapping the wall, or behind it) is refused.

    Parameters
    ----------
    masses, radii : sequences (masses > 0, radii > 0)
    positions, velocities : sequences of pairs, one per ball
    walls : sequence of ``(point, normal)``, each a pair of pairs (the normal non-zero)
    gap_tolerance : float, optional (float input only)

    Examples
    --------
    >>> sc = balls_in_plane([1, 1, 1], [1, 1, 1], [(0, 0), (2, 0), (5, 5)], [(1, 0), (0, 0), (0, 0)])
    >>> sc.H, sc.coordinates, sc.meta["uninvolved"]
    (Matrix([[-1, 0, 1, 0]]), ['x1', 'y1', 'x2', 'y2'], [3])
    >>> sc = balls_in_plane([2], [5], [(3, 4)], [(-1, -1)], walls=[((0, 0), (3, 4))])
    >>> sc.contacts, sc.H, sc.approaching
    (['wall1-1'], Matrix([[3/5, 4/5]]), [True])
    """
    import math

    from ..errors import ImpactInputError

    def pair(p):
        return p if hasattr(p, "__len__") and not isinstance(p, str) else [p]

    flat_p = [c for p in positions for c in pair(p)]
    flat_v = [c for p in velocities for c in pair(p)]
    flat_w = [c for w in walls for part in (pair(w) if len(pair(w)) == 2 else []) for c in pair(part)]
    exact = not _is_float_input(masses, radii, flat_p, flat_v, flat_w)
    nb = len(masses) if hasattr(masses, "__len__") else None
    if not nb:
        raise ImpactInputError("masses", "at least one ball is needed")
    m = _numbers(masses, "masses", exact, length=nb)
    r = _numbers(radii, "radii", exact, length=nb)
    _positive(m, "masses", exact)
    _positive(r, "radii", exact)
    P, V = [], []
    for name, src, dst in (("positions", positions, P), ("velocities", velocities, V)):
        if len(src) != nb:
            raise ImpactInputError(name, f"has {len(src)} entries, expected {nb} (one per ball)")
        for b, p in enumerate(src):
            if isinstance(p, str) or not hasattr(p, "__len__") or len(p) != 2:
                raise ImpactInputError(name, f"entry {b + 1} must be a pair (x, y), got {p!r}")
            dst.append(_numbers(p, name, exact))
    W = []  # (point, unit normal)
    for j, w in enumerate(walls):
        if isinstance(w, str) or not hasattr(w, "__len__") or len(w) != 2 or any(
                isinstance(part, str) or not hasattr(part, "__len__") or len(part) != 2 for part in w):
            raise ImpactInputError("walls", f"entry {j + 1} must be (point, normal), two pairs, got {w!r}")
        pt, nr = _numbers(w[0], "walls", exact), _numbers(w[1], "walls", exact)
        nn = nr[0] ** 2 + nr[1] ** 2
        if _sign(nn, exact) == 0:
            raise ImpactInputError("walls", f"entry {j + 1}: the normal is zero")
        if exact:
            length = sp.sqrt(nn)
            unit = [sp.radsimp(c / length) for c in nr]
        else:
            length = math.sqrt(nn)
            unit = [c / length for c in nr]
        W.append((pt, unit, nr))
    scale = max([1.0] + [abs(float(t)) for t in r] + [abs(float(t)) for p in P for t in p]
                + [abs(float(t)) for pt, _, _ in W for t in pt])
    contacts = []
    for i in range(nb):
        for j in range(i + 1, nb):
            d = [P[j][0] - P[i][0], P[j][1] - P[i][1]]
            rr = r[i] + r[j]
            if exact:  # certified_sign decides sqrt(d·d) − r exactly (algebraic)
                gap = sp.sqrt(d[0] ** 2 + d[1] ** 2) - rr
            else:
                gap = (d[0] ** 2 + d[1] ** 2) ** 0.5 - rr
            if _classify_gap(gap, scale, exact, gap_tolerance, f"balls {i + 1} and {j + 1}", (i, j)) == 0:
                n = [d[0] / rr, d[1] / rr]
                if exact:
                    n = [sp.radsimp(c) for c in n]
                contacts.append((f"{i + 1}-{j + 1}", [(i, (-n[0], -n[1])), (j, (n[0], n[1]))]))
    for j, (pt, unit, _) in enumerate(W):
        for b in range(nb):
            gap = unit[0] * (P[b][0] - pt[0]) + unit[1] * (P[b][1] - pt[1]) - r[b]
            if exact:
                gap = sp.radsimp(gap)
            if _classify_gap(gap, scale, exact, gap_tolerance, f"ball {b + 1} and wall {j + 1}", (b,), j) == 0:
                contacts.append((f"wall{j + 1}-{b + 1}", [(b, (unit[0], unit[1])), (None, None)]))
    return _assemble(m, V, 2, contacts, exact, lambda inv: [f"{c}{b + 1}" for b in inv for c in ("x", "y")],
                     {"builder": "balls_in_plane", "masses": m, "radii": r, "positions": P,
                      "walls": [(pt, nr) for pt, _, nr in W]})


def full_velocity(scene: Scene, reduced_velocity):
    """Every ball's velocity after the impact: the involved balls from ``reduced_velocity``
    (the scene's coordinates), the uninvolved ones unchanged.

    >>> sc = balls_on_line([1, 1, 1], [1, 1, 1], [0, 2, 7], [1, 0, 5])
    >>> full_velocity(sc, sp.Matrix([0, 1]))
    [0, 1, 5]
    """
    dim = scene.meta["dim"]
    out = list(scene.meta["all_velocities"])
    vals = list(reduced_velocity) if not hasattr(reduced_velocity, "tolist") or isinstance(
        reduced_velocity, sp.MatrixBase) else list(reduced_velocity.tolist())
    for slot, b in enumerate(scene.meta["bodies"]):
        if dim == 1:
            out[b - 1] = vals[slot]
        else:
            out[b - 1] = [vals[dim * slot + d] for d in range(dim)]
    return out
