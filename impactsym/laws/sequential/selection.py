"""The selection of sec. III-A, steps 4–5: the minimizers of ``‖v − v0‖_M`` over the feasible
set, by exact enumeration of its faces (values in ``Q(√q)``), the exact LP membership test of
a cone, and the two-surface shortcut.
"""

from __future__ import annotations

import math

import numpy as np

from ...arithmetic import certified_sign, compare_surds, rational_sqrt
from ...errors import DomainError, VerificationError
from .common import _Algebraic, _Rational, _dot, _independent, _matvec, _minner, _rank, _rref, _solve_columns

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule
sp = LazyModule("sympy", globals(), "sp")


# ---------------------------------------------------------------------------------------------
# Selection (steps 4-5)
# ---------------------------------------------------------------------------------------------
#: largest number of (outcome subset, contact subset) faces the selection enumerates
SELECTION_FACE_LIMIT = 200_000


def _select(system, outcomes, impulses, reading, raw=False):
    """Minimizers of ‖v − v0‖_M over the feasible set (see the docstring of :mod:`impactsym.laws.sequential`).

    Values are kept as ``(a, b, q)`` meaning ``a + b√q`` and compared exactly; a face's candidate
    is tested for feasibility only when its value can beat (or tie) the best found so far, and the
    outcomes themselves (feasible by construction) seed the search. The minimizers are returned as
    SymPy column vectors, or with ``raw=True`` as those ``(a, b, q)`` triples of field elements
    (the float path: no SymPy; :func:`_float_selection` rounds them).
    """
    F = system.F
    n = system.n
    O = [list(o) for o in outcomes]
    if reading == "energy" and len(O) == 1:
        # cone(o) ∩ sphere = {o}; o satisfies the momentum requirement by construction
        if raw:
            return ((O[0], [F.zero] * n, F.zero),)
        return (sp.Matrix([F.to_sympy(x) for x in O[0]]),)
    v0 = list(system.v0)
    M = system.M
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
        c = compare_surds(val, best_val, F)
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
                c = compare_surds(val, best_val, F)
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
    if raw:
        return tuple(best)
    return tuple(_vel_sympy(v, F) for v in best)


def _float_selection(vel, F):
    """The float64 array of a selected velocity ``(a, b, q)`` (``a + b√q``, :func:`_select` with
    ``raw=True``) as the float path reports it: each entry ``float(N(x, 17))`` of the exact value,
    bit for bit: :func:`~impactsym.arithmetic.literals.json_float` of a rational entry, SymPy's
    ``N`` only when a square root remains.

    >>> from flint import fmpq
    >>> _float_selection(([fmpq(1, 3), fmpq(2)], [fmpq(0), fmpq(0)], fmpq(0)), _Rational)
    array([0.33333333, 2.        ])
    """
    alpha, beta, q = _fold_surd(vel, F)
    if F is _Rational and all(b == 0 for b in beta):
        from ...arithmetic.literals import json_float

        return np.array([json_float(int(a.p), int(a.q)) for a in alpha], dtype=np.float64)
    return np.array([sp.N(x, 17) for x in _vel_sympy(vel, F)], dtype=np.float64)


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


def _same_surd(u, w, F) -> bool:
    (a1, b1, q1), (a2, b2, q2) = u, w
    return all(compare_surds((x1, y1, q1), (x2, y2, q2), F) == 0 for x1, y1, x2, y2 in zip(a1, b1, a2, b2))


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
    root = rational_sqrt(q)
    if root is not None:
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


def _select_two_surface(system, groups, exact):
    """The energy-reading selection of the two-surface closed form (see :func:`impactsym.laws.sequential.resolve._two_surface_path`):
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

    from ...errors import UndecidableSign
    from ...verify import enclose

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


def _verify_selected(system, selected, reading, outcomes=(), raw=False):
    """A rational selected velocity is checked exactly: valid, on the energy sphere (energy
    reading) and with its momentum jump in the row space of ``Hᵀ``. (Its impulse sign is part
    of the selection's own exact feasibility test.) A selected velocity that is one of the exact
    ``outcomes`` (``(v, p)`` pairs, verified with their impulse) is checked with that impulse,
    ``M(v − v0) = Hᵀp`` (a stronger statement than the row-space membership).

    Returns the impulse of each selected velocity when it is an outcome's (else ``None``).
    ``raw=True``: ``selected`` holds :func:`_select`'s ``(a, b, q)`` triples (a rational one,
    ``b = 0``, is checked; the impulses are returned as lists of field elements, no SymPy)."""
    from ...verify import verify_exact

    F = system.F
    impulses = []
    for vel in selected:
        p = None
        if raw:
            alpha, beta, _ = _fold_surd(vel, F)
            rational = F is _Rational and all(b == 0 for b in beta)
        else:
            rational = all(x.is_Rational for x in vel)
        if rational:
            exact_vel = list(alpha) if raw else [F.num(x) if F is _Rational else x for x in vel]
            if F is _Rational:
                p = next((q for v, q in outcomes if list(v) == exact_vel), None)
            if p is not None:
                system.verify("sequential (selection)", exact_vel, p, "equal" if reading == "energy" else None)
            elif F is not _Rational:
                # algebraic data: verify_exact checks on balls, which needs an impulse; M(v − v0) = Hᵀq
                # is solved exactly in the field (no solution: the momentum check fails). With H of
                # lower rank q is one of many, so its sign is not read (nor is the row-space test's)
                jump = _matvec(system.M, [F.norm(a - b) for a, b in zip(exact_vel, system.v0)], F)
                solved = _solve_columns(system.H, jump, F)
                if solved is None:
                    raise VerificationError("sequential (selection)", "momentum: M(v+ - v) is not in the row space of H^T")
                verify_exact("sequential (selection)", system.M, system.H, list(system.v0), exact_vel, solved[0],
                             energy_ratio=1 if reading == "energy" else None, impulse_nonnegative=False)
            else:
                verify_exact("sequential (selection)", system.M, system.H, list(system.v0), exact_vel, None,
                             energy_ratio=1 if reading == "energy" else None)
        impulses.append(None if p is None else list(p) if raw else sp.Matrix([F.to_sympy(x) for x in p]))
    return tuple(impulses)
