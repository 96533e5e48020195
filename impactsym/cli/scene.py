"""``impactsym scene show FILE|NAME [--json] [scene parameters]`` and ``impactsym scene list``.

``show`` prints what a scene reduces to: ``M``, ``H``, ``v`` (exact), the closed contacts and
which of them approach (``H v < 0``, decided exactly), the kinetic angles between contacts, and
the per-contact restitution. ``FILE|NAME`` is a built-in scene (``chain3``, ``pool``, ``cradle``,
..., with its parameters ``--masses``, ``--velocities``, ``--theta``, ``--tau``, ``--n-balls``,
``--strikers``), a shipped scene file by name, or a path to a ``.toml``/``.json`` scene file
(format: :mod:`impactsym.scenes.fileformat`).

``show --json`` is a scene file itself: written to a ``.json`` file it loads back
(:func:`impactsym.scenes.load_scene`) to the same ``M``, ``H``, ``v``, exactly. Its keys are those of
:func:`impactsym.scenes.scene_to_dict` (``format``, ``name``, ``description``, ``source``,
``coordinates``, ``contacts``, ``mass_matrix``, ``gradients``, ``velocity``, ``restitution`` when
stated, ``bodies``/``walls`` when known), the float twins ``mass_matrix_float``,
``gradients_float``, ``velocity_float``, ``restitution_float``, and ``reduced``
(:func:`impactsym.scenes.describe_scene`, plus ``scene``: the built-in's parameters).

``list`` lists the built-in scenes (name, parameters, description) and the shipped files (name,
description, source, file).
"""

from __future__ import annotations

import argparse

from .common import add_json_flag

__all__ = ["register", "run_show", "run_list", "render"]

#: scene parameter -> (metavar, help)
PARAM_HELP = {
    "masses": ("M1,M2,...", "masses (chain3, two-balls-wall, three-ball-cradle, cradle, balls-against-wall)"),
    "velocities": ("V1,V2,...", "velocities (chain3, two-balls-wall, three-ball-cradle, balls-against-wall)"),
    "theta": ("T", "pool angle theta in [0, 2*pi/3] (pool; required there)"),
    "tau": ("TAU", "incidence angle tau (pool, bernoulli)"),
    "n_balls": ("N", "number of balls (cradle, balls-against-wall)"),
    "strikers": ("K", "number of striking balls (cradle)"),
}


def register(sub) -> None:
    p = sub.add_parser(
        "scene",
        help="show what a scene reduces to (M, H, v, contacts, kinetic angles), or list the scenes",
        description="Show what a scene (built-in, shipped file or scene file) reduces to, or list the scenes.",
    )
    actions = p.add_subparsers(dest="action", metavar="ACTION", parser_class=type(p))
    actions.required = True
    show = actions.add_parser(
        "show",
        help="M, H, v, closed and approaching contacts, kinetic angles, restitution of one scene",
        description=("Print what the scene reduces to: M, H, v (exact), the closed contacts and which approach "
                     "(H v < 0, decided exactly), the kinetic angles between contacts, the restitution per contact. "
                     "With --json the output is itself a scene file (it loads back to the same M, H, v)."),
    )
    show.add_argument("scene", metavar="FILE|NAME",
                      help="a built-in scene, a shipped scene file (impactsym scene list) or a .toml/.json path")
    from .scene_args import ALL_PARAMS  # the light copy: the registry imports SymPy

    for name in ALL_PARAMS:
        metavar, text = PARAM_HELP[name]
        show.add_argument("--" + name.replace("_", "-"), dest=name, metavar=metavar, help=text)
    add_json_flag(show)
    show.add_argument("--timeout", metavar="SECONDS", default=argparse.SUPPRESS,
                      help="stop with exit status 2 if the work takes longer than SECONDS")
    show.set_defaults(func=run_show)
    lst = actions.add_parser("list", help="the built-in scenes and the shipped scene files",
                             description="List the built-in scenes (with their parameters) and the shipped scene files.")
    add_json_flag(lst)
    lst.add_argument("--timeout", metavar="SECONDS", default=argparse.SUPPRESS,
                     help="stop with exit status 2 if the work takes longer than SECONDS")
    lst.set_defaults(func=run_list)


