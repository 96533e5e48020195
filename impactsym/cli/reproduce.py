"""``impactsym reproduce``: the main job, an audit of both papers.

For now it reports what the foundation derives and checks: the single-impact derivation of
Seghete & Murphey sec. II-A compared with the printed ``λ`` and ``G_u``, and the machine-checked
properties of ``G_u`` for n = 2, 3 and general n.
"""

from __future__ import annotations

from .common import add_json_flag


def register(sub) -> None:
    p = sub.add_parser("reproduce", help="audit the papers' equations and examples (the main job)")
    add_json_flag(p)
    p.set_defaults(func=run)


def run(args):
    from derivations.reflection import derive_restitution, derive_single_impact, prove_all

    derivations = []
    for n in (2, 3):
        d = derive_single_impact(n)
        derivations.append({"law": "G_u (elastic, eqs. 1a-1b)", "dimension": n,
                            "lambda_matches_printed": d.matches_printed_lambda,
                            "G_matches_printed": d.matches_printed_G,
                            "discarded_roots": [str(r) for r, _ in d.discarded_roots],
                            "seconds": round(d.seconds, 3)})
        r = derive_restitution(n)
        derivations.append({"law": "G_u(e) (Newton restitution)", "dimension": n,
                            "lambda_matches_printed": r.matches_printed_lambda,
                            "G_matches_printed": r.matches_printed_G,
                            "energy_loss_matches": r.matches_printed_energy_loss,
                            "seconds": round(r.seconds, 3)})
    proofs = [p.as_dict() for p in prove_all()]
    ok = all(p["proven"] for p in proofs) and all(
        d["lambda_matches_printed"] and d["G_matches_printed"] for d in derivations)
    return {"derivations": derivations, "properties": proofs, "all_checks_pass": ok}, (0 if ok else 1)


def render(result: dict) -> str:
    out = ["Seghete & Murphey sec. II-A: single impact derived by SymPy"]
    for d in result["derivations"]:
        extra = f", energy loss matches: {d['energy_loss_matches']}" if "energy_loss_matches" in d else ""
        out.append(f"  {d['law']:<28} n={d['dimension']}: lambda matches print: {d['lambda_matches_printed']}, "
                   f"G matches print: {d['G_matches_printed']}{extra}  ({d['seconds']} s)")
    out.append("Properties of G_u (machine-checked):")
    for p in result["properties"]:
        out.append(f"  {p['name']:<42} n={str(p['dimension']):<2} proven={p['proven']}  ({p['seconds']:.3f} s)")
    out.append(f"all checks pass: {result['all_checks_pass']}")
    return "\n".join(out)
