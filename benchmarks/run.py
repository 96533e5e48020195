"""Run the speed-versus-error benchmark and the scaling measurements; write the committed results.

    python benchmarks/run.py            # full run: benchmarks/results/bench.{md,json,png}, scaling.md
    python benchmarks/run.py --quick    # the same, quick settings, into benchmarks/results/quick/

The numbers are from one run on the machine that ran it (2 cores); ratios matter, not absolutes.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

from impactsym import bench as benchmark  # noqa: E402
import scaling  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    out = HERE / "results" / ("quick" if args.quick else "")
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = benchmark.run(quick=args.quick, progress=lambda r: print(
            f"{r['formula']:24s} {r['case_set']:8s} {r['backend']:15s} {r['evals_per_second']:10.3g}/s "
            f"max rel {r['max_rel_error']}", flush=True))
        bench_seconds = time.time() - t0
        chain = [scaling.chain_derivation(n) for n in range(2, 9)]
        sizes = [1, 10, 100, 1000, 10**4, 10**5, 10**6] + ([] if args.quick else [10**7])
        batch = scaling.batch_scaling(sizes)
        exact = scaling.exact_scaling([1, 10, 100, 1000, 10000] + ([] if args.quick else [100000]))
    env = {"python": platform.python_version(), "numpy": np.__version__, "sympy": sp.__version__,
           "machine": platform.machine(), "processor_count": __import__("os").cpu_count()}
    res.update({"environment": env, "bench_seconds": bench_seconds, "scaling": {
        "chain_derivation": chain, "batch": batch, "exact": exact}})
    (out / "bench.json").write_text(json.dumps(res, indent=1) + "\n")
    benchmark.plot(res, out / "bench.png")
    md = [f"# impactsym bench ({'quick' if args.quick else 'full'} run)", "",
          f"Command: `python benchmarks/run.py{' --quick' if args.quick else ''}` "
          f"(equivalently `impactsym bench{' --quick' if args.quick else ''} --json`). "
          f"Environment: {env}. Bench time {bench_seconds:.0f} s.", "",
          "Relative error of one evaluation: max over output components of |f^ - f|/|f| against the "
          "ladder-checked mpmath reference (50 digits, exact binary inputs). `max err / (eps(1+cond))` is "
          "the largest error in units of eps (|f| + sum_j |x_j df/dx_j|): the stable-form target is a small "
          "constant there (<= 64; see benchmarks/README.md). Plot: `bench.png`.", "",
          benchmark.table(res), "", "## Scaling", "",
          "### Derivation and codegen time against chain length (n balls, n - 1 contacts, all symbolic)", "",
          "| balls | contacts | derive s | codegen (NumPy + C) s | C lines |", "|---:|---:|---:|---:|---:|"]
    md += [f"| {r['balls']} | {r['contacts']} | {r['derive_seconds']:.3f} | {r['codegen_seconds']:.3f} | {r['c_lines']} |"
           for r in chain]
    md += ["", "### chain3 kernel time per evaluation against batch size", "",
           "| batch | NumPy s/eval | C loop s/eval |", "|---:|---:|---:|"]
    md += [f"| {r['batch']} | {r.get('numpy_seconds_per_eval', float('nan')):.3g} | "
           f"{r.get('c-loop_seconds_per_eval', float('nan')):.3g} |" for r in batch]
    md += ["", "### Exact G_u(e) v (n = 2) against the size of the rational inputs", "",
           "| digits | SymPy law s | generated kernel on Fraction s | on flint fmpq s | result denominator digits |",
           "|---:|---:|---:|---:|---:|"]
    md += [f"| {r['digits']} | {r['sympy_law_seconds']:.3g} | {r['fraction_kernel_seconds']:.3g} | "
           f"{r.get('fmpq_kernel_seconds', float('nan')):.3g} | {r['result_digits']} |" for r in exact]
    (out / "bench.md").write_text("\n".join(md) + "\n")
    print(f"wrote {out}/bench.md, bench.json, bench.png")


if __name__ == "__main__":
    main()
