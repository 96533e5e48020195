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
    fast = _run_rational(args)
    if fast is not None:
        return fast
    from ..laws.reflection import reflect, reflection_map  # imported here: not needed for --help
    from ..numbers import exact_json

    M = matrix_arg(args.mass_matrix, "mass_matrix")
    u = vector_arg(args.gradient, "gradient")
    e = number_arg(args.restitution, "restitution")
    result = {"exact": True, "restitution": str(e)}
    G = reflection_map(M, u, e)
    matrix = exact_json("matrix", G)
    if G.cols == 1:  # a 1×1 map is a matrix of one row (exact_json flattens a column)
        matrix = {k: [x] for k, x in matrix.items()}
    result.update(matrix)
    if args.velocity is not None:
        v = vector_arg(args.velocity, "velocity")
        result.update(exact_json("velocity", reflect(M, u, v, e)))
    return result


def _run_rational(args) -> dict | None:
    """The result for input whose every entry is a plain rational (``2``, ``-1/3``, ``1.5``,
    ``1e-3``), computed, checked and verified in python-flint alone
    (:mod:`impactsym.laws.reflection_rational`): no SymPy or NumPy to import. ``None`` for anything
    else (``sqrt(2)``, a symbol, malformed text, input the law refuses): the general path then
    answers, and words every error as it always has. Both give the same output, byte for byte
    (``tests/test_cli_reflect_fast.py``)."""
    from ..arithmetic.literals import json_float, plain_matrix, plain_rational, plain_vector
    from ..errors import ImpactError

    M, u = plain_matrix(args.mass_matrix), plain_vector(args.gradient)
    try:
        e = plain_rational(args.restitution)
    except ZeroDivisionError:
        return None
    v = None if args.velocity is None else plain_vector(args.velocity)
    if M is None or u is None or e is None or (args.velocity is not None and v is None):
        return None
    from ..laws.reflection_rational import rational_reflection

    try:
        G, vplus, _ = rational_reflection(M, u, e, v)
    except ImpactError:
        return None
    n = G.nrows()

    def exact(x):
        return str(x), json_float(int(x.p), int(x.q))

    rows = [[exact(G[i, j]) for j in range(n)] for i in range(n)]
    result = {"exact": True, "restitution": str(_as_fmpq(e)),
              "matrix": [[s for s, _ in r] for r in rows], "matrix_float": [[f for _, f in r] for r in rows]}
    if vplus is not None:
        col = [exact(vplus[i, 0]) for i in range(n)]
        result.update(velocity=[s for s, _ in col], velocity_float=[f for _, f in col])
    return result


def _as_fmpq(q):
    """A ``Fraction`` as ``fmpq``, whose ``str`` is SymPy's (``"1/2"``, ``"-3"``)."""
    from flint import fmpq

    return fmpq(q.numerator, q.denominator)


def _fmt(rows) -> str:
    width = max(len(x) for r in rows for x in r)
    return "\n".join("  [" + ", ".join(x.rjust(width) for x in r) + "]" for r in rows)


def render(result: dict) -> str:
    out = [f"G_u(e) with e = {result['restitution']} (exact):", _fmt(result["matrix"])]
    if "velocity" in result:
        out += ["G_u(e) v =", _fmt([[x] for x in result["velocity"]])]
    return "\n".join(out)
