"""What is specific to ``impactsym resolve --law two-surface`` (Seghete & Murphey sec. III-B,
III-C; :mod:`impactsym.laws.two_surface`): no options, and the lines of its details.

``details`` in JSON: ``bound`` (the paper's ``N = ⌈π/β⌉``), ``wedge_angle``, ``kinetic_angle_cos``
(each with a ``_float`` twin) and ``decisions``. Each outcome is one branch (by first surface):
``order`` (an ordering longer than 10000 is given as ``{"first", "length", "alternating": true}``),
``details.reflections``, ``details.first``; certified outcomes carry ``digits``. The law is
elastic: ``--restitution`` other than 1 is refused.
"""

from __future__ import annotations

__all__ = ["options", "render"]


def options(args) -> dict:
    return {}


def render(result: dict) -> list[str]:
    d = result["details"]
    lines = ["no surface is approached: no impact (0 reflections), v+ = v-"
             for o in result["outcomes"] if o["details"].get("no_impact")]
    return lines + [f"wedge beta = {d['wedge_angle']} rad, cos(kinetic angle) = {d['kinetic_angle_cos']}, "
            f"bound N = ceil(pi/beta) = {d['bound']}"]
