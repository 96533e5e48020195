"""``impactsym resolve --law LAW|all ...``: resolve a (simultaneous) impact with one law, or with
every law side by side.

One generic module over the law interface (:mod:`impactsym.lawbook`): it reads the system
(explicit matrices, a built-in ``--scene``, or ``--scene-file``), the restitution and the law's
options, calls the law, and prints its :class:`~impactsym.resolution.Resolution` in the one JSON
schema of ``docs/resolution_schema.md``. What is specific to a law lives in its own module: the
options it reads from ``args`` and the lines of its details (:data:`LAW_CLI`).

An option that does not apply to the chosen law, scene or form is refused (exit 2), naming it;
nothing is silently ignored. With ``--law all`` every law's options may be given: each goes to
the laws that take it.
"""

from __future__ import annotations

import importlib

from ..errors import ImpactInputError
from .common import add_json_flag, option_name, refuse_inapplicable
from .scene_args import MATRIX_OPTIONS, add_system_arguments, form_options
from .plot import add_plot_option, plot_path, write_figure

#: law -> "module:options function" (module relative to impactsym.cli); the module's ``render``
#: gives the lines of the law's details
LAW_CLI: dict[str, str] = {
    "sequential": "resolve_sequential:options",
    "two-surface": "resolve_two_surface:options",
    "newton": "resolve_classical:newton_options",
    "poisson": "resolve_classical:poisson_options",
    "energetic": "resolve_classical:energetic_options",
    "han-gilmore": "resolve_classical:han_gilmore_options",
    "impulse-ratio": "resolve_impulse_ratio:options",
    "hertz": "resolve_compliant:hertz_options",
    "linear": "resolve_compliant:linear_options",
    "power": "resolve_compliant:power_options",
    "hunt-crossley": "resolve_compliant:hunt_crossley_options",
    "lzb": "resolve_compliant:lzb_options",
}
LAWS = tuple(LAW_CLI)
#: the laws that compute in floats (integrators): they read plain rational matrices and the built-in
#: scenes of rational data without SymPy (:func:`~impactsym.cli.scene_args.read_rational_system`)
FLOAT_LAWS = ("hertz", "linear", "power", "hunt-crossley", "lzb")

#: why an option is absent from a law (appended to the refusal)
NOT_APPLICABLE_BECAUSE: dict[tuple[str, str], str] = {
    ("han-gilmore", "allow_invalid"): "its outcomes are admissible by construction",
    ("two-surface", "max_reflections"): "the closed form needs no cap; --law sequential --two-surface-path "
                                        "iterate takes one",
}

#: options every law takes
COMMON_OPTIONS = ("law", "scene", "scene_file", "plot", "restitution")


def _law_options(law: str) -> tuple[str, ...]:
    from ..lawbook import get_law

    return get_law(law).options


def _scene_options():
    from .scene_args import SCENE_OPTIONS

    return SCENE_OPTIONS


def register(sub) -> None:
    p = sub.add_parser(
        "resolve",
        help="resolve a simultaneous impact with one law, or every law (--law all)",
        description="Resolve an impact given matrices (--mass-matrix, --gradients, --velocity) or --scene. "
                    "Every law takes every scene; --law all prints every law side by side.",
    )
    p.add_argument("--law", required=True, metavar="LAW",
                   help="one of: " + ", ".join(LAWS) + "; or all (every law that applies)")
    add_system_arguments(p)
    p.add_argument("--restitution", metavar="e", help='restitution: one coefficient, or one per contact "a,b"')
    p.add_argument("--ratios", metavar="A", help="impulse-ratio, energetic: ratios alpha_12,alpha_13,... against "
                   "contact 1, or from-hertz|from-linear|from-lzb (taken from that elastic model's impulses)")
    p.add_argument("--allow-invalid", action="store_true", help="report a result outside the law's domain (exit 0)")
    p.add_argument("--coupling", action="store_true", help="impulse-ratio: apply the kinetic-angle coupling criteria (eqs. 41-45)")
    p.add_argument("--variant", metavar="V", help="poisson: paper (default) or glocker-pfeiffer")
    p.add_argument("--reading", metavar="R", help="sequential: feasible set of the selection, energy (default) or cone")
    p.add_argument("--max-reflections", metavar="K", help="sequential: cap on the reflections of one ordering")
    p.add_argument("--float", action="store_true", help="sequential: float64 with certified branch decisions")
    p.add_argument("--two-surface-path", metavar="P", help="sequential: auto (default: iterate when the certified bound is small), closed-form or iterate")
    p.add_argument("--gaps", metavar="G", help="sequential: small gaps g1,g2,... opening the closed contacts (a "
                   "scene of balls on a line): the ordering and outcome those gaps produce (exact simulation)")
    p.add_argument("--stiffness", metavar="K", help='hertz, linear, power, hunt-crossley, lzb: contact stiffness, '
                   'one or one per contact "a,b" (default 1)')
    p.add_argument("--exponent", metavar="P", help="power (required), hunt-crossley, lzb (default 3/2): contact "
                   "force exponent p >= 1, one or one per contact")
    p.add_argument("--damping", metavar="D", help="hunt-crossley: damping coefficients D >= 0 instead of --restitution")
    p.add_argument("--tolerance", metavar="RTOL", help="hertz, linear, power, hunt-crossley, lzb: the integrator's "
                   "relative tolerance (default 1e-11)")
    add_plot_option(p, "the picture of the answer (two surfaces: the law in the plane of their M-normals; "
                       "otherwise the velocities before and after; --law all: every law's outcomes)")
    add_json_flag(p)
    p.set_defaults(func=run, _resolve_parser=p)


