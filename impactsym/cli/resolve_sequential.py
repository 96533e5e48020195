"""What is specific to ``impactsym resolve --law sequential`` (Seghete & Murphey sec. III,
:func:`impactsym.laws.sequential.resolve_sequential`): its options (``--reading energy|cone``,
``--max-reflections K``, ``--float``, ``--two-surface-path closed-form|iterate``) and the lines of
its details.

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
from .scene_args import int_option

__all__ = ["options", "render"]


def options(args) -> dict:
    reading = args.reading if args.reading is not None else "energy"
    if reading not in READINGS:
        raise ImpactInputError("reading", f"must be one of {', '.join(READINGS)}, got {reading!r}")
    cap = None if args.max_reflections is None else int_option(args.max_reflections, "max_reflections", 1)
    path = args.two_surface_path if args.two_surface_path is not None else "closed-form"
    if path not in TWO_SURFACE_PATHS:
        raise ImpactInputError("two_surface_path", f"must be one of {', '.join(TWO_SURFACE_PATHS)}, got {path!r}")
    return {"reading": reading, "max_reflections": cap, "float": bool(args.float), "two_surface_path": path}


def render(result: dict) -> list[str]:
    d = result["details"]
    c = d["counts"]
    lines = [f"{d['method']}, {d['backend']} backend: {len(result['outcomes'])} distinct outcome(s) from "
             f"{c['orderings']} ordering(s); {c['states_visited']} states, {c['sign_tests']} sign tests, "
             f"{c['exact_fallbacks']} exact fallbacks"]
    if d["two_surface_bound"] is not None:
        lines.append(f"paper's bound N = ceil(S_total/(2 S_0)) = {d['two_surface_bound']}")
    return lines
