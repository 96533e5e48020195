"""``impactsym resolve --law sequential``: every impact ordering, its outcomes and the selection
(Seghete & Murphey sec. III, :func:`impactsym.laws.sequential.resolve_sequential`).

Input: ``--mass-matrix M --gradients H --velocity v0``, or ``--scene NAME`` with the scene's
parameters: the Seghete & Murphey scenes of :data:`impactsym.models.seghete_murphey.SCENES`
(``two-balls-wall`` and ``three-ball-cradle`` take ``--masses``, ``--velocities``; ``cradle``
takes ``--n-balls``, ``--strikers``, ``--masses``; ``balls-against-wall`` takes ``--n-balls``,
``--masses``, ``--velocities``) or the Acary & Taha scenes (``chain3``, ``pool``, ``bernoulli``).
Options: ``--reading energy|cone``, ``--max-reflections K``, ``--float``,
``--two-surface-path closed-form|iterate``.

JSON: ``outcomes`` (each ``order``, ``reflections``, ``velocity`` + ``velocity_float``, ``impulse``
+ ``impulse_float``, ``orderings``, ``reflections_min``, ``reflections_max``), ``selected`` (+
``selected_float``, a list: ties are all listed), ``counts`` (``orderings``, ``states_visited``,
``sign_tests``, ``exact_fallbacks``, ``max_reflections_used``), ``two_surface_bound`` (the paper's
``N = ⌈S_total/(2 S_0)⌉``, for two independent contacts), ``approaching``, ``contacts``,
``exact``, ``backend``, ``method``, ``reading``, ``scene``.
"""

from __future__ import annotations

import mpmath
import numpy as np
import sympy as sp

from ..errors import ImpactInputError, NonTermination
from ..laws.sequential import (DEFAULT_MAX_REFLECTIONS, MAX_COORDINATES, READINGS, TWO_SURFACE_PATHS,
                               resolve_sequential, termination_bound)
from ..numbers import exact_str, parse_number, parse_vector
from .scene_args import float_range_guard, read_scene, scene_json

__all__ = ["run", "render", "SM_SCENE_PARAMS"]

#: Seghete & Murphey scene -> the options it takes
SM_SCENE_PARAMS = {
    "two-balls-wall": ("masses", "velocities"),
    "three-ball-cradle": ("masses", "velocities"),
    "cradle": ("n_balls", "strikers", "masses"),
    "balls-against-wall": ("n_balls", "masses", "velocities"),
}
_SM_PARAMS = ("n_balls", "strikers", "masses", "velocities")


#: the most balls ``--n-balls`` accepts: one coordinate per ball, so the sequential law's own limit
#: (``MAX_COORDINATES``); a larger scene is refused before it is built, naming the limit, rather
#: than left to run for minutes or exhaust memory
MAX_N_BALLS = MAX_COORDINATES