def check_options(args) -> None:
    """Refuse every option given that does not apply to the law and the scene (or to explicit matrices)."""
    law, scene = args.law, args.scene
    scenes = _scene_options()
    if scene is not None and scene not in scenes:
        from ..scenes import load_scene

        load_scene(scene)  # raises naming the scene (neither a name nor a file)
        raise ImpactInputError("scene", f"{scene!r} is a file: give it with --scene-file")
    form = form_options(args)
    law_opts = tuple(o for name in LAWS for o in _law_options(name)) if law == "all" else _law_options(law)
    context = f"--law {law} " + (f"--scene {scene}" if scene is not None else "with explicit matrices (no --scene)")
    try:
        refuse_inapplicable(args, args._resolve_parser, (*COMMON_OPTIONS, *law_opts, *form), context)
    except ImpactInputError as exc:
        arg = exc.argument
        why = NOT_APPLICABLE_BECAUSE.get((law, arg))
        owners = [name for name in LAWS if arg in _law_options(name)]
        if why is None and owners:
            why = f"{option_name(arg)} applies to --law {', '.join(owners)}"
        elif why is None and scene is None and any(arg in opts for opts in scenes.values()):
            why = (f"{option_name(arg)} applies only with --scene "
                   f"({', '.join(s for s in scenes if arg in scenes[s])})")
        elif why is None and (scene is not None or args.scene_file is not None) and arg in MATRIX_OPTIONS:
            why = f"{option_name(arg)} cannot be combined with --scene (the scene defines M, H and v)"
        if why:
            raise ImpactInputError(exc.argument, f"{exc.condition}; {why}") from None
        raise


def _cli_options(law: str, args) -> dict:
    module_name, func_name = LAW_CLI[law].split(":")
    module = importlib.import_module(f"impactsym.cli.{module_name}")
    return getattr(module, func_name)(args)


def run(args) -> dict:
    if args.law != "all" and args.law not in LAW_CLI:
        raise ImpactInputError("law", f"unknown law {args.law!r}; known: {', '.join(LAWS)}, all")
    check_options(args)
    path = plot_path(args)  # checked before the work
    from ..lawbook import get_law, resolve_all
    from .scene_args import float_range_guard, read_rational_system, read_system

    # a law that computes in floats (and the sequential law's --float path) reads plain rational
    # matrices, and the built-in scenes of rational data (built in Fractions), without SymPy (issue 15)
    floats = args.law in FLOAT_LAWS or (args.law == "sequential" and args.float and args.gaps is None)
    system = (read_rational_system(args) if floats and path is None else None) or read_system(args)
    if args.law == "all":
        given = {law: {k: v for k, v in _cli_options(law, args).items()} for law in LAWS}
        with float_range_guard(args):
            results = resolve_all(system, options=given)
        out = {"schema": _schema(), "law": "all", "scene": system.scene, "system": system.as_json(),
               "laws": {name: (r.as_json() if not isinstance(r, str) else {"refused": r})
                        for name, r in results.items()}}
    else:
        law = get_law(args.law)
        opts = _cli_options(args.law, args)
        law.check(system, opts)
        with float_range_guard(args):
            res = law.resolve(system, **opts)
        out = res.as_json()
        if args.law == "impulse-ratio" and opts.get("coupling"):
            from .resolve_impulse_ratio import coupling_details

            out["details"]["coupling_decision"] = coupling_details(system)
    if path is not None:
        _plot(args, system, out, path)
    return out


def _schema() -> str:
    from ..resolution import SCHEMA

    return SCHEMA


