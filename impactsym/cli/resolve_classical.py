"""``impactsym resolve --law newton|poisson|energetic|han-gilmore``: the classical laws of
Acary & Taha secs. 2.2 and 3.2 on the same scenes as the impulse-ratio law.

JSON (every law): ``impulses``, ``velocity``, ``energy_before``, ``energy_after`` (exact strings
and ``_float`` twins), ``valid``, ``violations``, ``notes``; Newton also ``unique_impulse`` and
``other_impulses``; Poisson ``compression_impulses``; energetic ``direction`` and ``delta``;
Han–Gilmore ``outcomes`` (each with its ``sequences`` of impact stages; ``impulses`` and
``velocity`` are those of the first outcome).
"""

from __future__ import annotations

from ..laws import classical
from ..numbers import parse_number
from .resolve_impulse_ratio import ratios_arg
from .scene_args import read_scene, scene_json

__all__ = ["run_newton", "run_poisson", "run_energetic", "run_han_gilmore", "render"]


def _common(args, *, vector_e=False):
    # which options apply to which law is checked once, by impactsym.cli.resolve.check_options
    M, H, v, desc = read_scene(args)
    text = args.restitution if args.restitution is not None else "1"
    if vector_e and "," in text:
        e = [parse_number(x, "restitution") for x in text.split(",")]
    else:
        e = parse_number(text, "restitution")
    return M, H, v, e, desc


def _out(result, e, desc):
    out = result.as_json()
    out["restitution"] = [str(x) for x in e] if isinstance(e, list) else str(e)
    out.update(scene_json(desc))
    return out


def run_newton(args) -> dict:
    M, H, v, e, desc = _common(args)
    return _out(classical.newton_moreau(M, H, v, e, allow_invalid=args.allow_invalid), e, desc)


def run_poisson(args) -> dict:
    M, H, v, e, desc = _common(args, vector_e=True)
    return _out(classical.poisson(M, H, v, e, variant=args.variant or "paper", allow_invalid=args.allow_invalid), e, desc)


def run_energetic(args) -> dict:
    M, H, v, e, desc = _common(args)
    return _out(classical.energetic(M, H, v, e, ratios_arg(args.ratios), allow_invalid=args.allow_invalid), e, desc)


def run_han_gilmore(args) -> dict:
    M, H, v, e, desc = _common(args)
    return _out(classical.han_gilmore(M, H, v, e), e, desc)


def render(result: dict) -> str:
    lines = [f"{result['law']} law, e = {result['restitution']}"]
    if result.get("scene"):
        lines.append("scene: " + ", ".join(f"{k}={v}" for k, v in result["scene"].items()))
    if result["law"] == "han-gilmore":
        for i, o in enumerate(result["outcomes"], 1):
            seqs = "; ".join(" -> ".join("{" + ",".join(map(str, st)) + "}" for st in s) for s in o["sequences"])
            lines.append(f"outcome {i}: v+ = [{', '.join(o['velocity'])}]  p = [{', '.join(o['impulses'])}]  "
                         f"T+ = {o['energy_after']}  via {seqs}")
        if result.get("unterminated"):
            lines.append(f"{len(result['unterminated'])} sequence(s) cut at the stage cap (still approaching)")
        return "\n".join(lines)
    lines.append("p  = [" + ", ".join(result["impulses"]) + "]")
    lines.append("v+ = [" + ", ".join(result["velocity"]) + "]")
    lines.append(f"T- = {result['energy_before']}, T+ = {result['energy_after']}")
    for n in result.get("notes", []):
        lines.append("note: " + n)
    lines.append(f"valid: {result['valid']}")
    for v in result["violations"]:
        lines.append("  violated: " + v["message"])
    return "\n".join(lines)
