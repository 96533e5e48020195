"""The sequential resolver: input checks, the choice between the DAG search and the two-surface
closed form, the exact merge of outcomes, and the selection.
"""

from __future__ import annotations

import numpy as np

from ...arithmetic import as_fmpq, certified_sign
from ...errors import DomainError, ImpactInputError, NonTermination
from ...mechanics import check_gradients, check_mass_matrix, check_velocity
from ...numbers import check_finite_exact, is_exact, to_exact
from .common import (AUTO_ITERATE_MAX_COUNT, DEFAULT_MAX_REFLECTIONS, MAX_COORDINATES, MAX_STATE_BITS, READINGS,
                     TWO_SURFACE_PATHS,
                     _Rational, _rank)
from .collapse import _CollapseDetector, _verified_collapse
from .float_search import INELASTIC_FALLBACK_BUDGET, _FallbackBudget, _float_search
from .results import InfiniteOrder, Outcome, SequentialResolution
from .search import (_ExactSystem, _Reflector, _aggregate, _cap_error, _diff_key, _explore, _explore_rational,
                     _merge_exact_keys, _state_bits_error, _verified_replay)
from .selection import _select, _select_two_surface, _verify_selected
from .independence import ProductGraph, combine, components, length_distributions
from .sparse import read_floats, read_rational
from .witness import valid_velocity_witness, witness_of_rows

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule, sympy_instance
sp = LazyModule("sympy", globals(), "sp")


#: split the exact rational search into independent groups of contacts (:mod:`.independence`);
#: ``False`` searches the whole system as one DAG (the tests compare the two)
DECOMPOSE_INDEPENDENT = True


def _dense_fmpq(M, H, v0):
    """Dense ``fmpq`` rows of float ``M``, ``H`` and the list of ``v0``: their exact binary values."""
    return ([[as_fmpq(x) for x in row] for row in M], [[as_fmpq(x) for x in row] for row in H],
            [as_fmpq(x) for x in v0])


def _coordinates(mass_matrix):
    """The number of rows of ``mass_matrix`` read without converting it (``None`` if unknown)."""
    if isinstance(mass_matrix, str):
        return mass_matrix.count(";") + 1
    shape = getattr(mass_matrix, "shape", None)
    if shape is not None and len(shape) >= 1:
        return int(shape[0])
    if isinstance(mass_matrix, (list, tuple)):
        return len(mass_matrix)
    return None


def _restitution_entries(restitution):
    """The entries of ``restitution`` as given: one scalar, or a sequence (``"a,b"`` text too)."""
    if isinstance(restitution, str):
        parts = [t.strip() for t in restitution.split(",")]
        return parts[0] if len(parts) == 1 else parts, len(parts) > 1
    if sympy_instance(restitution, "MatrixBase"):
        return list(restitution), True
    if isinstance(restitution, np.ndarray):
        if restitution.ndim == 0:
            return restitution.item(), False
        return list(restitution.reshape(-1)) if restitution.ndim == 1 else None, True
    if isinstance(restitution, (list, tuple)):
        return list(restitution), True
    return restitution, False


def check_restitutions(restitution, contacts: int, *, exact: bool) -> tuple:
    """One restitution per contact, checked: ``0 ≤ e_i ≤ 1``, finite, real.

    ``restitution`` is a scalar (every contact) or one entry per contact (row of ``H``).
    Exact mode returns exact SymPy numbers (a float entry: its exact binary value); float mode
    returns Python floats.

    >>> check_restitutions("1/2", 2, exact=True), check_restitutions([0.5, 1], 2, exact=False)
    ((1/2, 1/2), (0.5, 1.0))
    >>> check_restitutions([1, 2], 2, exact=True)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: restitution: entry 2 must lie in [0, 1], got 2
    """
    entries, seq = _restitution_entries(restitution)
    if entries is None:
        raise ImpactInputError("restitution", "must be a number or a 1-D sequence of numbers")
    if seq and len(entries) != contacts:
        raise ImpactInputError("restitution", f"has {len(entries)} entries; give one number per contact "
                                              f"(k={contacts} rows of gradients) or a single number")
    values = entries if seq else [entries] * contacts
    if not seq and contacts > 1:  # one number for every contact: checked once
        return check_restitutions(entries, 1, exact=exact) * contacts
    out = []
    for idx, x in enumerate(values, 1):
        if isinstance(x, bool) or x is None:
            raise ImpactInputError("restitution", f"entry {idx} must be a number, got {x!r}")
        if exact:
            if isinstance(x, (float, np.floating)) and not np.isfinite(x):
                raise ImpactInputError("restitution", f"entry {idx} must be a finite real number, got {x}")
            val = check_finite_exact(to_exact(x, "restitution"), "restitution")
            if certified_sign(val) < 0 or certified_sign(val - 1) > 0:
                raise ImpactInputError("restitution", f"entry {idx} must lie in [0, 1], got {val}")
        else:
            try:
                val = float(x)
            except (TypeError, ValueError):
                raise ImpactInputError("restitution", f"entry {idx} must be a number, got {x!r}") from None
            if not np.isfinite(val):
                raise ImpactInputError("restitution", f"entry {idx} must be a finite real number, got {val}")
            if not 0.0 <= val <= 1.0:
                raise ImpactInputError("restitution", f"entry {idx} must lie in [0, 1], got {val!r}")
        out.append(val)
    return tuple(out)