def _plot(args, system, out, path) -> None:
    from ..figures import resolve_figure

    if args.law == "all":
        from ..figures import laws_figure_from_json

        fig = laws_figure_from_json(out)
    else:
        fig = resolve_figure(args.law, system.M, system.H, system.v, out)[0]
    write_figure(fig, path)


# ------------------------------------------------------------------------------------ text
def _vec(xs) -> str:
    return "[" + ", ".join(map(str, xs)) + "]" if xs is not None else "-"


def _order(order, names) -> str:
    """An ordering with the contacts' names: ``1-2 > 2-3``; stages of simultaneous impacts in braces."""
    if order is None:
        return ""
    if isinstance(order, dict) and order.get("infinite"):  # inelastic collapse
        prefix = " > ".join(names[c] for c in order["prefix"])
        cycle = " > ".join(names[c] for c in order["cycle"])
        return "order " + (prefix + " > " if prefix else "") + f"({cycle}) repeated forever: inelastic collapse, the limit"
    if isinstance(order, dict):
        return f"alternating from {names[order['first']]} ({order['length']} impacts)"
    flat = [("{" + ",".join(names[c] for c in o) + "}") if isinstance(o, list) else names[o] for o in order]
    return "order " + " > ".join(flat) if flat else "no impact"


def render_one(result: dict) -> str:
    from ..lawbook import get_law

    law = result["law"]
    sysj = result["system"]
    e = sysj["restitution"]
    lines = [f"{law}: {get_law(law).title}"]
    head = f"exactness: {result['exactness']}" + (f" ({result['digits']} digits)" if result["digits"] else "")
    head += f"; outcome: {result['uniqueness']}; e = {e if e is not None else 'default (1)'}"
    lines.append(head)
    if result.get("scene"):
        lines.append("scene: " + ", ".join(f"{k}={v}" for k, v in result["scene"].items()))
    lines.append("contacts: " + ", ".join(sysj["contacts"]))
    lines.append(f"T- = {result['kinetic_energy_before']}")
    many = len(result["outcomes"]) > 1
    for i, o in enumerate(result["outcomes"], 1):
        tag = f"outcome {i}: " if many else ""
        extra = f", {o['orderings']} ordering(s)" if o.get("orderings") not in (None, 1) else ""
        ord_text = _order(o["order"], sysj["contacts"])
        lines.append(f"{tag}v+ = {_vec(o['velocity'])}  p = {_vec(o['impulses'])}  T+ = {o['kinetic_energy_after']}"
                     + (f"  ({ord_text}{extra})" if ord_text else ""))
    for s in result["selected"]:
        reading = result["details"].get("reading", "")
        lines.append(f"selected ({reading} reading): v+ = {_vec(s['velocity'])}")
    module_name = LAW_CLI[law].split(":")[0]
    lines += importlib.import_module(f"impactsym.cli.{module_name}").render(result)
    for n in result["notes"]:
        lines.append("note: " + n)
    lines.append(f"valid: {result['valid']}")
    for v in result["violations"]:
        lines.append("  violated: " + v["message"])
    return "\n".join(lines)


def render_all(result: dict) -> str:
    sysj = result["system"]
    lines = []
    if result.get("scene"):
        lines.append("scene: " + ", ".join(f"{k}={v}" for k, v in result["scene"].items()))
    lines.append(f"contacts: {', '.join(sysj['contacts'])}; v- = {_vec(sysj['velocity'])}")
    rows = [("law", "outcome", "v+", "T+", "valid")]
    for name, r in result["laws"].items():
        if "refused" in r:
            rows.append((name, r["refused"], "", "", ""))
            continue
        if r["velocity"] is not None:
            rows.append((name, r["uniqueness"], _vec(r["velocity"]), str(r["kinetic_energy_after"]), str(r["valid"])))
            continue
        for i, o in enumerate(r["outcomes"], 1):
            rows.append((name if i == 1 else "", f"{r['uniqueness']} {i}/{len(r['outcomes'])}", _vec(o["velocity"]),
                         str(o["kinetic_energy_after"]), str(o["valid"])))
    widths = [max(len(r[c]) for r in rows if not (c == 1 and r[2] == "" and r[0] != "law")) for c in range(5)]
    for r in rows:
        if r[2] == "" and r[0] != "law":
            lines.append(f"{r[0]:<{widths[0]}}  {r[1]}")
        else:
            lines.append("  ".join(f"{x:<{w}}" for x, w in zip(r, widths)).rstrip())
    return "\n".join(lines)


def render(result: dict) -> str:
    return render_all(result) if result.get("law") == "all" else render_one(result)
