"""Reading an impact scene from ``impactsym resolve``'s options: either the matrices
(``--mass-matrix``, ``--gradients``, ``--velocity``) or a canonical scene (``--scene chain3|pool|
bernoulli`` with ``--theta``, ``--tau``, ``--masses``, ``--velocities``) from
:mod:`impactsym.models.acary_taha`. Exactly one of the two forms; options that do not apply to
the chosen form are refused, never ignored."""

from __future__ import annotations

from contextlib import contextmanager

import sympy as sp

from ..errors import ImpactInputError
from ..numbers import exact_str, parse_number, parse_vector
from .common import matrix_arg, vector_arg

__all__ = ["SCENES", "SCENE_OPTIONS", "read_scene", "read_system", "scene_json", "float_range_guard", "int_option"]

#: scene name -> the parameter options it accepts
SCENES = {"chain3": ("masses", "velocities"), "pool": ("theta", "tau"), "bernoulli": ("tau",)}
_PARAMS = ("theta", "tau", "masses", "velocities")


def read_scene(args):
    """``(M, H, v, description)`` from the parsed options (exact SymPy matrices)."""
    given = {name: getattr(args, name, None) for name in _PARAMS}
    if args.scene is None:
        for name, val in given.items():
            if val is not None:
                raise ImpactInputError(name, f"--{name} applies only with --scene ({', '.join(SCENES)})")
        missing = [opt for opt, val in (("mass_matrix", args.mass_matrix), ("gradients", args.gradients),
                                        ("velocity", args.velocity)) if val is None]
        if missing:
            raise ImpactInputError(missing[0], "is required unless --scene is given")
        M = matrix_arg(args.mass_matrix, "mass_matrix")
        H = matrix_arg(args.gradients, "gradients")
        v = vector_arg(args.velocity, "velocity")
        return M, H, v, {"scene": None}
    for opt, val in (("mass_matrix", args.mass_matrix), ("gradients", args.gradients), ("velocity", args.velocity)):
        if val is not None:
            raise ImpactInputError(opt, "cannot be combined with --scene (the scene defines M, H and v)")
    name = args.scene
    if name not in SCENES:
        raise ImpactInputError("scene", f"unknown scene {name!r}; known: {', '.join(SCENES)}")
    for pname, val in given.items():
        if val is not None and pname not in SCENES[name]:
            raise ImpactInputError(pname, f"--{pname} does not apply to --scene {name} (it takes: "
                                   f"{', '.join('--' + x for x in SCENES[name])})")
    from ..models import acary_taha

    if name == "chain3":
        masses = list(parse_vector(given["masses"], "masses")) if given["masses"] else [1, 1, 1]
        vels = list(parse_vector(given["velocities"], "velocities")) if given["velocities"] else [1, 0, 0]
        if len(masses) != 3:
            raise ImpactInputError("masses", f"chain3 needs three masses, got {len(masses)}")
        if len(vels) != 3:
            raise ImpactInputError("velocities", f"chain3 needs three velocities, got {len(vels)}")
        for m in masses:
            from ..exact import certified_sign

            if certified_sign(m) <= 0:
                raise ImpactInputError("masses", f"must be positive, got {m}")
        sc = acary_taha.chain3(masses, vels)
        desc = {"scene": "chain3", "masses": [exact_str(m) for m in masses], "velocities": [exact_str(x) for x in vels]}
    elif name == "pool":
        if given["theta"] is None:
            raise ImpactInputError("theta", "is required with --scene pool (e.g. --theta pi/4)")
        theta = parse_number(given["theta"], "theta")
        tau = parse_number(given["tau"], "tau") if given["tau"] else sp.Integer(0)
        sc = acary_taha.pool(theta, tau)
        desc = {"scene": "pool", "theta": exact_str(theta), "tau": exact_str(tau), "contacts": sc.contacts}
    else:
        tau = parse_number(given["tau"], "tau") if given["tau"] else -sp.pi / 6
        sc = acary_taha.bernoulli(tau)
        desc = {"scene": "bernoulli", "theta": "2*pi/3", "tau": exact_str(tau), "contacts": sc.contacts}
    return sc.M, sc.H, sc.v, desc


