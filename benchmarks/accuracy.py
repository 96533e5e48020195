"""The accuracy bench of issue 15: every corner (full grid) and a larger seeded adversarial search,
for every closed-form kernel in NumPy, plain Python and C; writes the worst case found, and where.

    python benchmarks/accuracy.py                 # full grid + search (budget 400 per kernel)
    python benchmarks/accuracy.py --budget 100 --grid default --kernel chain3_impulse_ratio

Results: ``benchmarks/results/accuracy.{md,json}``. The bound checked is 64 eps (1 + cond) on
every output (:func:`impactsym.accuracy.accuracy_check`); the tests run the default grid and a
24-point search with seed 15 (``tests/test_accuracy_search.py``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from impactsym.accuracy import (CORNER_KERNELS, DISCONTINUOUS, accuracy_check, adversarial_search,  # noqa: E402
                                corner_cases, kernel_implementations, reference, wedge_samples)
from impactsym.reference_values import ReferenceUnstable  # noqa: E402


def run_kernel(kernel, grid_full: bool, budget: int, seeds, bound=64.0, wedges: int = 0) -> dict:
    impls = kernel_implementations(kernel)
    ref = reference(kernel)
    t0 = time.time()
    n = outside = unstable = 0
    problems, worst = [], None
    for case in corner_cases(kernel, grid_full):
        n += 1
        try:
            v = accuracy_check(kernel, case.inputs, impls, bound, ref)
        except ReferenceUnstable:
            unstable += 1
            continue
        outside += v.outside_domain
        if v.problems:
            problems.append({"inputs": v.inputs, "problems": v.problems})
        if worst is None or v.worst > worst.worst:
            worst = v
    if worst is not None and worst.problems == []:  # the screened ratio is an upper bound: make it exact
        worst = accuracy_check(kernel, worst.inputs, impls, bound, ref, screen=False)
    grid_s = time.time() - t0
    t0 = time.time()
    searches = []
    for seed in seeds:
        r = adversarial_search(kernel, budget=budget, seed=seed, impls=impls, bound=bound)
        searches.append(r)
        problems += [{"inputs": f.inputs, "problems": f.problems, "found_by": f"search seed {seed}"} for f in r.failures]
        if r.worst.worst > worst.worst:
            worst = r.worst
    search_s = time.time() - t0
    t0 = time.time()
    n_wedge = 0
    if wedges and kernel in DISCONTINUOUS:  # random hard wedges (the two-surface kernels' special angles)
        wworst = None
        for seed in seeds:
            for x in wedge_samples(kernel, wedges, seed):
                try:
                    v = accuracy_check(kernel, x, impls, bound, ref)
                except (ReferenceUnstable, OverflowError):
                    continue
                n_wedge += 1
                if v.problems:
                    problems.append({"inputs": v.inputs, "problems": v.problems, "found_by": f"wedge samples seed {seed}"})
                if wworst is None or v.worst > wworst.worst:
                    wworst = v
        if wworst is not None and not wworst.problems:
            wworst = accuracy_check(kernel, wworst.inputs, impls, bound, ref, screen=False)
        if wworst is not None and wworst.worst > worst.worst:
            worst = wworst
    return {"kernel": kernel, "grid_points": n, "grid_outside_domain": outside, "grid_reference_unstable": unstable,
            "grid_seconds": round(grid_s, 1), "search_points": sum(r.evaluations for r in searches),
            "search_seconds": round(search_s, 1), "wedge_points": n_wedge, "wedge_seconds": round(time.time() - t0, 1),
            "problems": len(problems), "problem_examples": problems[:5],
            "worst_ratio": worst.worst, "worst_output": worst.output, "worst_inputs": worst.inputs}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--grid", choices=("full", "default"), default="full")
    ap.add_argument("--budget", type=int, default=400)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--kernel", action="append")
    ap.add_argument("--wedges", type=int, default=500,
                    help="random hard wedges per seed for the two-surface kernels (impactsym.accuracy.wedge_samples)")
    ap.add_argument("--out", default=str(HERE / "results" / "accuracy"))
    args = ap.parse_args()
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k in args.kernel or CORNER_KERNELS:
            row = run_kernel(k, args.grid == "full", args.budget, range(1, args.seeds + 1), wedges=args.wedges)
            rows.append(row)
            print(f"{k:30s} grid {row['grid_points']:6d} ({row['grid_seconds']}s) search {row['search_points']} "
                  f"wedges {row['wedge_points']} "
                  f"problems {row['problems']:4d} worst {row['worst_ratio']:.3g} {row['worst_output']} "
                  f"at {row['worst_inputs']}", flush=True)
    meta = {"command": "python benchmarks/accuracy.py " + " ".join(sys.argv[1:]), "grid": args.grid,
            "budget": args.budget, "seeds": args.seeds, "wedges": args.wedges, "bound": "64 eps (1 + cond)"}
    write(rows, meta, Path(args.out))


def write(rows, meta, out: Path) -> None:
    """``out.json`` (every row) and ``out.md`` (the table)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps({**meta, "kernels": rows}, indent=1) + "\n")
    md = ["# Accuracy bench (issue 15)", "", f"Command: `{meta['command']}`. Grid: {meta['grid']} corner grid "
          f"(`impactsym.accuracy.corner_cases`); search: {meta['seeds']} seeds x {meta['budget']} points "
          f"(`adversarial_search`); two-surface kernels also {meta['seeds']} seeds x {meta.get('wedges', 0)} random "
          "hard wedges (`wedge_samples`). Implementations: NumPy, plain Python, C (gcc). Ratio = error / "
          "(eps (|f| + sum_j |x_j df/dx_j|)), the worst over outputs and implementations; a reflection count "
          "must be the certified count of an input within 64 eps (`impactsym/accuracy.py`).", "",
          "| kernel | grid points | search points | wedge points | problems | worst ratio | output | where |",
          "|---|---:|---:|---:|---:|---:|---|---|"]
    for r in rows:
        where = ", ".join(f"{k}={v:.17g}" for k, v in r["worst_inputs"].items())
        outp = sorted(set(r["worst_output"].values()) - {None})
        md.append(f"| {r['kernel']} | {r['grid_points']} | {r['search_points']} | {r.get('wedge_points', 0)} | "
                  f"{r['problems']} | "
                  f"{r['worst_ratio']:.3g} | {', '.join(outp)} | {where} |")
    out.with_suffix(".md").write_text("\n".join(md) + "\n")
    print(f"wrote {out}.md, {out}.json")


if __name__ == "__main__":
    main()