def _check_inputs(mass_matrix, gradients, velocity, exact, restitution=1):
    if exact is None:
        exact = is_exact(mass_matrix, gradients, velocity, restitution)
    M = check_mass_matrix(mass_matrix, exact=exact)
    n = M.shape[0]
    H = check_gradients(gradients, n, exact=exact)
    v = check_velocity(velocity, n, exact=exact)
    return exact, M, H, v


def _group_outcomes(root_table, merged) -> dict:
    """Aggregate the orderings' statistics per distinct outcome: ``{canonical key: [orderings,
    fewest reflections, most reflections, representative ordering]}``, the representative the
    shortest, then lexicographically first, ordering."""
    groups: dict = {}
    for key in root_table:
        canon = merged[key]
        cnt, lo, hi, rep = root_table[key]
        if canon not in groups:
            groups[canon] = [cnt, lo, hi, rep]
        else:
            a = groups[canon]
            a[0] += cnt
            a[1] = min(a[1], lo)
            a[2] = max(a[2], hi)
            if (len(rep), rep) < (len(a[3]), a[3]):
                a[3] = rep
    return groups


def resolve_sequential(mass_matrix, gradients, velocity, *, reading: str | None = None,
                       max_reflections: int = DEFAULT_MAX_REFLECTIONS, exact: bool | None = None,
                       select: bool = True, two_surface: str = "auto",
                       restitution=1) -> SequentialResolution:
    """Every impact ordering of a corner impact, its outcomes, and the selected solution.

    Parameters
    ----------
    mass_matrix : matrix-like (n×n), symmetric positive definite
    gradients : matrix-like (k×n), gradient rows ``H_i`` of the closed contacts, any k ≥ 1
    velocity : vector-like (n,), pre-impact velocity ``v0``
    reading : ``"energy"``, ``"cone"`` or ``None`` (default)
        The feasible set of the selection: conic hull of the outcomes with the momentum-cone
        requirement, intersected with the energy sphere (``"energy"``) or not (``"cone"``).
        ``None``: ``"energy"`` for the elastic law (every ``e_i = 1``), ``"cone"`` otherwise.
        The energy reading is refused (``DomainError``) when some ``e_i < 1`` and ``select``
        is true: the outcomes no longer share the energy sphere (``docs/sequential_restitution.md``).
    max_reflections : int
        Cap on the reflections of any one ordering; exceeding it raises ``NonTermination``.
    exact : bool, optional
        Force the exact (``True``) or float (``False``) path; default: exact iff every input is.
    select : bool
        Compute the selection (steps 4–5). ``False`` skips it (``selected`` is empty).
    two_surface : ``"auto"`` (default), ``"closed-form"`` or ``"iterate"``
        With exactly two linearly independent rows, ``"closed-form"`` takes every branch from
        :func:`impactsym.laws.two_surface.resolve_two_surfaces` in O(1), whatever the count (the
        reflection cap does not apply: nothing is iterated); ``"iterate"`` forces the search,
        and is refused up front (``NonTermination``) when the certified count of a branch
        exceeds ``max_reflections``. ``"auto"`` chooses by the count: exact rational data whose
        paper bound ``N = ⌈π/β⌉`` (the longest branch of any velocity) is certainly at most
        ``AUTO_ITERATE_MAX_COUNT`` are iterated (a few exact reflections cost less than the
        closed form's certified evaluation; :func:`impactsym.laws.two_surface.bound_at_most`
        decides it in rational arithmetic), everything else takes the closed form. Both paths
        give the same exact outcomes; the iteration also reports ``bound``. With the closed
        form the energy reading selects the outcome(s) with the largest ``⟨o, v0⟩_M`` (exact, or certified Arb comparison of
        certified outcomes; see :func:`_two_surface_path`); the cone reading of certified
        outcomes is skipped in exact mode (``selected`` empty, ``selection_note`` says why) and
        refused in float mode (``DomainError``): a float run never succeeds with an empty
        selection. With some ``e_i < 1`` the closed form (elastic) does not apply and two
        contacts are always iterated.
    restitution : number or sequence of numbers
        Newton restitution ``e_i ∈ [0, 1]`` of each contact (row of ``H``), or one number for
        all; each single impact on contact ``i`` applies ``G_{H_i}(e_i) = I − (1+e_i)
        M⁻¹H_iᵀH_i/(H_i M⁻¹H_iᵀ)``. ``1`` (default) is the paper's elastic law, unchanged. With
        ``e_i < 1`` an alternation of two contacts may never end (inelastic collapse): it is
        decided exactly and its limit returned (``Outcome.collapse``, ``InfiniteOrder``), see
        :mod:`impactsym.laws.sequential.collapse`; a collapse that involves more contacts is
        refused (``NonTermination``).

    Returns
    -------
    SequentialResolution

    Raises
    ------
    ImpactInputError
        Bad shapes, a mass matrix that is not SPD, a zero gradient row, a bad ``reading`` or cap,
        a restitution outside ``[0, 1]``, not finite, or with the wrong number of entries,
        more than ``MAX_COORDINATES`` coordinates (refused before any exact work).
    DomainError
        No non-zero velocity is valid for all closed contacts (no elastic outcome exists); the
        energy reading requested with restitution < 1.
    NonTermination
        An ordering exceeds ``max_reflections`` or provably never ends (elastic: a velocity
        recurs; restitution < 1: a collapse that is not a two-contact alternation with a
        certified limit), or the exact states of the search exceed ``MAX_STATE_BITS``.
    VerificationError
        An exact outcome failed its check before return (a bug; never returned).

    Examples
    --------
    ``M = diag(11/10, 1)``, both contacts approaching: two outcomes (sec. III-B.3). The two
    orderings of length 4 apply a kinetic rotation and its inverse, so both outcomes are equally
    near ``v0``: the energy reading selects both (a tie); the plain cone selects ``0``.

    >>> r = resolve_sequential("11/10,0;0,1", "1,0;-1,1", "-1,-2")
    >>> [(o.order, list(o.velocity)) for o in r.outcomes]
    [((0, 1, 0, 1), [173/147, 278/147]), ((1, 0, 1, 0), [359/441, 922/441])]
    >>> r.selected == tuple(o.velocity for o in r.outcomes)
    True
    >>> list(resolve_sequential("11/10,0;0,1", "1,0;-1,1", "-1,-2", reading="cone").selected[0])
    [0, 0]

    Float mode counts its exact fallbacks (here the grazing contact 2–3 of the cradle):

    >>> r = resolve_sequential(np.eye(3), [[-1.0, 1, 0], [0, -1, 1]], [1.0, 0, 0], two_surface="iterate")
    >>> r.outcomes[0].velocity, r.exact, r.exact_fallbacks > 0
    (array([0., 0., 1.]), False, True)

    Restitution ``1/2`` on every contact of the three-ball cradle: the impacts 1-2, 2-3, 1-2
    end; below ``7 − 4√3`` the alternation never ends and its limit is the plastic outcome:

    >>> r = resolve_sequential("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", restitution="1/2")
    >>> [(o.order, list(o.velocity)) for o in r.outcomes], r.reading
    ([((0, 1, 0), [13/64, 15/64, 9/16])], 'cone')
    >>> o = resolve_sequential("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", restitution="1/20").outcomes[0]
    >>> o.collapse, o.order, o.reflections, list(o.velocity)
    (True, InfiniteOrder(prefix=(), cycle=(0, 1)), None, [1/3, 1/3, 1/3])

    References
    ----------
    Seghete & Murphey, sec. III-A (algorithm steps 1–5), sec. III-B (branching), eq. 4.
    """
    if reading is not None and reading not in READINGS:
        raise ImpactInputError("reading", f"must be one of {', '.join(READINGS)}, got {reading!r}")
    if isinstance(max_reflections, bool) or not isinstance(max_reflections, (int, np.integer)) or max_reflections < 1:
        raise ImpactInputError("max_reflections", f"must be a positive integer, got {max_reflections!r}")
    cap = int(max_reflections)
    if two_surface not in TWO_SURFACE_PATHS:
        raise ImpactInputError("two_surface", f"must be one of {', '.join(TWO_SURFACE_PATHS)}, got {two_surface!r}")
    size = _coordinates(mass_matrix)
    if size is not None and size > MAX_COORDINATES:
        raise ImpactInputError(
            "mass_matrix", f"has {size} coordinates, more than the sequential law's limit MAX_COORDINATES="
            f"{MAX_COORDINATES}")
    # exact rational input is read once into sparse fmpq data and checked there (never again)
    data = fdata = None
    if exact is not False and is_exact(restitution):
        data = read_rational(mass_matrix, gradients, velocity)
    if data is not None:
        exact = True
        M = H = v0 = None  # dense SymPy forms are made only where a path needs them
        E = check_restitutions(restitution, data.k, exact=True)
    else:
        exact, M, H, v0 = _check_inputs(mass_matrix, gradients, velocity, exact, restitution)
        E = check_restitutions(restitution, H.shape[0], exact=exact)
    elastic = all(x == 1 for x in E)
    if reading is None:
        reading = "energy" if elastic else "cone"
    elif reading == "energy" and not elastic and select:
        raise DomainError(
            "reading: the energy reading intersects the feasible set with the energy sphere ||v||_M = "
            "||v0||_M, which only elastic impacts keep (restitution 1 on every contact); with restitution "
            "< 1 use reading='cone' or select=False")
    if data is not None:
        null = data.null_vector()
        witness = (sp.Matrix([sp.Rational(int(x.p), int(x.q)) for x in null]) if null is not None
                   else valid_velocity_witness(data.to_sympy()[1]))
    elif exact:
        Mx, Hx, vx = M, H, v0
        witness = valid_velocity_witness(Hx)
    else:
        # float input: the floats' exact binary values, in fmpq (no SymPy); the witness is a tuple
        # of them, decided exactly as valid_velocity_witness decides it
        # (sparse when M passes the exact check, as rational input is read; dense rows otherwise)
        Mx = Hx = vx = None
        fdata = read_floats(M, H, v0)
        null = fdata.null_vector() if fdata is not None else None
        if null is not None:
            witness = tuple(null)
        else:
            witness = witness_of_rows([[as_fmpq(x) for x in row] for row in H], H.shape[1])
            witness = None if witness is None else tuple(witness)
    if witness is None:
        if not elastic:
            raise DomainError("gradients: no non-zero velocity v satisfies H v >= 0 (only v = 0 would be valid, "
                              "which the sequential law with restitution < 1 does not resolve)")
        raise DomainError("gradients: no non-zero velocity v satisfies H v >= 0 "
                          "(the closed contacts admit no elastic exit velocity)")
    if not elastic:
        if not exact:  # float input: every value is its exact binary value (fmpq)
            Eq = [as_fmpq(x) for x in E]
            system = (_ExactSystem.from_sparse(fdata, Eq) if fdata is not None
                      else _ExactSystem.from_rationals(*_dense_fmpq(M, H, v0), Eq))
            return _inelastic(M, H, v0, system, exact, cap, reading, select, witness, E)
        Ex = list(E)
        if data is not None and all(x.is_Rational for x in Ex):
            system = _ExactSystem.from_sparse(data, Ex)
        else:  # an irrational restitution: the algebraic backend
            if data is not None:
                Mx, Hx, vx = data.to_sympy()
            system = _ExactSystem(Mx, Hx, vx, Ex)
        return _inelastic(M, H, v0, system, exact, cap, reading, select, witness, E)
    system = (_ExactSystem.from_sparse(data) if data is not None else _ExactSystem(Mx, Hx, vx) if exact
              else _ExactSystem.from_sparse(fdata) if fdata is not None
              else _ExactSystem.from_rationals(*_dense_fmpq(M, H, v0)))
    F = system.F
    two_bound = None
    short = False
    if system.k == 2 and (data.rank() if data is not None else _rank(system.H, F)) == 2:
        from ..two_surface import _branch_counts_prepared, _certified_bound, _Data, bound_at_most, branch_counts

        path, short = two_surface, False
        if path == "auto":
            # iterate when the paper's bound N (the longest branch of any velocity) is certainly
            # small: then a few exact reflections cost less than the closed form's Arb work
            path = "closed-form"
            if exact and F is _Rational and AUTO_ITERATE_MAX_COUNT <= cap and bound_at_most(
                    system.s[0], system.s[1], _gram_entry(system, 0, 1), AUTO_ITERATE_MAX_COUNT):
                path, short = "iterate", True
        if path == "closed-form":
            if data is not None:
                return _two_surface_path(None, None, None, system, exact, reading, select, witness,
                                         prepared=_prepared_two_surface(system))
            return _two_surface_path(M, H, v0, system, exact, reading, select, witness)
        if not short:
            # iterating: refuse up front when a branch needs more than the cap (its exact states
            # grow linearly, so reaching the cap would cost memory quadratic in it)
            if data is not None:
                counts = _branch_counts_prepared(_prepared_two_surface(system))
            elif exact:
                counts = branch_counts(Mx, Hx, vx)
            elif fdata is not None:  # float input: the counts of the floats' exact binary values
                counts = _branch_counts_prepared(_prepared_two_surface(system))
            else:
                counts = branch_counts(*_dense_fmpq(M, H, v0))
            if counts and max(counts.values()) > cap:
                raise NonTermination(
                    f"max_reflections: the ordering starting with surface {max(counts, key=counts.get)} needs "
                    f"{max(counts.values())} reflections (certified count of the two-surface closed form), more "
                    f"than the cap max_reflections={cap}; raise the cap or use the two-surface closed form")
        if exact and F is _Rational:  # the paper's bound, as the closed form reports it
            g01 = _gram_entry(system, 0, 1)
            two_bound = _certified_bound(_Data(system.s[0], system.s[1], g01, F.zero, F.zero), {})
    if exact:
        # a state is (v, w = H v); w is updated with the Gram matrix H M^-1 H^T, not recomputed
        if F is _Rational:
            def sign_of(state, i, node):
                wi = state[1][i]
                return (wi > 0) - (wi < 0), wi
        else:
            def sign_of(state, i, node):
                wi = state[1][i]
                return F.sign(wi), wi

        if F is _Rational:
            def key_of(state):
                return tuple([(x.p, x.q) for x in state[0]])
        else:
            def key_of(state):
                return state[0]
        if F is _Rational:
            comps = components(system) if DECOMPOSE_INDEPENDENT else []
            if len(comps) > 1:  # independent groups of contacts: searched apart, counts combined
                g, tests, root_table = _decomposed_search(system, comps, cap)
            else:
                g, tests = _explore_rational(system, cap)
                root_table = _aggregate(g, _diff_key)
        else:
            w0 = tuple(system.w(system.v0, i) for i in range(system.k))
            g, tests = _explore(sign_of, _Reflector(system), (system.v0, w0), cap, {}, key_of)
            g.vel = [state[0] for state in g.vel]
            root_table = _aggregate(g, lambda v: v)
        fallbacks = 0
        keys = list(root_table)
        merged = _merge_exact_keys(keys, F)
    else:
        g, tests, fallbacks, root_table, merged, float_sys = _float_search(M, H, v0, system, cap)
    approaching = tuple(F.sign(system.w(system.v0, i)) < 0 for i in range(system.k))
    # Merge outcome keys that are the same velocity (exact comparison), aggregate stats.
    groups = _group_outcomes(root_table, merged)
    items = sorted(groups.items(), key=lambda kv: (len(kv[1][3]), kv[1][3]))
    g.outcome_index = {}
    for idx, (canon, _) in enumerate(items):
        for key, c in merged.items():
            if c == canon:
                g.outcome_index[key] = idx
    outcomes = []
    exact_outcomes = []
    for canon, (cnt, lo, hi, rep) in items:
        v_ex, p_ex = _verified_replay(system, rep)
        exact_outcomes.append((v_ex, p_ex))
        if exact:
            vel = sp.Matrix([F.to_sympy(x) for x in v_ex])
            imp = sp.Matrix([F.to_sympy(x) for x in p_ex])
        else:
            vel = np.array(canon, dtype=float)
            imp = float_sys.impulse(rep)
        outcomes.append(Outcome(rep, len(rep), vel, imp, cnt, lo, hi))
    total = sum(o.orderings for o in outcomes)
    longest = max(o.reflections_max for o in outcomes)
    if longest > cap:
        raise _cap_error(cap)
    selected: tuple | None = ()
    selected_raw = None
    selected_impulses: tuple = ()
    if select:
        if short and reading == "energy":
            # two independent surfaces: the feasible set is an arc between the two outcomes, and
            # <v, v0>_M on it is largest at an end point (see _two_surface_path): compare exactly
            selected = _select_arc_end(system, [v for v, _ in exact_outcomes])
        else:
            selected = _select(system, [v for v, _ in exact_outcomes], [p for _, p in exact_outcomes], reading,
                               raw=not exact)
        selected_impulses = _verify_selected(system, selected, reading, exact_outcomes, raw=not exact)
        if not exact:  # float mode: SymPy vectors only when read (SequentialResolution.selected)
            selected_raw, selected = (F, selected), None
    res = SequentialResolution(tuple(outcomes), selected, reading, total, longest, len(g.vel), tests,
                               fallbacks, exact, F.name if exact else "float", approaching, witness, _graph=g,
                               restitution=tuple(sp.Integer(1) if exact else 1.0 for _ in range(system.k)))
    res._selected_raw = selected_raw
    if data is not None and data.rank() == data.k:
        # H has full row rank: p of M(v+ - v0) = H^T p is unique, the one verified with the outcome
        res.selected_impulses = selected_impulses
    res.bound = two_bound
    return res


