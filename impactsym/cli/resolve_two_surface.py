"""``impactsym resolve --law two-surface``: a two-surface impact resolved in O(1)
(Seghete & Murphey sec. III-B, III-C; :mod:`impactsym.laws.two_surface`).

Takes ``--mass-matrix``, ``--gradients`` (exactly two rows) and ``--velocity``, or a canonical
scene with two contacts (``--scene chain3`` or ``pool``). JSON: ``outcomes`` (one per first
surface that the velocity approaches: ``order``, ``reflections``, ``velocity`` and
``velocity_float``, ``exact``, ``digits``), ``bound`` (the paper's ``N = ⌈π/β⌉``), ``wedge_angle``,
``kinetic_angle_cos``, ``decisions``. An ordering longer than 10000 is given as
``{"first", "length", "alternating": true}``. The law is elastic: ``--restitution`` other than 1
is refused.
"""

from __future__ import annotations

from ..errors import ImpactInputError
from ..laws.two_surface import resolve_two_surfaces
from ..numbers import parse_number
from .scene_args import float_range_guard, read_scene, scene_json

__all__ = ["run", "render"]


def run(args) -> dict:
    if args.restitution is not None and parse_number(args.restitution, "restitution") != 1:
        raise ImpactInputError("restitution", "the two-surface law is elastic (sequential G_u): e must be 1")
    M, H, v, desc = read_scene(args)
    out = {"law": "two-surface"}
    with float_range_guard(args):
        out.update(resolve_two_surfaces(M, H, v).as_dict())
    out.update(scene_json(desc))
    return out


def render(result: dict) -> str:
    lines = [f"two-surface law (Seghete & Murphey sec. III): wedge beta = {result['wedge_angle']} rad, "
             f"cos(kinetic angle) = {result['kinetic_angle_cos']}, bound N = ceil(pi/beta) = {result['bound']}"]
    for o in result["outcomes"]:
        order = o["order"]
        if isinstance(order, dict):
            order = f"[{order['first']}, {1 - order['first']}, ...] ({order['length']} surfaces)"
        kind = "exact" if o["exact"] else f"{o['digits']} certified digits" if o["digits"] else "float"
        if o.get("no_impact") or o["first"] in (-1, None):  # neither surface is approached
            lines.append("no surface is approached: no impact (0 reflections), v+ = v-")
        else:
            lines.append(f"first surface {o['first']}: {o['reflections']} reflections, order {order}")
        lines.append(f"  v+ = [{', '.join(o['velocity'] if isinstance(o['velocity'][0], str) else map(str, o['velocity']))}]  ({kind})")
    return "\n".join(lines)
