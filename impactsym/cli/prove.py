"""``impactsym prove``: machine-checked properties of ``G_u`` for n = 2, 3 and general n."""

from __future__ import annotations

from .common import add_json_flag

#: the largest explicit dimension proved (dimension 4 took 103 s; the general-n proofs cover it)
MAX_DIMENSION = 3


def register(sub) -> None:
    p = sub.add_parser(
        "prove",
        help="prove G^2=I, G^TMG=M, det(G)=-1 and more, for n = 2, 3 and general n",
        description="Run the SymPy proofs of derivations/reflection.py and report each with its cost.",
    )
    p.add_argument("--dimension", action="append", metavar="D",
                   help='restrict to dimension D (1, 2, 3 or "n"); repeatable')
    p.add_argument("--property", action="append", metavar="NAME", help="restrict to one property; repeatable")
    add_json_flag(p)
    p.set_defaults(func=run)


def run(args) -> dict:
    from derivations.reflection import PROPERTIES, prove_all

    from ..errors import ImpactInputError

    dims = [2, 3, "n"]
    if args.dimension:
        dims = []
        for d in args.dimension:
            if d == "n":
                dims.append("n")
            elif d.strip().isdigit() and 1 <= int(d) <= MAX_DIMENSION:
                dims.append(int(d))
            else:
                raise ImpactInputError("dimension", f'must be 1, 2, 3 or "n", got {d!r} (the "n" proofs hold '
                                       f'for every dimension; an explicit dimension above {MAX_DIMENSION} takes '
                                       f'minutes of symbolic algebra)')
    names = args.property or list(PROPERTIES)
    for nm in names:
        if nm not in PROPERTIES:
            raise ImpactInputError("property", f"unknown {nm!r}; known: {', '.join(PROPERTIES)}")
    results = prove_all(dims, names)
    return {"properties": [r.as_dict() for r in results],
            "all_proven": all(r.proven for r in results)}


def render(result: dict) -> str:
    rows = result["properties"]
    w = max(len(r["name"]) for r in rows)
    out = [f"{'property'.ljust(w)}  dim  proven  seconds  method"]
    for r in rows:
        out.append(f"{r['name'].ljust(w)}  {str(r['dimension']).ljust(3)}  {str(r['proven']).ljust(6)}  "
                   f"{r['seconds']:7.3f}  {r['method'].split(':')[0].split('(')[0].strip()}")
    out.append(f"all proven: {result['all_proven']}")
    return "\n".join(out)