def _decomposed_search(system, comps, cap):
    """The search of each independent group of contacts alone (:mod:`.independence`), and the
    table of the whole system's outcomes combined from theirs: ``(product graph, sign tests,
    {outcome key: [orderings, shortest, longest, representative]})``."""
    graphs, parts = [], []
    tests = system.k  # the root's signs, decided once (components() reads them)
    for comp in comps:
        gc, t = _explore_rational(system, cap, allowed=set(comp))
        tests += t - len(comp)
        dist = length_distributions(gc, _diff_key)
        reps = _aggregate(gc, _diff_key)
        parts.append({key: (dist[key], reps[key][3]) for key in dist})
        graphs.append(gc)
    return ProductGraph(graphs), tests, combine(parts)


def _select_arc_end(system, outcomes):
    """The energy-reading selection of two independent surfaces from exact rational outcomes:
    the outcome(s) with the largest ``⟨o, v0⟩_M`` (both on a tie), the rule of
    :func:`_two_surface_path`."""
    F = system.F
    v0 = system.v0
    if system.sparse is not None:
        Mv0 = system.sparse.mul_M({j: x for j, x in enumerate(v0) if x != 0})
    else:
        Mv0 = {i: sum((m * x for m, x in zip(row, v0)), F.zero) for i, row in enumerate(system.M)}
    vals = [sum((m * o[j] for j, m in Mv0.items()), F.zero) for o in outcomes]
    best = max(vals)
    return tuple(sp.Matrix([F.to_sympy(x) for x in o]) for o, val in zip(outcomes, vals) if val == best)


