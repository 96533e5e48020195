"""``impactsym bench``: speed versus error of every evaluation path (see :mod:`impactsym.bench`).

``--quick`` measures chain3, the impulse-ratio root and reflect_2 with smaller batches (about a
minute); the full run (all formulas, batches of 10⁶) is what ``benchmarks/run.py`` commits under
``benchmarks/results/``.
"""

from __future__ import annotations

import sys

from ..errors import ImpactInputError
from .common import add_json_flag
from .plot import add_plot_option, plot_path


def register(sub) -> None:
    p = sub.add_parser("bench", help="throughput and error of SymPy, mpmath, lambdify, NumPy and C evaluation",
                       description="Measure every backend on every formula, on a uniform sample of the valid "
                                   "domain and on the hard-case set.")
    p.add_argument("--quick", action="store_true", help="three formulas, smaller batches (about a minute)")
    p.add_argument("--formula", action="append", metavar="NAME", help="restrict to a formula (kernel name); repeatable")
    add_plot_option(p, "the log-log plot of throughput against error")
    add_json_flag(p)
    p.set_defaults(func=run)


def run(args) -> dict:
    import warnings

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
    from ..bench import table

    return table(result)