def _int_option(text, argument, minimum, maximum=None):
    """An integer option, given as an integer or an exact integer expression (``10**2``).

    >>> _int_option("10**2", "n_balls", 2)
    100
    >>> _int_option("1000000000000", "n_balls", 2, 200)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: n_balls: must be at most 200, got 1000000000000
    """
    value = parse_number(str(text), argument)
    if not value.is_Integer:
        raise ImpactInputError(argument, f"must be an integer, got {text!r}")
    value = int(value)
    if value < minimum:
        raise ImpactInputError(argument, f"must be >= {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise ImpactInputError(argument, f"must be at most {maximum}, got {value}")  # before any work
    return value


def _read(args):
    """``(M, H, v, description, contacts)``."""
    from ..models import seghete_murphey as sm

    given = {k: getattr(args, k, None) for k in _SM_PARAMS}
    if args.scene in SM_SCENE_PARAMS:
        for opt, val in (("mass_matrix", args.mass_matrix), ("gradients", args.gradients), ("velocity", args.velocity)):
            if val is not None:
                raise ImpactInputError(opt, "cannot be combined with --scene (the scene defines M, H and v)")
        allowed = SM_SCENE_PARAMS[args.scene]
        for name, val in given.items():
            if val is not None and name not in allowed:
                raise ImpactInputError(name, f"--{name.replace('_', '-')} does not apply to --scene {args.scene} "
                                       f"(it takes: {', '.join('--' + a.replace('_', '-') for a in allowed)})")
        kw = {}
        if given["masses"] is not None:
            kw["masses"] = list(parse_vector(given["masses"], "masses"))
        if given["velocities"] is not None:
            kw["velocities"] = list(parse_vector(given["velocities"], "velocities"))
        if given["n_balls"] is not None:
            kw["n_balls"] = _int_option(given["n_balls"], "n_balls", 1, MAX_N_BALLS)
        if given["strikers"] is not None:
            kw["strikers"] = _int_option(given["strikers"], "strikers", 1, MAX_N_BALLS)
        try:
            sc = sm.SCENES[args.scene](**kw)
        except TypeError as exc:  # pragma: no cover - guarded by SM_SCENE_PARAMS
            raise ImpactInputError("scene", str(exc)) from None
        desc = {"scene": args.scene, **{k: (v if isinstance(v, int) else [exact_str(x) for x in v])
                                        for k, v in kw.items()}}
        return sc.M, sc.H, sc.v, desc, list(sc.contacts)
    for name in ("n_balls", "strikers"):
        if given[name] is not None:
            raise ImpactInputError(name, f"--{name.replace('_', '-')} applies only with --scene cradle or balls-against-wall")
    if args.scene is not None and args.scene not in ("chain3", "pool", "bernoulli"):
        known = list(SM_SCENE_PARAMS) + ["chain3", "pool", "bernoulli"]
        raise ImpactInputError("scene", f"unknown scene {args.scene!r}; known: {', '.join(known)}")
    M, H, v, desc = read_scene(args)
    return M, H, v, desc, [f"{i + 1}" for i in range(H.shape[0])]


def _vec(name, value) -> dict:
    if isinstance(value, sp.MatrixBase):
        return {name: [exact_str(x) for x in value], name + "_float": [float(sp.N(x, 17)) for x in value]}
    if isinstance(value, mpmath.matrix):
        return {name: [mpmath.nstr(value[i], 30) for i in range(value.rows)],
                name + "_float": [float(value[i]) for i in range(value.rows)]}
    arr = np.asarray(value, dtype=float).reshape(-1)
    return {name: [float(x) for x in arr], name + "_float": [float(x) for x in arr]}


def _order_json(order):
    return order.to_json() if hasattr(order, "to_json") else [int(i) for i in order]


def run(args) -> dict:
    reading = args.reading if args.reading is not None else "energy"
    if reading not in READINGS:
        raise ImpactInputError("reading", f"must be one of {', '.join(READINGS)}, got {reading!r}")
    cap = (DEFAULT_MAX_REFLECTIONS if args.max_reflections is None
           else _int_option(args.max_reflections, "max_reflections", 1))
    path = args.two_surface_path if args.two_surface_path is not None else "closed-form"
    if path not in TWO_SURFACE_PATHS:
        raise ImpactInputError("two_surface_path", f"must be one of {', '.join(TWO_SURFACE_PATHS)}, got {path!r}")
    if args.restitution is not None:
        raise ImpactInputError("restitution", "the sequential law is elastic (Seghete & Murphey treat e = 1 only)")
    M, H, v, desc, contacts = _read(args)
    if args.float:
        M, H, v = (np.array(np.array(A).tolist(), dtype=float) if isinstance(A, sp.MatrixBase) else
                   np.asarray(A, dtype=float) for A in (M, H, v))
        v = v.reshape(-1)
    with float_range_guard(args):
        r = resolve_sequential(M, H, v, reading=reading, max_reflections=cap, exact=not args.float,
                               two_surface=path)
    if args.max_reflections is not None:
        used = max((o.reflections_max for o in r.outcomes), default=0)
        if used > cap:  # the two-surface closed form needs no cap; a cap the user gave still binds
            raise NonTermination(f"max_reflections: an ordering needs {used} reflections, more than the cap "
                                 f"max_reflections={cap}; raise the cap or omit --max-reflections")
    outcomes = []
    for o in r.outcomes:
        d = {"order": _order_json(o.order), "reflections": o.reflections}
        d.update(_vec("velocity", o.velocity))
        d.update(_vec("impulse", o.impulse))
        d.update({"orderings": o.orderings, "reflections_min": o.reflections_min,
                  "reflections_max": o.reflections_max})
        outcomes.append(d)
    selected = r.selected
    if args.float:  # the float path reports floats, also where the selection compared exactly
        selected = [np.array([float(sp.N(x, 17)) for x in sel]) if isinstance(sel, sp.MatrixBase) else sel
                    for sel in selected]
    bound = r.bound
    if bound is None and len(contacts) == 2 and not args.float:
        try:
            bound = termination_bound(M, H)
        except Exception:  # parallel rows: no wedge, no bound
            bound = None
    out = {"law": "sequential", "exact": r.exact, "backend": r.backend, "method": r.method,
           "reading": reading, "contacts": contacts, "approaching": list(r.approaching),
           "outcomes": outcomes,
           "selected": [_vec("v", s)["v"] for s in selected],
           "selected_float": [_vec("v", s)["v_float"] for s in selected],
           "two_surface_bound": bound,
           "counts": {"orderings": r.orderings, "states_visited": r.states_visited, "sign_tests": r.sign_tests,
                      "exact_fallbacks": r.exact_fallbacks, "max_reflections_used": r.max_reflections_used}}
    out.update(scene_json(desc))
    return out


def render(result: dict) -> str:
    lines = [f"sequential resolution (Seghete & Murphey sec. III), {result['method']}, "
             f"{'exact' if result['exact'] else 'float'} ({result['backend']})"]
    if result.get("scene"):
        lines.append("scene: " + ", ".join(f"{k}={v}" for k, v in result["scene"].items()))
    lines.append("contacts: " + ", ".join(f"{c}{' (approaching)' if a else ''}"
                                          for c, a in zip(result["contacts"], result["approaching"])))
    c = result["counts"]
    lines.append(f"{len(result['outcomes'])} distinct outcome(s) from {c['orderings']} ordering(s); "
                 f"{c['states_visited']} states, {c['sign_tests']} sign tests, {c['exact_fallbacks']} exact fallbacks")
    for o in result["outcomes"]:
        order = o["order"] if isinstance(o["order"], list) else f"alternating from {o['order']['first']}"
        lines.append(f"  order {order} ({o['reflections']} reflections, {o['orderings']} ordering(s)): "
                     f"v+ = [{', '.join(map(str, o['velocity']))}]")
    if result["two_surface_bound"] is not None:
        lines.append(f"paper's bound N = ceil(S_total/(2 S_0)) = {result['two_surface_bound']}")
    for s in result["selected"]:
        lines.append(f"selected ({result['reading']} reading): [{', '.join(map(str, s))}]")
    return "\n".join(lines)