def _gram_entry(system, i, j):
    """``H_i M⁻¹ H_jᵀ`` from the sparse Gram column ``j``."""
    return next((a for r, a in system.gcols[j] if r == i), system.F.zero)


def _prepared_two_surface(system):
    """The checked rational data of two contacts as the ``fmpq_mat`` tuple the two-surface law
    takes (:func:`impactsym.laws.two_surface._resolve`): nothing is read or checked again."""
    from .sparse import two_surface_data

    return two_surface_data(system.sparse, system.wcols)


def _inelastic_cap_error(cap, k):
    def make(path):
        tail = path[-min(len(path), 64):]
        involved = sorted({i + 1 for i in tail})
        return NonTermination(
            f"max_reflections: an ordering exceeded the cap max_reflections={cap} with restitution < 1; its last "
            f"{len(tail)} impacts involve contacts {involved}. This is either a two-contact inelastic collapse whose "
            "other contacts were not yet certified within the cap (raise the cap), or a collapse involving "
            f"{'more than two contacts' if len(involved) > 2 else 'these contacts'}, which has no closed form here "
            "(not decided; refused rather than truncated)")
    return make


def _leaf_of(g, order):
    node = g.root
    for i in order:
        node = next(child for j, child in g.children[node] if j == i)
    return node


