"""``impactsym reflect``: the single-impact map ``G_u(e)`` and ``G_u(e) v``."""

from __future__ import annotations

from .common import add_json_flag, matrix_arg, number_arg, vector_arg


def register(sub) -> None:
    p = sub.add_parser(
        "reflect",
        help="single-impact map G_u(e) = I - (1+e) M^-1 u^T u/(u M^-1 u^T)",
        description="Print G_u (and G_u v), exactly for exact input (Seghete & Murphey sec. II-A).",
    )
    p.add_argument("--mass-matrix", required=True, metavar="M", help='mass matrix, "a,b;c,d" (exact entries)')
    p.add_argument("--gradient", required=True, metavar="u", help='gradient covector u = Dphi, "a,b"')
    p.add_argument("--velocity", metavar="v", help='pre-impact velocity, "a,b"')
    p.add_argument("--restitution", default="1", metavar="e", help="Newton restitution e in [0, 1] (default 1)")
    add_json_flag(p)
    p.set_defaults(func=run)


def run(args) -> dict:
    from ..laws.reflection import reflect, reflection_map  # imported here: not needed for --help
    from ..numbers import exact_json

    M = matrix_arg(args.mass_matrix, "mass_matrix")
    u = vector_arg(args.gradient, "gradient")
    e = number_arg(args.restitution, "restitution")
    result = {"exact": True, "restitution": str(e)}
    result.update(exact_json("matrix", reflection_map(M, u, e)))
    if args.velocity is not None:
        v = vector_arg(args.velocity, "velocity")
        result.update(exact_json("velocity", reflect(M, u, v, e)))
    return result


def _fmt(rows) -> str:
    width = max(len(x) for r in rows for x in r)
    return "\n".join("  [" + ", ".join(x.rjust(width) for x in r) + "]" for r in rows)


def render(result: dict) -> str:
    out = [f"G_u(e) with e = {result['restitution']} (exact):", _fmt(result["matrix"])]
    if "velocity" in result:
        out += ["G_u(e) v =", _fmt([[x] for x in result["velocity"]])]
    return "\n".join(out)
