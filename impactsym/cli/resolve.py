"""``impactsym resolve --law LAW ...``: resolve a (simultaneous) impact with one law.

Each law lives in its own module and answers through :data:`LAWS`, a table from the law's
CLI name to ``"module:function"``; the function takes the parsed ``args`` and returns the JSON
result (a dict). The options are shared by the laws; :data:`LAW_OPTIONS` says which apply to
which law and :data:`SCENE_OPTIONS` which apply to which scene, and one check
(:func:`~impactsym.cli.common.refuse_inapplicable`) refuses any other option given (exit 2),
naming it: nothing is silently ignored.
"""

from __future__ import annotations

import importlib

from ..errors import ImpactInputError
from .common import add_json_flag, option_name, refuse_inapplicable
from .plot import add_plot_option, plot_path, write_figure

#: CLI law name -> "module:function" (module relative to impactsym)
LAWS: dict[str, str] = {
    "impulse-ratio": "cli.resolve_impulse_ratio:run",
    "newton": "cli.resolve_classical:run_newton",
    "poisson": "cli.resolve_classical:run_poisson",
    "energetic": "cli.resolve_classical:run_energetic",
    "han-gilmore": "cli.resolve_classical:run_han_gilmore",
    "two-surface": "cli.resolve_two_surface:run",
    "sequential": "cli.resolve_sequential:run",
}


#: law -> the law's own options (beyond --scene and the scene's or the matrices' options)
LAW_OPTIONS: dict[str, tuple[str, ...]] = {
    "impulse-ratio": ("restitution", "ratios", "allow_invalid", "coupling"),
    "newton": ("restitution", "allow_invalid"),
    "poisson": ("restitution", "allow_invalid", "variant"),
    "energetic": ("restitution", "allow_invalid", "ratios"),
    "han-gilmore": ("restitution",),
    "two-surface": ("restitution",),
    "sequential": ("reading", "max_reflections", "float", "two_surface_path"),
}

#: why an option is absent from a law (appended to the refusal)
NOT_APPLICABLE_BECAUSE: dict[tuple[str, str], str] = {
    ("sequential", "restitution"): "the sequential law is elastic (Seghete & Murphey treat e = 1 only)",
    ("han-gilmore", "allow_invalid"): "its outcomes are admissible by construction",
    ("two-surface", "max_reflections"): "the closed form needs no cap; --law sequential --two-surface-path "
                                        "iterate takes one",
}

#: the explicit form of an impact (used when no --scene is given)
MATRIX_OPTIONS = ("mass_matrix", "gradients", "velocity")

#: scene -> the options it takes; Acary & Taha's scenes serve every law, Seghete & Murphey's
#: (the last four) only --law sequential
SCENE_OPTIONS: dict[str, tuple[str, ...]] = {
    "chain3": ("masses", "velocities"),
    "pool": ("theta", "tau"),
    "bernoulli": ("tau",),
    "two-balls-wall": ("masses", "velocities"),
    "three-ball-cradle": ("masses", "velocities"),
    "cradle": ("n_balls", "strikers", "masses"),
    "balls-against-wall": ("n_balls", "masses", "velocities"),
}
ALL_LAWS_SCENES = ("chain3", "pool", "bernoulli")


def law_scenes(law: str) -> tuple[str, ...]:
    """The scenes a law accepts."""
    return tuple(SCENE_OPTIONS) if law == "sequential" else ALL_LAWS_SCENES


