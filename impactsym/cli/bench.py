"""``impactsym bench``: speed versus error of every evaluation path (see :mod:`impactsym.bench`).

``--quick`` measures chain3, the impulse-ratio root and reflect_2 with smaller batches (about a
minute); the full run (all formulas, batches of 10⁶) is what ``benchmarks/run.py`` commits under
``benchmarks/results/``.

``--law NAME`` (or ``all``) measures instead how the cost of a law grows with its problem (balls of a
cradle, dimension of a dense M, digits of the numbers, the reflection count of two surfaces), on the
exact and the float path: time and peak memory per size and the fitted growth
(:mod:`impactsym.cost_model`; ``--out DIR`` writes the table, JSON and plots;
``benchmarks/cost_model.py`` commits every law's).
"""

from __future__ import annotations

import sys

from ..errors import ImpactInputError
from .common import add_json_flag, refuse_inapplicable
from .plot import add_plot_option, plot_path


def register(sub) -> None:
    p = sub.add_parser("bench", help="throughput and error of SymPy, mpmath, lambdify, NumPy and C evaluation; "
                                     "--law: the cost model of a law",
                       description="Measure every backend on every formula, on a uniform sample of the valid "
                                   "domain and on the hard-case set. With --law: how the time and peak memory of "
                                   "a law grow with its problem (balls, dimension, digits, reflection count), "
                                   "exact and float paths, with the fitted growth.")
    p.add_argument("--quick", action="store_true", help="three formulas, smaller batches (about a minute); "
                                                        "with --law: the small sizes")
    p.add_argument("--formula", action="append", metavar="NAME", help="restrict to a formula (kernel name); repeatable")
    p.add_argument("--law", metavar="NAME", help="instead: the cost model of one law (a name of the lawbook: "
                                                 "sequential, two-surface, newton, ..., lzb), or all")
    p.add_argument("--axis", metavar="NAME", help="with --law: only this axis (balls, approaching, dimension, "
                                                  "digits, reflections; which ones a law has depends on the law)")
    p.add_argument("--sizes", metavar="N,N,...", help="with --law and one axis: the problem sizes (balls, "
                                                      "dimension, digits; for reflections d of the mass ratio 1:100^d)")
    p.add_argument("--out", metavar="DIR", help="with --law: write cost_model.md, cost_model.json and "
                                                "cost_model/<law>.png into DIR (checked before the work); a "
                                                "cost model already there keeps the other laws' tables")
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
    from .common import writable_dir
    from .. import cost_model

    refuse_inapplicable(args, args._bench_parser, ("law", "axis", "sizes", "quick", "out"),
                        "--law (the cost model of a law)")
    if args.law != "all" and args.law not in cost_model.COST_LAWS:
        raise ImpactInputError("law", f"unknown {args.law!r}; known: {', '.join(cost_model.COST_LAWS)}, or all")
    laws = list(cost_model.COST_LAWS) if args.law == "all" else [args.law]
    sizes = _sizes_arg(args.sizes)
    if (args.axis is not None or sizes is not None) and len(laws) > 1:
        raise ImpactInputError("axis" if args.axis is not None else "sizes", "applies to one law, not --law all")
    out = writable_dir(args.out, "out")
    if out is not None:
        cost_model.read_results(out)  # a cost_model.json there that is not ours: refused before the work
    axes = None if args.axis is None else [args.axis]
    if laws and (axes or sizes):  # checked before the work: an unknown axis, sizes out of range
        cost_model.check_request(laws[0], axes, sizes)
    progress = None if args.json else (lambda line: sys.stderr.write(line + "\n"))
    report = cost_model.run(laws, quick=args.quick, progress=progress, axes=axes, sizes=sizes)
    if out is not None:
        cmd = "impactsym bench --law " + args.law + (" --quick" if args.quick else "")
        for path in cost_model.write_results(report, out, cmd):
            if not args.json:
                sys.stderr.write(f"wrote {path}\n")
    return {"cost_model": report}


def run(args) -> dict:
    import warnings

    if args.law is not None:
        return run_law(args)
    for opt in ("sizes", "axis", "out"):
        if getattr(args, opt) is not None:
            raise ImpactInputError(opt, "applies with --law only")

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

        return markdown(result["cost_model"])
    from ..bench import table

    return table(result)
