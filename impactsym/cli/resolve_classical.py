"""What is specific to ``impactsym resolve --law newton|poisson|energetic|han-gilmore`` (the
classical laws of Acary & Taha secs. 2.2 and 3.2): their options and the lines of their details.
The rest (reading the system, the outcome, the JSON schema) is the generic
:mod:`impactsym.cli.resolve` over :mod:`impactsym.lawbook`.

``details`` in JSON: Newton ``unique_impulse`` and ``other_impulses``; Poisson
``compression_impulses`` and ``compression_velocity``; energetic ``direction`` and ``delta``;
Han–Gilmore ``stages`` (each outcome's ``details.sequences`` lists every sequence of impact stages
that reaches it, 0-based contacts impacting together; ``order`` is the first of them).
"""

from __future__ import annotations

from .resolve_impulse_ratio import ratios_arg

__all__ = ["newton_options", "poisson_options", "energetic_options", "han_gilmore_options", "render"]


def newton_options(args) -> dict:
    return {"allow_invalid": bool(args.allow_invalid)}


def poisson_options(args) -> dict:
    return {"allow_invalid": bool(args.allow_invalid), "variant": args.variant or "paper"}


def energetic_options(args) -> dict:
    return {"allow_invalid": bool(args.allow_invalid), "ratios": ratios_arg(args.ratios)}


def han_gilmore_options(args) -> dict:
    return {}


def render(result: dict) -> list[str]:
    d = result["details"]
    lines = []
    if result["law"] == "han-gilmore":
        names = result["system"]["contacts"]
        for i, o in enumerate(result["outcomes"], 1):
            if len(o["details"]["sequences"]) > 1:
                seqs = "; ".join(" > ".join("{" + ",".join(names[c] for c in st) + "}" for st in s)
                                 for s in o["details"]["sequences"])
                lines.append(f"  outcome {i} via every one of: {seqs}")
    if d.get("unique_impulse") is False:
        lines.append("the impulse is not unique (v+ is): other impulses " + str(d.get("other_impulses")))
    if "compression_impulses" in d:
        lines.append(f"compression impulses p_c = [{', '.join(d['compression_impulses'])}]")
    if "direction" in d:
        lines.append(f"direction = [{', '.join(map(str, d['direction']))}], delta = {d.get('delta')}")
    return lines