class _BoundedReflector(_Reflector):
    """The rational reflector of the restitution search, keeping the total size of the exact
    states it makes below ``MAX_STATE_BITS`` (as the elastic rational search does)."""

    def __init__(self, system):
        super().__init__(system)
        self.bits = 0
        self.states = 0

    def __call__(self, state, i, wi):
        out = super().__call__(state, i, wi)
        self.states += 1
        self.bits += sum(x.p.bit_length() + x.q.bit_length() for x in out[0][0])
        if self.bits > MAX_STATE_BITS:
            raise _state_bits_error(self.states)
        return out


def _is_collapse_key(key) -> bool:
    return isinstance(key, tuple) and len(key) == 2 and isinstance(key[0], str) and key[0] == "collapse"


def _inelastic(M, H, v0, system, exact, cap, reading, select, witness, E):
    """The DAG search with restitution < 1: the impacts ``G_{H_i}(e_i)``, collapse leaves for
    two-contact alternations that never end (:mod:`.collapse`), outcomes verified exactly."""
    F = system.F
    k = system.k
    cap_error = _inelastic_cap_error(cap, k)

    def state_of(v):
        return (v, tuple(system.w(v, i) for i in range(k)))

    exact_search = exact
    fallbacks = 0
    if not exact:
        try:
            g, tests, fallbacks, root_table, merged, float_sys = _float_search(
                M, H, v0, system, cap, restitution=E, collapse=True, cap_error=cap_error)
        except _FallbackBudget:
            # every decision is being re-made exactly: search exactly on the floats' binary values
            exact_search = True
            fallbacks = INELASTIC_FALLBACK_BUDGET
    if exact_search:
        if F is _Rational:
            def sign_of(state, i, node):
                wi = state[1][i]
                return (wi > 0) - (wi < 0), wi

            def key_of(state):
                return tuple([(x.p, x.q) for x in state[0]])
        else:
            def sign_of(state, i, node):
                wi = state[1][i]
                return F.sign(wi), wi

            def key_of(state):
                return state[0]
        holder: dict = {}
        detector = _CollapseDetector(system, lambda node: holder["g"].vel[node][0], state_of, lambda v: v)
        reflector = _Reflector(system) if F is not _Rational else _BoundedReflector(system)
        g, tests = _explore(sign_of, reflector, state_of(system.v0), cap, holder, key_of,
                            collapse=detector, cap_error=cap_error)
        g.vel = [state[0] for state in g.vel]
        root_table = _aggregate(g, lambda v: v)
        plain = [key for key in root_table if not _is_collapse_key(key)]
        merged = _merge_exact_keys(plain, F)
    ckeys = [key for key in root_table if _is_collapse_key(key)]
    cmerged = _merge_exact_keys([key[1] for key in ckeys], F)
    for key in ckeys:
        merged[key] = ("collapse", cmerged[key[1]])
    approaching = tuple(F.sign(system.w(system.v0, i)) < 0 for i in range(k))
    groups = _group_outcomes(root_table, merged)
    items = sorted(groups.items(), key=lambda kv: (_is_collapse_key(kv[0]), len(kv[1][3]), kv[1][3]))
    g.outcome_index = {}
    for idx, (canon, _) in enumerate(items):
        for key, c in merged.items():
            if c == canon:
                g.outcome_index[key] = idx
    outcomes = []
    exact_outcomes = []
    for canon, (cnt, lo, hi, rep) in items:
        collapse = _is_collapse_key(canon)
        if collapse:
            cycle = g.collapse[_leaf_of(g, rep)][0]
            v_ex, p_ex = _verified_collapse(system, rep[:-1], cycle)
        else:
            v_ex, p_ex = _verified_replay(system, rep)
        exact_outcomes.append((v_ex, p_ex))
        if exact:
            vel = sp.Matrix([F.to_sympy(x) for x in v_ex])
            imp = sp.Matrix([F.to_sympy(x) for x in p_ex])
        elif collapse or exact_search:  # float mode: the rounded exact outcome
            vel = np.array([float(F.to_sympy(x)) for x in v_ex])
            imp = np.array([float(F.to_sympy(x)) for x in p_ex])
        else:
            vel = np.array(canon, dtype=float)
            imp = float_sys.impulse(rep)
        if collapse:
            outcomes.append(Outcome(InfiniteOrder(tuple(rep[:-1]), cycle), None, vel, imp, cnt, None, None,
                                    collapse=True))
        else:
            outcomes.append(Outcome(rep, len(rep), vel, imp, cnt, lo, hi))
    total = sum(o.orderings for o in outcomes)
    longest = max((o.reflections_max for o in outcomes if not o.collapse), default=0)
    selected: tuple | None = ()
    selected_raw = None
    if select:
        selected = _select(system, [v for v, _ in exact_outcomes], [p for _, p in exact_outcomes], reading,
                           raw=not exact)
        _verify_selected(system, selected, reading, raw=not exact)
        if not exact:
            selected_raw, selected = (F, selected), None
    res = SequentialResolution(tuple(outcomes), selected, reading, total, longest, len(g.vel), tests,
                               fallbacks, exact, F.name if exact else "float", approaching, witness, _graph=g,
                               restitution=tuple(E), collapse=any(o.collapse for o in outcomes))
    res._selected_raw = selected_raw
    return res