def run_show(args) -> dict:
    from ..numbers import exact_json
    from ..scenes import describe_scene, load_scene, scene_to_dict
    from ..scenes.registry import ALL_PARAMS

    params = {name: getattr(args, name, None) for name in ALL_PARAMS}
    scene = load_scene(args.scene, params)
    out = scene_to_dict(scene)
    twins = {}
    for key, value in (("mass_matrix", scene.M), ("gradients", scene.H), ("velocity", scene.v)):
        twins[key + "_float"] = _floats(value, scene.exact)
    if scene.restitution is not None:
        twins["restitution_float"] = [exact_json("e", e)["e_float"] for e in scene.restitution]
    ordered = {}
    for key, value in out.items():  # each twin right after its exact key
        ordered[key] = value
        if key + "_float" in twins:
            ordered[key + "_float"] = twins[key + "_float"]
    reduced = describe_scene(scene)
    if scene.meta.get("scene_json") is not None:
        reduced["scene"] = scene.meta["scene_json"]
    ordered["reduced"] = reduced
    return ordered


def _floats(value, exact: bool):
    import numpy as np
    import sympy as sp

    if exact:
        rows = value.tolist()
        if value.cols == 1:
            return [float(sp.N(x, 17)) for x in value]
        return [[float(sp.N(x, 17)) for x in row] for row in rows]
    arr = np.asarray(value, dtype=float)
    return arr.tolist()


def run_list(args) -> dict:
    from ..scenes.reading import read_scene_file  # the standard library only: no SymPy to list
    from ..scenes.registry import BUILTIN_SCENES, SCENE_PARAMS, SHIPPED_SCENES

    builtin = [{"name": name, "params": list(SCENE_PARAMS[name]), "description": text}
               for name, text in BUILTIN_SCENES.items()]
    shipped = []
    for name, path in SHIPPED_SCENES.items():
        d = read_scene_file(path)
        shipped.append({"name": name, "description": d.get("description"), "source": d.get("source"),
                        "file": path.name})
    return {"builtin": builtin, "shipped": shipped}


def _row(values) -> str:
    return "[" + ", ".join(str(x) for x in values) + "]"


def render(result: dict) -> str:
    if "builtin" in result and "shipped" in result:
        return _render_list(result)
    return _render_show(result)


def _render_list(result: dict) -> str:
    lines = ["built-in scenes (impactsym scene show NAME [parameters]):"]
    for s in result["builtin"]:
        params = " ".join("--" + p.replace("_", "-") for p in s["params"])
        lines.append(f"  {s['name']:<20} {s['description']}")
        lines.append(f"  {'':<20} parameters: {params}")
    lines += ["", "shipped scene files (impactsym scene show NAME):"]
    for s in result["shipped"]:
        lines.append(f"  {s['name']:<34} {s['description']}")
    return "\n".join(lines)


def _render_show(r: dict) -> str:
    red = r["reduced"]
    title = r.get("name") or "scene"
    lines = [f"scene {title}" + (f": {r['description']}" if r.get("description") else "")]
    if r.get("source"):
        lines.append(f"source: {r['source']}")
    if red.get("scene"):
        lines.append("parameters: " + ", ".join(f"{k}={v}" for k, v in red["scene"].items() if k != "scene"))
    lines.append(f"{'exact' if red['exact'] else 'float'}; {red['n']} coordinates ({', '.join(r['coordinates'])}), "
                 f"{red['k']} closed contact(s)")
    if red.get("uninvolved_bodies"):
        lines.append(f"balls in no closed contact (left out of M): {', '.join(map(str, red['uninvolved_bodies']))}")
    lines.append("M =")
    lines += [f"  {_row(row)}" for row in r["mass_matrix"]]
    lines.append("H =")
    lines += [f"  {_row(row)}   {name}" for row, name in zip(r["gradients"], r["contacts"])]
    lines.append(f"v = {_row(r['velocity'])}")
    lines.append(f"kinetic energy T = {red['kinetic_energy']}")
    lines.append("contacts (w = H v):")
    rest = r.get("restitution")
    for i, (name, w, state) in enumerate(zip(r["contacts"], red["relative_velocity"], red["contact_states"])):
        e = f", e = {rest[i]}" if rest is not None else ""
        lines.append(f"  {name}: w = {w} ({state}){e}")
    if rest is None:
        lines.append("restitution: not stated by the scene")
    lines.append("kinetic angles (cos theta_ij = H_i M^-1 H_j^T / sqrt(...)):")
    for a in red["kinetic_angles"]:
        lines.append(f"  {a['contacts'][0]} / {a['contacts'][1]}: cos = {a['cos']}, theta = {a['angle']} "
                     f"({a['angle_float'] * 180 / 3.141592653589793:.4g} deg){', coupled' if a['coupled'] else ''}")
    if red["orthogonal_pairs"]:
        lines.append(f"  {red['orthogonal_pairs']} other pair(s) orthogonal (cos = 0, theta = pi/2)")
    if not red["kinetic_angles"] and not red["orthogonal_pairs"]:
        lines.append("  (one contact: no pair)")
    return "\n".join(lines)
