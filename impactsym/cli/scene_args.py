"""Reading the system of ``impactsym resolve`` (and of the commands built on it) from its options:
explicit matrices (``--mass-matrix``, ``--gradients``, ``--velocity``), a named scene (``--scene
NAME`` with its parameters: a built-in or a shipped scene file, :mod:`impactsym.scenes.registry`),
or a scene file (``--scene-file PATH``, :mod:`impactsym.scenes.fileformat`). Exactly one of the
three forms; options that do not apply to the chosen form are refused, never ignored."""

from __future__ import annotations

from contextlib import contextmanager

from ..errors import ImpactInputError
from .common import matrix_arg, vector_arg

__all__ = ["SCENE_OPTIONS", "MATRIX_OPTIONS", "read_system", "read_rational_system", "float_range_guard", "int_option",
           "restitution_arg", "add_system_arguments"]

#: the parameters any built-in scene takes (``impactsym.scenes.registry.ALL_PARAMS``; a test checks
#: they agree): the CLI reads them without importing the scenes (and SymPy) at start-up
ALL_PARAMS = ("masses", "velocities", "theta", "tau", "n_balls", "strikers")


def __getattr__(name):  # SCENE_OPTIONS, int_option: loaded on first use (start-up stays light)
    if name == "SCENE_OPTIONS":
        from ..scenes.registry import SCENE_PARAMS, SHIPPED_SCENES

        return {**SCENE_PARAMS, **{n: () for n in SHIPPED_SCENES}}
    if name == "int_option":
        from ..scenes.registry import int_option

        return int_option
    raise AttributeError(name)


#: the explicit form of an impact
MATRIX_OPTIONS = ("mass_matrix", "gradients", "velocity")


def add_system_arguments(p) -> None:
    """The options of the three forms of a system, for a subcommand's parser."""
    p.add_argument("--mass-matrix", metavar="M", help='mass matrix "a,b;c,d"')
    p.add_argument("--gradients", metavar="H", help='gradient rows of the closed contacts "a,b;c,d"')
    p.add_argument("--velocity", metavar="v", help='pre-impact velocity "a,b"')
    p.add_argument("--scene", metavar="NAME",
                   help="a named scene instead of matrices: a built-in (chain3, pool, bernoulli, two-balls-wall, "
                        "three-ball-cradle, cradle, balls-against-wall) or a shipped scene file (impactsym scene list)")
    p.add_argument("--scene-file", metavar="PATH", help="a scene file (TOML or JSON; see impactsym.scenes.fileformat), "
                   "or a shipped scene file's name (impactsym scene list)")
    p.add_argument("--theta", metavar="T", help="pool: angle between the lines 1-2 and 2-3 (e.g. pi/4)")
    p.add_argument("--tau", metavar="T", help="pool/bernoulli: incidence angle of ball 1")
    p.add_argument("--masses", metavar="m", help='chain3, two-balls-wall, three-ball-cradle, cradle, '
                   'balls-against-wall: masses "m1,m2,..."')
    p.add_argument("--velocities", metavar="v", help='chain3, two-balls-wall, three-ball-cradle, '
                   'balls-against-wall: pre-impact velocities "v1,v2,..."')
    p.add_argument("--n-balls", metavar="N", help="scenes cradle, balls-against-wall: number of balls "
                   "(an integer expression such as 10**2; at most 10000, the sequential law's MAX_COORDINATES)")
    p.add_argument("--strikers", metavar="K", help="scene cradle: number of striking balls")


def form_options(args) -> tuple[str, ...]:
    """The options the chosen form takes (for the refusal of every other)."""
    if getattr(args, "scene_file", None) is not None:
        return ("scene_file",)
    if args.scene is not None:
        return __getattr__("SCENE_OPTIONS").get(args.scene, ())
    return MATRIX_OPTIONS