def _two_surface_path(M, H, v0, system, exact, reading, select, witness, prepared=None):
    """Outcomes of two independent surfaces from the O(1) closed form, merged exactly.

    The selection (energy reading) needs no face enumeration: the feasible set lies on the arc
    of the energy sphere between the two outcomes ``o_1``, ``o_2`` (it is the whole arc when
    ``v0 ∈ span(M⁻¹Hᵀ)``, only its end points otherwise), ``v0``'s direction is not on the arc
    (``v0`` is invalid, the arc is valid), and ``⟨v, v0⟩_M`` restricted to such an arc is largest
    at an end point. So the selection is the outcome(s) with the largest ``⟨o_i, v0⟩_M``: an exact
    comparison, or a certified one (Arb) for certified outcomes. When both branches have the same
    even count the two values are equal exactly (``o_2 = R⁻¹v0`` for ``o_1 = Rv0``, ``R`` a
    kinetic isometry), and both are selected."""
    from ..two_surface import _resolve, resolve_two_surfaces

    F = system.F
    ts = resolve_two_surfaces(M, H, v0) if prepared is None else _resolve(True, None, None, None, system.n,
                                                                          prepared=prepared)
    groups: list = []  # [velocity, [orders], impulse, exact, two-surface outcome]
    for o in ts.outcomes:
        # (reflections, first surface, order): a closed-form order may be too long for len()
        first = -1 if o.first is None else o.first
        order = (o.reflections, first, tuple(o.order) if o.reflections <= 10_000 else o.order)
        for grp in groups:
            if o.exact and grp[3] and all(certified_sign(a - b) == 0 for a, b in zip(o.velocity, grp[0])):
                grp[1].append(order)
                break
            if not exact and not o.exact and grp[3] is False and np.array_equal(o.velocity, grp[0]):
                grp[1].append(order)
                break
        else:
            groups.append([o.velocity, [order], o.impulse, o.exact, o])
    outcomes = []
    orders = []
    for grp in groups:
        grp[1] = sorted(grp[1], key=lambda t: t[:2])  # the iteration's order: shortest, then first surface
    groups.sort(key=lambda grp: grp[1][0][:2])
    for idx, (vel, ords, imp, _, _) in enumerate(groups):
        lens = [t[0] for t in ords]
        outcomes.append(Outcome(ords[0][2], lens[0], vel, imp, len(ords), min(lens), max(lens)))
        orders.extend((t[2], idx) for t in ords)
    selected: tuple | None = ()
    selected_raw = None
    note = None
    all_exact = all(g[3] for g in groups)
    short = max(o.reflections for o in outcomes) <= 10_000
    if select and reading == "energy" and (exact or not short):
        selected = _select_two_surface(system, groups, exact)
    elif select and (all_exact or not exact):
        if exact:
            exact_outs = [tuple(F.num(x) for x in o.velocity) for o in outcomes]
        elif short:  # float input: replay short orderings exactly (an exact selection)
            exact_outs = [system.replay(o.order)[0] for o in outcomes]
        else:
            raise DomainError(
                f"select: the {reading} reading needs the exact outcomes, but the orderings take "
                f"{max(o.reflections for o in outcomes)} reflections (more than 10000 are not replayed "
                "exactly); use reading='energy' or select=False")
        selected = _select(system, exact_outs, None, reading, raw=not exact)
        if not exact:
            selected_raw, selected = (F, selected), None
    elif select:
        note = (f"the {reading} reading needs exact outcomes; these are certified digits "
                "(use reading='energy')")
    approaching = tuple(F.sign(system.w(system.v0, i)) < 0 for i in range(system.k))
    res = SequentialResolution(tuple(outcomes), selected, reading, len(orders),
                               max(o.reflections_max for o in outcomes), 0, 2, 0, exact and all_exact,
                               (F.name if exact else "float"), approaching, witness,
                               method="two-surface closed form", bound=ts.bound, _orders=orders)
    res.selection_note = note
    res._selected_raw = selected_raw
    res.restitution = tuple(sp.Integer(1) if exact else 1.0 for _ in range(system.k))
    if exact and selected:
        # two independent rows: p of M(v+ - v0) = H^T p is unique; a selected outcome's impulse is
        # the one the two-surface law verified with it (exact outcomes only)
        imps = tuple(next((g[2] for g in groups if g[0] is s and g[3]), None) for s in selected)
        if all(p is not None for p in imps):
            res.selected_impulses = imps
    return res
