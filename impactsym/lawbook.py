"""Every law behind one interface: :class:`Law`, the table :data:`LAWS`, :func:`resolve` and
:func:`resolve_all`.

In the spirit of ``sympy.physics.mechanics``' ``MethodBase``, a law is an object with a name, the
options it takes, how it reads the restitution, a test of whether it applies to a system
(:meth:`Law.why_not`), and :meth:`Law.resolve`, which takes a
:class:`~impactsym.resolution.System` and returns one :class:`~impactsym.resolution.Resolution`.
The laws themselves live in :mod:`impactsym.laws`; the classes here only translate their results
into the one outcome type, so that every law is compared, printed and exported alike.

=================  ==========================================  ======================  ===========
law                source                                      restitution             outcomes
=================  ==========================================  ======================  ===========
``sequential``     Seghete & Murphey sec. III (``G_u(e)``)     per contact             gap-dependent
``two-surface``    Seghete & Murphey sec. III-B, III-C          elastic only            gap-dependent
``newton``         Acary & Taha sec. 2.2 (Newton/Moreau LCP)    one                     unique
``poisson``        Acary & Taha eq. 11                          per contact             unique
``energetic``      Acary & Taha eq. 12                          one (global)            unique
``han-gilmore``    Acary & Taha eqs. 15–16                      one                     set-valued
``impulse-ratio``  Acary & Taha eq. 38                          one (global)            unique
=================  ==========================================  ======================  ===========

The integrated laws ``hertz``, ``linear``, ``power``, ``hunt-crossley`` and ``lzb`` (Acary & Taha
sec. 3.4; Liu, Zhao & Brogliato) live in :mod:`impactsym.lawbook_compliant`, which registers them
here on import, and lets ``impulse-ratio`` and ``energetic`` take ``ratios="from-hertz"`` etc.

Examples
--------
>>> from impactsym.resolution import System
>>> chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
>>> r = resolve("sequential", chain)
>>> r.uniqueness, [list(o.velocity) for o in r.outcomes]
('unique', [[0, 0, 1]])
>>> {name: (res.uniqueness, res.velocity) for name, res in resolve_all(chain, laws=["newton", "han-gilmore"]).items()}
{'newton': ('unique', Matrix([
[-1/3],
[ 2/3],
[ 2/3]])), 'han-gilmore': ('set-valued', None)}
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numpy as np

from .errors import DomainError, ImpactInputError, NonTermination
from .resolution import Outcome, RationalMatrix, Resolution, System, is_mpmath, is_sympy

# SymPy and mpmath are imported where an exact or certified value is handled: the laws' table, their
# options and a float law's answer (the compliant laws) need neither.

__all__ = ["Law", "LAWS", "get_law", "resolve", "resolve_all", "law_names"]


def _violations(items) -> list:
    return [v.as_dict() if hasattr(v, "as_dict") else dict(v) for v in items]


def _jsonable(value):
    """Law-specific details in JSON form (exact strings; numbers with a float twin elsewhere)."""
    if is_sympy(value, "MatrixBase"):
        return [str(x) for x in value]
    if isinstance(value, np.ndarray):
        return [float(x) for x in value.reshape(-1)]
    if is_sympy(value):
        return str(value)
    if isinstance(value, (np.floating, float)):
        return float(value)
    if is_mpmath(value):
        import mpmath

        return mpmath.nstr(value, 17)
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value


def _details(d: dict) -> dict:
    """Law-specific details for JSON: numbers and vectors as exact strings with ``_float`` twins
    (CONVENTIONS), everything else as is (made JSON-ready)."""
    from .resolution import number_json, vector_json

    out: dict = {}
    for key, val in d.items():
        if is_sympy(val, "MatrixBase") or isinstance(val, np.ndarray) or (
                isinstance(val, (list, tuple)) and val and all((is_sympy(x) or isinstance(x, (float, int, np.floating)))
                                                               and not isinstance(x, bool) for x in val)):
            exact = isinstance(val, (list, tuple)) and all(is_sympy(x) or isinstance(x, int) for x in val)
            out.update(vector_json(key, _sympy_column(val) if exact else val))
        elif is_sympy(val) or isinstance(val, (np.floating, float)):
            out.update(number_json(key, val))
        else:
            out[key] = _jsonable(val)
    return out


def _sympy_column(values):
    import sympy as sp

    return sp.Matrix(list(values))


def _float_array(A) -> np.ndarray:
    """The float64 array of an exact matrix (SymPy or :class:`~impactsym.resolution.RationalMatrix`):
    each entry's nearest float, as SymPy's ``float`` rounds a rational (``±inf`` beyond the range)."""
    def near(x):
        try:
            return float(x)
        except OverflowError:  # a Fraction beyond the float range; SymPy's float gives inf there
            return math.inf if x > 0 else -math.inf

    if is_sympy(A, "MatrixBase"):
        from .laws.sequential.sparse import _sympy_rows

        got = _sympy_rows(A)  # over ZZ or QQ: the non-zero entries as fmpq (a scene's 1000 x 1000 M)
        if got is not None:
            rows, cols, data = got
            out = np.zeros((rows, cols), dtype=np.float64)
            cache: dict = {}
            for i, row in enumerate(data):
                for j, q in row.items():
                    f = cache.get(q)
                    if f is None:  # a rational's nearest float, as SymPy's float of it (ties to even)
                        f = cache[q] = near(Fraction(int(q.p), int(q.q)))
                    out[i, j] = f
            return out
    if isinstance(A, RationalMatrix):  # the non-zero entries only (a 1000-ball scene's M is diagonal)
        out = np.zeros(A.shape, dtype=np.float64)
        for (i, j), x in A.nonzeros().items():
            out[i, j] = near(x)
        return out
    return np.array([[near(x) for x in row] for row in A.tolist()], dtype=np.float64)


def _is_one(x) -> bool:
    """``sympify(x) == 1``, without SymPy for a plain number."""
    if type(x) in (int, float, Fraction):
        return x == 1
    import sympy as sp

    return sp.sympify(x) == 1


def _impulses_of(system: System, velocity):
    """``p`` with ``Hᵀp = M(v⁺ − v⁻)`` when ``H`` has full row rank (exact for exact input), for
    outcomes a law gives without impulses (the sequential selection); None otherwise."""
    M, H, v = system.M, system.H, system.v
    if is_sympy(velocity, "MatrixBase") and is_sympy(M, "MatrixBase"):
        import sympy as sp

        W = H * M.inv() * H.T
        if W.det() == 0:
            return None
        return sp.Matrix([sp.radsimp(sp.simplify(x)) for x in W.inv() * H * (velocity - v)])
    if is_mpmath(velocity, "matrix"):
        return None
    Hf = np.asarray(H.tolist() if is_sympy(H, "MatrixBase") else H, dtype=float)
    Mf = np.asarray(M.tolist() if is_sympy(M, "MatrixBase") else M, dtype=float)
    if np.linalg.matrix_rank(Hf) < Hf.shape[0]:
        return None
    vf = np.asarray([float(x) for x in (v if not is_sympy(v, "MatrixBase") else list(v))], dtype=float)
    rhs = Mf @ (np.asarray(velocity, dtype=float).reshape(-1) - vf)
    return np.linalg.lstsq(Hf.T, rhs, rcond=None)[0]


def _kind(outcomes, multiple: str) -> str:
    """``"unique"`` when every outcome has the same velocity (exactly, or bit for bit for floats;
    certified outcomes are never assumed equal), else ``multiple``."""
    vels = [o.velocity for o in outcomes]
    if len(vels) <= 1:
        return "unique"
    first = vels[0]
    for w in vels[1:]:
        if is_sympy(first, "MatrixBase") and is_sympy(w, "MatrixBase"):
            import sympy as sp

            if any(sp.simplify(a - b) != 0 for a, b in zip(first, w)):
                return multiple
        elif isinstance(first, np.ndarray) and isinstance(w, np.ndarray):
            if not np.array_equal(first, w):
                return multiple
        else:
            return multiple
    return "unique"


class Law:
    """One impact law behind the common interface.

    Attributes
    ----------
    name : the law's CLI name
    title : one line: what the law is and where it comes from
    options : the keyword options :meth:`resolve` accepts (their CLI forms are ``--option-name``)
    restitution : ``"none"`` (elastic only), ``"scalar"`` (one coefficient) or ``"per-contact"``
    """

    name = ""
    title = ""
    options: tuple[str, ...] = ()
    restitution = "scalar"

    def why_not(self, system: System, **options) -> tuple[str, str] | None:
        """Why the law does not apply to ``system`` with ``options``: ``(argument, reason)``, the
        argument being the input to change; None when the law applies."""
        return None

    def resolve(self, system: System, **options) -> Resolution:
        """Resolve ``system``; every law returns a :class:`~impactsym.resolution.Resolution`."""
        raise NotImplementedError  # pragma: no cover

    def check(self, system: System, options: dict) -> None:
        unknown = [k for k in options if k not in self.options]
        if unknown:
            raise ImpactInputError(unknown[0], f"is not an option of --law {self.name} "
                                   f"(it takes: {', '.join(self.options) or 'none'})")
        why = self.why_not(system, **options)
        if why is not None:
            raise ImpactInputError(why[0], f"--law {self.name} does not apply: {why[1]}")

    def __call__(self, system: System, **options) -> Resolution:
        self.check(system, options)
        return self.resolve(system, **options)

    def __repr__(self) -> str:
        return f"<law {self.name}: {self.title}>"


# ------------------------------------------------------------------------------- classical
class _Classical(Law):
    function = ""

    def _call(self, system, e, **options):
        from .laws import classical

        return getattr(classical, self.function)(system.M, system.H, system.v, e, **options)

    def _restitution(self, system):
        return system.restitution_scalar(self.name)

    def resolve(self, system, **options):
        r = self._call(system, self._restitution(system), **options)
        details = _details(r.details)
        details["unique_impulse"] = r.unique_impulse
        if r.other_impulses:
            details["other_impulses"] = [_jsonable(p) for p in r.other_impulses]
        out = Outcome(r.velocity, r.impulses, valid=r.valid, violations=_violations(r.violations))
        return Resolution(self.name, system, [out], notes=list(r.notes), details=details, raw=r)


class Newton(_Classical):
    name, function = "newton", "newton_moreau"
    title = "Newton/Moreau: 0 <= H v+ + e H v- _|_ p >= 0 (Acary & Taha sec. 2.2)"
    options = ("allow_invalid",)


class Poisson(_Classical):
    name, function = "poisson", "poisson"
    title = "Poisson: compression LCP, then p = (1 + e_p) p_c (Acary & Taha eq. 11)"
    options = ("allow_invalid", "variant")
    restitution = "per-contact"

    def _restitution(self, system):
        e = system.restitution
        return system.restitution_vector() if isinstance(e, (list, tuple)) else system.restitution_scalar(self.name)


class Energetic(_Classical):
    name, function = "energetic", "energetic"
    title = "global energetic coefficient T+ = e T- along a direction (Acary & Taha eq. 12)"
    options = ("allow_invalid", "ratios")

    def _call(self, system, e, ratios=None, allow_invalid=False):
        from .laws import classical

        return classical.energetic(system.M, system.H, system.v, e, ratios, allow_invalid=allow_invalid)


class HanGilmore(Law):
    name = "han-gilmore"
    title = "Han & Gilmore's sequential stages, every hypothesis followed (Acary & Taha eqs. 15-16)"
    options = ()

    def resolve(self, system, **options):
        from .laws import classical

        r = classical.han_gilmore(system.M, system.H, system.v, system.restitution_scalar(self.name))
        outs = []
        for o in r.outcomes:
            seqs = [[[i - 1 for i in stage] for stage in seq] for seq in o.sequences]
            outs.append(Outcome(o.velocity, o.impulses, order=seqs[0], orderings=len(seqs),
                                details={"sequences": seqs}))
        notes = list(r.notes)
        if r.unterminated:
            notes.append(f"{len(r.unterminated)} stage sequence(s) cut at the stage cap (still approaching)")
        return Resolution(self.name, system, outs, uniqueness=_kind(outs, "set-valued"),
                          notes=notes, details={"stages": "0-based contact indices impacting together"}, raw=r)


class ImpulseRatio(Law):
    name = "impulse-ratio"
    title = "impulse ratios p_j = alpha_1j p_1 with T+ = e T- (Acary & Taha eq. 38)"
    options = ("ratios", "allow_invalid", "coupling")

    def why_not(self, system, ratios=None, coupling=False, **_):
        if ratios is None and system.k > 1 and not coupling:
            names = "alpha_12" if system.k == 2 else f"alpha_12, ..., alpha_1{system.k}"
            return ("ratios", f"expected {system.k - 1} ratio(s) {names} for {system.k} closed contacts "
                    "(--ratios), got none; or --coupling to set the ratios of uncoupled contacts")
        return None

    def resolve(self, system, ratios=None, allow_invalid=False, coupling=False):
        from .laws.impulse_ratio import impulse_ratio_law

        e = system.restitution_scalar(self.name)
        r = impulse_ratio_law(system.M, system.H, system.v, e, ratios, allow_invalid=allow_invalid,
                              coupling=coupling)
        A, B, C = r.coefficients
        details = _details({"ratios": list(r.ratios), "delta": r.delta, "delta_normalized": r.delta_normalized})
        details.update({"coefficients": _details({"A": A, "B": B, "C": C}), "real_solution": r.real_solution})
        if r.coupling:
            details["coupling"] = _jsonable(r.coupling)
        out = Outcome(r.velocity, r.impulses, valid=r.valid, violations=_violations(r.violations))
        return Resolution(self.name, system, [out], details=details, raw=r)


# ------------------------------------------------------------------------ Seghete & Murphey
def _order_json(order):
    return order.to_json() if hasattr(order, "to_json") else [int(i) for i in order]


class TwoSurface(Law):
    name = "two-surface"
    title = "two surfaces in O(1): every branch's count and exit velocity (Seghete & Murphey sec. III)"
    options = ()
    restitution = "none"

    def why_not(self, system, **_):
        if system.k != 2:
            where = "gradients" if system.scene is None else "scene"
            return where, f"it resolves exactly two contacts; this system has {system.k}"
        e = system.restitution
        vals = e if isinstance(e, (list, tuple)) else [e]
        if any(x is not None and not _is_one(x) for x in vals):
            return "restitution", "the two-surface law is elastic (sequential G_u): e must be 1"
        return None

    def resolve(self, system, **options):
        import mpmath

        from .laws.two_surface import resolve_two_surfaces

        r = resolve_two_surfaces(system.M, system.H, system.v)
        outs = [Outcome(o.velocity, o.impulse, order=_order_json(o.order), orderings=1, digits=o.digits,
                        details={"reflections": o.reflections, "first": o.first, "no_impact": o.first is None})
                for o in r.outcomes]
        c = r.kinetic_angle_cos
        details = {"bound": r.bound, "wedge_angle": mpmath.nstr(r.wedge_angle, 17),
                   "wedge_angle_float": float(r.wedge_angle), "kinetic_angle_cos": str(c),
                   "kinetic_angle_cos_float": float(c), "decisions": _jsonable(r.decisions)}
        return Resolution(self.name, system, outs, uniqueness=_kind(outs, "gap-dependent"),
                          details=details, raw=r)


class Sequential(Law):
    name = "sequential"
    title = "every ordering of single impacts G_u, their outcomes and the selection (Seghete & Murphey sec. III)"
    options = ("reading", "max_reflections", "float", "two_surface_path", "gaps")
    restitution = "per-contact"

    def why_not(self, system, gaps=None, **options):
        if gaps is None:
            return None
        given = [k for k, v in options.items() if v not in (None, False, "auto")]
        if given:
            return given[0], "--gaps simulates the impact; it takes no option of the ordering search"
        if system.source is None or system.source.meta.get("builder") != "balls_on_line":
            return "gaps", ("gaps need the geometry of balls on a line (a line scene or scene file); "
                            "this system has none")
        return None

    def _with_gaps(self, system, gaps):
        """The outcome that the gaps produce (:func:`impactsym.gaps.resolve_with_gaps`), verified
        by replaying its ordering with ``G_u(e)`` exactly."""
        import sympy as sp

        from .errors import VerificationError
        from .gaps import resolve_with_gaps
        from .laws.reflection import reflect

        e = system.restitution_vector()
        g = resolve_with_gaps(system.source, gaps, e)
        v = system.v
        for i in g.order:  # the law's own single impacts G_u(e), in the simulated order
            v = reflect(system.M, system.H[i, :], v, e[i])
        if any(sp.simplify(a - b) != 0 for a, b in zip(v, g.velocity)):
            raise VerificationError(self.name, f"the simulated outcome {list(g.velocity)} is not the ordering "
                                    f"{list(g.order)} replayed with G_u(e): {list(v)}")
        out = Outcome(g.velocity, g.impulses, order=[int(i) for i in g.order], orderings=1,
                      details={"reflections": len(g.order)})
        details = {"method": "exact small-gap simulation (impactsym.gaps)", "gaps": [str(x) for x in g.gaps],
                   "times": [str(t) for t in g.times], "positions": [str(x) for x in g.positions],
                   "impulses_unique": g.impulses_unique}
        return Resolution(self.name, system, [out], uniqueness="unique",
                          notes=["the outcome of these gaps; other gaps may give another ordering and outcome"],
                          details=details, raw=g)

    def resolve(self, system, reading=None, max_reflections=None, float=False, two_surface_path="auto",
                gaps=None):
        if gaps is not None:
            return self._with_gaps(system, gaps)
        from .laws.sequential import DEFAULT_MAX_REFLECTIONS, resolve_sequential, termination_bound

        M, H, v = system.M, system.H, system.v
        if float and system.exact:
            M, H, v = (_float_array(A) for A in (M, H, v))
            v = v.reshape(-1)
            system = System(M, H, v, system.restitution, contacts=system.contacts, scene=system.scene, exact=False,
                            coordinates=system.coordinates, source=system.source)
        cap = DEFAULT_MAX_REFLECTIONS if max_reflections is None else max_reflections
        kw = {} if system.restitution is None else {"restitution": system.restitution}
        r = resolve_sequential(M, H, v, reading=reading, max_reflections=cap, exact=not float and system.exact,
                               two_surface=two_surface_path, **kw)
        if max_reflections is not None:
            used = max((o.reflections_max or 0 for o in r.outcomes), default=0)
            if used > cap:  # the two-surface closed form needs no cap; a cap the user gave still binds
                raise NonTermination(f"max_reflections: an ordering needs {used} reflections, more than the cap "
                                     f"max_reflections={cap}; raise the cap or omit --max-reflections")
        outs = []
        for o in r.outcomes:
            extra = {"collapse": bool(getattr(o, "collapse", False))}
            outs.append(Outcome(o.velocity, o.impulse, order=_order_json(o.order), orderings=o.orderings,
                                details={"reflections": o.reflections, "reflections_min": o.reflections_min,
                                         "reflections_max": o.reflections_max, **_jsonable(extra)}))
        selected = []
        known = getattr(r, "selected_impulses", ()) or ()
        floats = float or not system.exact  # the float path reports floats (of the exact selection)
        for idx, s in enumerate(r.selected_float if floats else r.selected):
            if floats:
                s = np.array(s, dtype=np.float64)
            elif idx < len(known) and known[idx] is not None:  # exact, verified by the law (full row rank)
                selected.append(Outcome(s, known[idx]))
                continue
            selected.append(Outcome(s, _impulses_of(system, s)))
        bound = r.bound
        elastic = all(_is_one(x) for x in system.restitution_vector())
        if bound is None and system.k == 2 and system.exact and not float and elastic:  # the bound is elastic
            try:
                bound = termination_bound(M, H)
            except (DomainError, ImpactInputError):  # parallel rows: no wedge, no bound
                bound = None
        details = {"backend": r.backend, "method": r.method, "reading": r.reading,
                   "approaching": list(r.approaching), "two_surface_bound": bound,
                   "counts": {"orderings": r.orderings, "states_visited": r.states_visited,
                              "sign_tests": r.sign_tests, "exact_fallbacks": r.exact_fallbacks,
                              "max_reflections_used": r.max_reflections_used}}
        notes = [r.selection_note] if r.selection_note else []
        if len(outs) > 1:
            notes.append("which outcome happens depends on the gaps between the touching bodies: --gaps g1,g2,... "
                         "gives the one that given gaps produce")
        return Resolution(self.name, system, outs, selected=selected,
                          uniqueness=_kind(outs, "gap-dependent"), notes=notes,
                          details=details, raw=r)


#: every law, by CLI name, in the order of tables
LAWS: dict[str, Law] = {law.name: law for law in (Sequential(), TwoSurface(), Newton(), Poisson(), Energetic(),
                                                 HanGilmore(), ImpulseRatio())}


def law_names() -> list[str]:
    return list(LAWS)


def get_law(name: str) -> Law:
    """The law called ``name`` (:data:`LAWS`); an unknown name is refused naming the known ones."""
    try:
        return LAWS[name]
    except (KeyError, TypeError):
        raise ImpactInputError("law", f"unknown law {name!r}; known: {', '.join(LAWS)}") from None


def resolve(law: str, system: System, **options) -> Resolution:
    """Resolve ``system`` with the law called ``law`` (options as :attr:`Law.options`)."""
    return get_law(law)(system, **options)


#: what a law may raise on a system it cannot resolve (reported per law by :func:`resolve_all`)
REFUSALS = (ImpactInputError, DomainError, NonTermination)


def resolve_all(system: System, laws=None, options: dict | None = None) -> dict[str, Any]:
    """Every law on one system: ``{law: Resolution, or the reason (str) it does not apply or
    refused}``, in the order of :data:`LAWS`. ``options`` maps a law's name to its options.
    Each answer is remembered on the system (:meth:`~impactsym.resolution.System.resolution_memo`):
    the same law and options on the same system (``impactsym check`` after a resolution) answer
    at once."""
    from .resolution import _UNKEYED, _frozen

    options = options or {}
    out: dict[str, Any] = {}
    memo = system.resolution_memo()
    for name in (laws or LAWS):
        law = get_law(name)
        opts = options.get(name, {})
        key = _frozen((name, opts)) if memo is not None else None
        if key is _UNKEYED:
            key = None
        if key is not None and key in memo:
            out[name] = memo[key]
            continue
        why = law.why_not(system, **opts)
        if why is not None:
            out[name] = f"does not apply: {why[1]}"
        else:
            try:
                out[name] = law.resolve(system, **opts)
            except REFUSALS as exc:
                out[name] = f"refused: {exc}"
        if key is not None:
            memo[key] = out[name]
    return out


from . import lawbook_compliant  # noqa: E402,F401  (registers the compliant and LZB laws into LAWS, issue 13)
