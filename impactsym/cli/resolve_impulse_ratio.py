"""``impactsym resolve --law impulse-ratio``: the impulse-ratio law of Acary & Taha (eq. 38).

JSON: ``impulses``, ``velocity``, ``delta`` (``D = B² − 4AC``; ``delta_normalized`` is the
paper's Δ = D/B²), ``ratios``, ``coefficients``, ``valid``, ``violations``, each exact array with
its ``_float`` twin, and ``coupling`` (the ratios ``--coupling`` set to zero, with the reason).
Outside the law's domain the command exits with status 2 naming every violated condition,
unless ``--allow-invalid``.
"""

from __future__ import annotations

from ..laws.coupling import coupling_decision
from ..laws.impulse_ratio import impulse_ratio_law
from ..numbers import exact_str, parse_number
from .scene_args import read_scene, scene_json

__all__ = ["run", "render"]


def ratios_arg(text):
    if text is None:
        return None
    parts = [x.strip() for x in text.split(",")]
    return [parse_number(x, "ratios") for x in parts]


def run(args) -> dict:
    M, H, v, desc = read_scene(args)
    e = parse_number(args.restitution if args.restitution is not None else "1", "restitution")
    result = impulse_ratio_law(M, H, v, e, ratios_arg(args.ratios), allow_invalid=args.allow_invalid,
                               coupling=args.coupling)
    out = result.as_json()
    out["restitution"] = str(e)
    if args.coupling:
        d = coupling_decision(M, H, v)
        out["coupling_decision"] = {
            "participating": d.participating,
            "approaching": d.approaching,
            "cos_kinetic_angles": {f"{i + 1}-{j + 1}": exact_str(c) for (i, j), c in d.cosines.items()},
            "coupled": {f"{i + 1}-{j + 1}": c for (i, j), c in d.coupled.items()},
            "reachable_from_primary": d.reachable,
        }
    out.update(scene_json(desc))
    return out


def render(result: dict) -> str:
    lines = [f"impulse-ratio law (Acary & Taha eq. 38), e = {result['restitution']}, "
             f"ratios a = ({', '.join(result['ratios'])})"]
    if result.get("scene"):
        lines.append("scene: " + ", ".join(f"{k}={v}" for k, v in result["scene"].items()))
    for note in result.get("coupling", []):
        lines.append(f"coupling: {note['ratio']} set to 0 ({note['reason']}; cos theta = {note['cos_kinetic_angle']})")
    lines.append(f"D = B^2 - 4AC = {result['delta']}  (paper's normalized Delta = {result['delta_normalized']})")
    if result["impulses"] is None:
        lines.append("no real solution (D < 0)")
    else:
        lines.append("p  = [" + ", ".join(result["impulses"]) + "]")
        lines.append("v+ = [" + ", ".join(result["velocity"]) + "]")
    lines.append(f"valid: {result['valid']}")
    for v in result["violations"]:
        lines.append("  violated: " + v["message"])
    return "\n".join(lines)