def read_system(args):
    """The :class:`~impactsym.resolution.System` of the options, with ``--restitution`` (one
    number, or one per contact ``"a,b"``; a scene file's own per-contact restitution otherwise)."""
    from ..resolution import System

    scene_file = getattr(args, "scene_file", None)
    e = restitution_arg(getattr(args, "restitution", None))
    if scene_file is not None and args.scene is not None:
        raise ImpactInputError("scene", "cannot be combined with --scene-file (the file defines the scene; give one)")
    if scene_file is not None or args.scene is not None:
        from ..scenes import load_scene

        for opt in MATRIX_OPTIONS:
            if getattr(args, opt) is not None:
                raise ImpactInputError(opt, "cannot be combined with --scene (the scene defines M, H and v)")
        params = {p: getattr(args, p, None) for p in ALL_PARAMS}
        if scene_file is not None:
            for p, val in params.items():
                if val is not None:
                    raise ImpactInputError(p, f"--{p.replace('_', '-')} does not apply to --scene-file (the file "
                                              "holds the scene's values)")
            from ..scenes.registry import SHIPPED_SCENES

            sc = load_scene(scene_file if scene_file in SHIPPED_SCENES else _existing_file(scene_file))
        else:
            sc = load_scene(args.scene, params)
        return System.from_scene(sc, e, description=sc.meta.get("scene_json") or {"scene": args.scene})
    for name in ALL_PARAMS:
        if getattr(args, name, None) is not None:
            raise ImpactInputError(name, f"--{name.replace('_', '-')} applies only with --scene")
    missing = [opt for opt in MATRIX_OPTIONS if getattr(args, opt) is None]
    if missing:
        raise ImpactInputError(missing[0], "is required unless --scene or --scene-file is given")
    M = matrix_arg(args.mass_matrix, "mass_matrix")
    H = matrix_arg(args.gradients, "gradients")
    v = vector_arg(args.velocity, "velocity")
    return System.from_matrices(M, H, v, e)


def read_rational_system(args):
    """The :class:`~impactsym.resolution.System` of explicit matrices whose every entry (and
    ``--restitution``) is plain rational text (``2``, ``-1/3``, ``1.5``, ``1e-3``), or of a built-in
    scene of rational data whose parameters are plain rational text
    (:func:`~impactsym.scenes.registry.build_rational_scene`: chain3, the scenes of balls on a
    line, the pool at θ = 0 and π/2), read and checked exactly without SymPy
    (:meth:`~impactsym.resolution.System.from_rationals`): for the laws that compute in floats.
    ``None`` for anything else (any other pool, Bernoulli's problem, a scene file, ``sqrt(2)``,
    malformed text, input the checks refuse): :func:`read_system` then reads it, and words every
    error as it always has."""
    from ..arithmetic.literals import plain_matrix, plain_rational, plain_vector
    from ..errors import ImpactError
    from ..resolution import System

    if getattr(args, "scene_file", None) is not None:
        return None
    scene = None
    if args.scene is not None:  # a built-in scene of rational data (balls on a line), built in Fractions
        from ..scenes.registry import build_rational_scene

        if any(getattr(args, opt) is not None for opt in MATRIX_OPTIONS):
            return None
        scene = build_rational_scene(args.scene, {p: getattr(args, p, None) for p in ALL_PARAMS})
        if scene is None:
            return None
        M, H, v = scene.M, scene.H, list(scene.v)
    else:
        if any(getattr(args, name, None) is not None for name in ALL_PARAMS):
            return None
        if any(getattr(args, opt) is None for opt in MATRIX_OPTIONS):
            return None
        M, H, v = plain_matrix(args.mass_matrix), plain_matrix(args.gradients), plain_vector(args.velocity)
        if M is None or H is None or v is None:
            return None
    text = getattr(args, "restitution", None)
    try:
        e = None if text is None else ([plain_rational(x) for x in str(text).split(",")] if "," in str(text)
                                       else plain_rational(text))
    except ZeroDivisionError:
        return None
    if e is not None and (e if isinstance(e, list) else [e]).count(None):
        return None
    try:
        if scene is None:
            return System.from_rationals(M, H, v, e)
        return System.from_rationals(M, H, v, e, contacts=list(scene.contacts), scene=scene.meta["scene_json"],
                                     coordinates=list(scene.coordinates), source=scene)
    except ImpactError:
        return None


def _existing_file(text: str):
    from pathlib import Path

    p = Path(text)
    if not p.is_file():
        raise ImpactInputError("scene_file", f"no such file {text!r}")
    return p


def restitution_arg(text):
    """``--restitution``: one exact number, or one per contact ``"a,b,c"``; None when absent."""
    if text is None:
        return None
    from ..numbers import parse_number

    if "," in str(text):
        return [parse_number(x, "restitution") for x in str(text).split(",")]
    return parse_number(text, "restitution")


@contextmanager
def float_range_guard(args):
    """Turn an ``OverflowError`` of a law's float twins (an exact result beyond the float range,
    about 1.8e308) into a refusal naming the input, instead of a traceback."""
    try:
        yield
    except OverflowError:
        if getattr(args, "scene", None) is None and getattr(args, "scene_file", None) is None:
            arg = "velocity"
        else:
            arg = next((a for a in ("velocities", "masses") if getattr(args, a, None) is not None), "scene")
        raise ImpactInputError(arg, "the result is beyond the float range (about 1.8e308), where its float "
                               "twin cannot be given; scale the input down") from None
