"""``impactsym bench``: speed versus error of every evaluation path (see :mod:`impactsym.bench`).

``--quick`` measures chain3, the impulse-ratio root and reflect_2 with smaller batches (about a
minute); the full run (all formulas, batches of 10⁶) is what ``benchmarks/run.py`` commits under
``benchmarks/results/``.

``--law NAME`` measures instead how the cost of one law grows with its problem (contacts and
coordinates of a cradle, the reflection count of two surfaces): time and peak memory per size and
the fitted exponent (:mod:`impactsym.cost_model`; ``benchmarks/cost_model.py`` commits every law's).
"""

from __future__ import annotations

import sys

from ..errors import ImpactInputError
from .common import add_json_flag, refuse_inapplicable
from .plot import add_plot_option, plot_path


def register(sub) -> None:
    p = sub.add_parser("bench", help="throughput and error of SymPy, mpmath, lambdify, NumPy and C evaluation",
                       description="Measure every backend on every formula, on a uniform sample of the valid "
                                   "domain and on the hard-case set.")
    p.add_argument("--quick", action="store_true", help="three formulas, smaller batches (about a minute)")
    p.add_argument("--formula", action="append", metavar="NAME", help="restrict to a formula (kernel name); repeatable")
    p.add_argument("--law", metavar="NAME", help="instead: the cost model of one law (sequential, two-surface, newton, "
                                                 "poisson, energetic, han-gilmore, impulse-ratio)")
    p.add_argument("--sizes", metavar="N,N,...", help="with --law: the problem sizes (balls; for two-surface d of "
                                                      "the mass ratio 1:100^d)")
    add_plot_option(p, "the log-log plot of throughput against error")
    add_json_flag(p)
    p.set_defaults(func=run, _bench_parser=p)


def _sizes_arg(text: str | None):
    if text is None:
        return None
    try:
        sizes = tuple(int(x) for x in text.split(","))
    except ValueError:
        raise ImpactInputError("sizes", f"must be comma-separated positive integers, got {text!r}") from None
    if not sizes or any(n < 1 for n in sizes):
        raise ImpactInputError("sizes", f"must be comma-separated positive integers, got {text!r}")
    return sizes


def run_law(args) -> dict:
    from .. import cost_model

    refuse_inapplicable(args, args._bench_parser, ("law", "sizes", "quick"), "--law (the cost model of one law)")
    if args.law not in cost_model.LAWS:
        raise ImpactInputError("law", f"unknown {args.law!r}; known: {', '.join(cost_model.LAWS)}")
    sizes = _sizes_arg(args.sizes) or (cost_model.QUICK_SIZES if args.quick else cost_model.DEFAULT_SIZES)[args.law]
    if args.law == "sequential" and max(sizes) > 40:
        raise ImpactInputError("sizes", "sequential: at most 40 balls here (the search is exact)")
    if args.law == "two-surface" and max(sizes) > 200:
        raise ImpactInputError("sizes", "two-surface: d at most 200 (mass ratio 1:100^d)")
    if args.law != "two-surface" and max(sizes) > 64:
        raise ImpactInputError("sizes", f"{args.law}: at most 64 balls here")
    if args.law != "two-surface" and min(sizes) < 2:
        raise ImpactInputError("sizes", "a cradle needs at least 2 balls")
    return {"cost_model": cost_model.law_cost(args.law, sizes)}


def run(args) -> dict:
    import warnings

    if args.law is not None:
        return run_law(args)
    if args.sizes is not None:
        raise ImpactInputError("sizes", "applies with --law only")

    from .. import bench as benchmark

    path = plot_path(args)  # checked before the (long) work
    formulas = None
    if args.formula:
        for f in args.formula:
            if f.replace("-", "_") not in benchmark.FORMULAS:
                raise ImpactInputError("formula", f"unknown {f!r}; known: {', '.join(benchmark.FORMULAS)}")
        formulas = tuple(f.replace("-", "_") for f in args.formula)
    progress = None if args.json else (lambda r: sys.stderr.write(
        f"  {r['formula']:24s} {r['case_set']:8s} {r['backend']:15s} {r['evals_per_second']:10.3g} evals/s\n"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = benchmark.run(quick=args.quick, formulas=formulas, progress=progress)
    if path is not None:
        benchmark.plot(result, path)
    return result


def render(result: dict) -> str:
    if "cost_model" in result:
        from ..cost_model import markdown

        return markdown([result["cost_model"]])
    from ..bench import table

    return table(result)