def register(sub) -> None:
    p = sub.add_parser(
        "resolve",
        help="resolve a simultaneous impact with one law",
        description="Resolve an impact given matrices (--mass-matrix, --gradients, --velocity) or --scene.",
    )
    p.add_argument("--law", required=True, metavar="LAW", help="one of: " + ", ".join(LAWS) if LAWS else "law")
    p.add_argument("--mass-matrix", metavar="M", help='mass matrix "a,b;c,d"')
    p.add_argument("--gradients", metavar="H", help='gradient rows of the closed contacts "a,b;c,d"')
    p.add_argument("--velocity", metavar="v", help='pre-impact velocity "a,b"')
    p.add_argument("--restitution", metavar="e", help="restitution coefficient")
    p.add_argument("--scene", metavar="NAME",
                   help="a canonical scene instead of matrices: chain3, pool, bernoulli (every law); "
                        "two-balls-wall, three-ball-cradle, cradle, balls-against-wall (--law sequential)")
    p.add_argument("--ratios", metavar="A", help="impulse ratios alpha_12,alpha_13,... against contact 1")
    p.add_argument("--allow-invalid", action="store_true", help="report a result outside the law's domain (exit 0)")
    p.add_argument("--coupling", action="store_true", help="apply the kinetic-angle coupling criteria (eqs. 41-45)")
    p.add_argument("--theta", metavar="T", help="pool: angle between the lines 1-2 and 2-3 (e.g. pi/4)")
    p.add_argument("--tau", metavar="T", help="pool/bernoulli: incidence angle of ball 1")
    p.add_argument("--masses", metavar="m", help='chain3: the three masses "m1,m2,m3"')
    p.add_argument("--velocities", metavar="v", help='chain3: the three pre-impact velocities "v1,v2,v3"')
    p.add_argument("--variant", metavar="V", help="poisson: paper (default) or glocker-pfeiffer")
    p.add_argument("--reading", metavar="R", help="sequential: feasible set of the selection, energy (default) or cone")
    p.add_argument("--max-reflections", metavar="K", help="sequential: cap on the reflections of one ordering")
    p.add_argument("--float", action="store_true", help="sequential: float64 with certified branch decisions")
    p.add_argument("--two-surface-path", metavar="P", help="sequential: closed-form (default) or iterate")
    p.add_argument("--n-balls", metavar="N", help="sequential scenes cradle, balls-against-wall: number of balls "
                   "(an integer expression such as 10**2; at most 200, the sequential law's MAX_COORDINATES)")
    p.add_argument("--strikers", metavar="K", help="sequential scene cradle: number of striking balls")
    add_plot_option(p, "the picture of the answer (two surfaces: the law in the plane of their M-normals; "
                       "otherwise the velocities before and after)")
    add_json_flag(p)
    p.set_defaults(func=run, _resolve_parser=p)


def check_options(args) -> None:
    """Refuse every option given that does not apply to the law and the scene (or to explicit matrices)."""
    law, scene = args.law, args.scene
    if scene is not None and scene not in law_scenes(law):
        other = " (that scene is --law sequential's)" if scene in SCENE_OPTIONS else ""
        raise ImpactInputError("scene", f"unknown scene {scene!r} for --law {law}{other}; known: "
                               f"{', '.join(law_scenes(law))}")
    form = SCENE_OPTIONS[scene] if scene is not None else MATRIX_OPTIONS
    context = f"--law {law} " + (f"--scene {scene}" if scene is not None else "with explicit matrices (no --scene)")
    try:
        refuse_inapplicable(args, args._resolve_parser, ("law", "scene", "plot", *LAW_OPTIONS[law], *form), context)
    except ImpactInputError as exc:
        arg = exc.argument
        why = NOT_APPLICABLE_BECAUSE.get((law, arg))
        owners = [name for name, opts in LAW_OPTIONS.items() if arg in opts]
        if why is None and owners:
            why = f"{option_name(arg)} applies to --law {', '.join(owners)}"
        elif why is None and scene is None and any(arg in opts for opts in SCENE_OPTIONS.values()):
            why = (f"{option_name(arg)} applies only with --scene "
                   f"({', '.join(s for s in law_scenes(law) if arg in SCENE_OPTIONS[s])})")
        elif why is None and scene is not None and arg in MATRIX_OPTIONS:
            why = f"{option_name(arg)} cannot be combined with --scene (the scene defines M, H and v)"
        if why:
            raise ImpactInputError(exc.argument, f"{exc.condition}; {why}") from None
        raise


def run(args) -> dict:
    if args.law not in LAWS:
        raise ImpactInputError("law", f"unknown law {args.law!r}; known: {', '.join(LAWS) or '(none yet)'}")
    check_options(args)
    path = plot_path(args)  # checked before the work
    module_name, func_name = LAWS[args.law].split(":")
    module = importlib.import_module(f"impactsym.{module_name}")
    result = getattr(module, func_name)(args)
    if path is not None:
        from ..figures import resolve_figure

        M, H, v = _system(args)
        write_figure(resolve_figure(args.law, M, H, v, result)[0], path)
    return result


def _system(args):
    """``(M, H, v)`` as the law read them (exact), for ``--plot``."""
    if args.law == "sequential":
        from .resolve_sequential import _read

        return _read(args)[:3]
    from .scene_args import read_scene

    return read_scene(args)[:3]


def render(result: dict) -> str:
    """Text output: the law module's own ``render`` (the result's ``"law"`` is its LAWS key)."""
    import json

    module_name, _ = LAWS.get(result.get("law"), ":").split(":")
    module = importlib.import_module(f"impactsym.{module_name}") if module_name else None
    render_law = getattr(module, "render", None)
    return render_law(result) if render_law else json.dumps(result, indent=2)