def scene_json(desc: dict) -> dict:
    """The scene description as it goes into the JSON result (``None`` for explicit matrices)."""
    return {"scene": desc if desc.get("scene") else None}


@contextmanager
def float_range_guard(args):
    """Turn an ``OverflowError`` of a law's float twins (an exact result beyond the float range,
    about 1.8e308) into a refusal naming the input, instead of a traceback."""
    try:
        yield
    except OverflowError:
        if getattr(args, "scene", None) is None:
            arg = "velocity"
        else:
            arg = next((a for a in ("velocities", "masses") if getattr(args, a, None) is not None), "scene")
        raise ImpactInputError(arg, "the result is beyond the float range (about 1.8e308), where its float "
                               "twin cannot be given; scale the input down") from None


# ----------------------------------------------------------------------------------------------
# Every built-in scene, for every law
# ----------------------------------------------------------------------------------------------
#: Seghete & Murphey scene -> the options it takes
SM_SCENE_PARAMS = {
    "two-balls-wall": ("masses", "velocities"),
    "three-ball-cradle": ("masses", "velocities"),
    "cradle": ("n_balls", "strikers", "masses"),
    "balls-against-wall": ("n_balls", "masses", "velocities"),
}
#: every built-in scene -> the options it takes
SCENE_OPTIONS = {**SCENES, **SM_SCENE_PARAMS}
_SM_PARAMS = ("n_balls", "strikers", "masses", "velocities")


def _max_n_balls() -> int:
    from ..laws.sequential import MAX_COORDINATES

    return MAX_COORDINATES


def int_option(text, argument, minimum, maximum=None):
    """An integer option, given as an integer or an exact integer expression (``10**2``).

    >>> int_option("10**2", "n_balls", 2)
    100
    >>> int_option("1000000000000", "n_balls", 2, 200)
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


def _read_sm(args):
    """A Seghete & Murphey scene: ``(Scene, description)``."""
    from ..models import seghete_murphey as sm

    given = {k: getattr(args, k, None) for k in _SM_PARAMS}
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
        kw["n_balls"] = int_option(given["n_balls"], "n_balls", 1, _max_n_balls())
    if given["strikers"] is not None:
        kw["strikers"] = int_option(given["strikers"], "strikers", 1, _max_n_balls())
    sc = sm.SCENES[args.scene](**kw)
    desc = {"scene": args.scene, **{k: (v if isinstance(v, int) else [exact_str(x) for x in v])
                                    for k, v in kw.items()}}
    return sc, desc


def read_system(args):
    """The :class:`~impactsym.resolution.System` of ``resolve``'s options: explicit matrices, or a
    built-in ``--scene`` (every scene for every law), with ``--restitution`` (one number, or one
    per contact ``"a,b"``)."""
    from ..resolution import System

    for opt, val in (("mass_matrix", args.mass_matrix), ("gradients", args.gradients), ("velocity", args.velocity)):
        if val is not None and args.scene is not None:
            raise ImpactInputError(opt, "cannot be combined with --scene (the scene defines M, H and v)")
    e = restitution_arg(getattr(args, "restitution", None))
    if args.scene in SM_SCENE_PARAMS:
        sc, desc = _read_sm(args)
        return System.from_scene(sc, e, description=desc)
    if args.scene is not None and args.scene not in SCENES:
        raise ImpactInputError("scene", f"unknown scene {args.scene!r}; known: {', '.join(SCENE_OPTIONS)}")
    M, H, v, desc = read_scene(args)
    contacts = desc.get("contacts") if desc.get("scene") else None
    system = System.from_matrices(M, H, v, e, scene=desc if desc.get("scene") else None)
    if contacts and len(contacts) == system.k:
        system.contacts = list(contacts)
    return system


def restitution_arg(text):
    """``--restitution``: one exact number, or one per contact ``"a,b,c"``; None when absent."""
    if text is None:
        return None
    if "," in str(text):
        return [parse_number(x, "restitution") for x in str(text).split(",")]
    return parse_number(text, "restitution")
