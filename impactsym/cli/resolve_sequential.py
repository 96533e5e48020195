"""What is specific to ``impactsym resolve --law sequential`` (Seghete & Murphey sec. III,
:func:`impactsym.laws.sequential.resolve_sequential`): its options (``--reading energy|cone``,
``--max-reflections K``, ``--float``, ``--two-surface-path auto|closed-form|iterate``, ``--gaps
g1,g2,…``) and the lines of its details. ``--restitution`` takes one coefficient or one per contact
(``G_u(e)`` per impact; :func:`~impactsym.laws.sequential.resolve_sequential`).

``details`` in JSON: ``backend``, ``method``, ``reading``, ``approaching``, ``two_surface_bound``
(the paper's ``N = ⌈S_total/(2 S_0)⌉`` for two independent contacts) and ``counts``
(``orderings``, ``states_visited``, ``sign_tests``, ``exact_fallbacks``, ``max_reflections_used``).
Each outcome: ``order`` (a representative ordering), ``orderings`` (how many give it),
``details.reflections``, ``reflections_min``, ``reflections_max``. ``selected`` holds the
selection's velocities (ties are all listed).
"""

from __future__ import annotations

from ..errors import ImpactInputError
from ..laws.sequential import READINGS, TWO_SURFACE_PATHS

__all__ = ["options", "render"]


def options(args) -> dict:
    reading = args.reading  # None: energy when elastic, cone when some e < 1 (the law decides)
    if reading is not None and reading not in READINGS:
        raise ImpactInputError("reading", f"must be one of {', '.join(READINGS)}, got {reading!r}")
    from ..scenes.registry import int_option

    cap = None if args.max_reflections is None else int_option(args.max_reflections, "max_reflections", 1)
    path = args.two_surface_path if args.two_surface_path is not None else "auto"
    if path not in TWO_SURFACE_PATHS:
        raise ImpactInputError("two_surface_path", f"must be one of {', '.join(TWO_SURFACE_PATHS)}, got {path!r}")
    gaps = None if args.gaps is None else _gaps(args.gaps)
    return {"reading": reading, "max_reflections": cap, "float": bool(args.float), "two_surface_path": path,
            "gaps": gaps}


def _gaps(text):
    from ..numbers import parse_vector

    return list(parse_vector(text, "gaps"))


def render(result: dict) -> list[str]:
    d = result["details"]
    if "gaps" in d:
        return [f"{d['method']}: gaps [{', '.join(d['gaps'])}], impacts at t = [{', '.join(d['times'])}]"]
    c = d["counts"]
    lines = [f"{d['method']}, {d['backend']} backend: {len(result['outcomes'])} distinct outcome(s) from "
             f"{c['orderings']} ordering(s); {c['states_visited']} states, {c['sign_tests']} sign tests, "
             f"{c['exact_fallbacks']} exact fallbacks"]
    if d["two_surface_bound"] is not None:
        lines.append(f"paper's bound N = ceil(S_total/(2 S_0)) = {d['two_surface_bound']}")
    return lines
