"""What is specific to ``impactsym resolve --law impulse-ratio`` (Acary & Taha eq. 38): its options
(``--ratios``, ``--coupling``, ``--allow-invalid``) and the lines of its details.

``details`` in JSON: ``delta`` (``D = B² − 4AC``), ``delta_normalized`` (the paper's Δ = D/B²),
``ratios``, ``coefficients``, ``real_solution``, ``coupling`` (the ratios ``--coupling`` set to
zero, with the reason) and, with ``--coupling``, ``coupling_decision``. Outside the law's domain
the command exits with status 2 naming every violated condition, unless ``--allow-invalid``.
"""

from __future__ import annotations

from ..numbers import exact_str, parse_number

__all__ = ["ratios_arg", "options", "coupling_details", "render"]


def ratios_arg(text):
    """``--ratios``: exact numbers ``"a,b"``, or a model ``from-hertz|from-linear|from-lzb``
    (:mod:`impactsym.lawbook_compliant`: the elastic model's impulse ratios, then eq. 38)."""
    if text is None:
        return None
    if str(text).strip().lower().startswith("from-"):
        from ..lawbook_compliant import ratio_source

        return ratio_source(str(text).strip())
    parts = [x.strip() for x in text.split(",")]
    return [parse_number(x, "ratios") for x in parts]


def options(args) -> dict:
    return {"ratios": ratios_arg(args.ratios), "allow_invalid": bool(args.allow_invalid),
            "coupling": bool(args.coupling)}


def coupling_details(system) -> dict:
    """The kinetic-angle coupling decision of the system (``--coupling``)."""
    from ..laws.coupling import coupling_decision

    d = coupling_decision(system.M, system.H, system.v)
    return {
        "participating": d.participating,
        "approaching": d.approaching,
        "cos_kinetic_angles": {f"{i + 1}-{j + 1}": exact_str(c) for (i, j), c in d.cosines.items()},
        "coupled": {f"{i + 1}-{j + 1}": c for (i, j), c in d.coupled.items()},
        "reachable_from_primary": d.reachable,
    }


def render(result: dict) -> list[str]:
    d = result["details"]
    lines = [f"ratios a = ({', '.join(d['ratios'])})"]
    src = d.get("ratio_source")
    if src:
        dist = src["kinetic_distance"]
        lines.append(f"ratios from the elastic {src['model']} model (rtol {src['model_tolerance']:g}); its v+ = "
                     f"[{', '.join(f'{x:.10g}' for x in src['model_velocity'])}]; kinetic-metric distance "
                     + ("-" if dist is None else f"{dist:.3g} ({src['kinetic_distance_relative']:.3g} of |v-|_M)"))
    for note in d.get("coupling", []):
        lines.append(f"coupling: {note['ratio']} set to 0 ({note['reason']}; cos theta = {note['cos_kinetic_angle']})")
    lines.append(f"D = B^2 - 4AC = {d['delta']}  (paper's normalized Delta = {d['delta_normalized']})")
    if not d["real_solution"]:
        lines.append("no real solution (D < 0)")
    return lines
