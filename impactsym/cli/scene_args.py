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

__all__ = ["SCENES", "read_scene", "scene_json", "float_range_guard"]

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
