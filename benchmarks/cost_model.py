"""The cost model of every law (issue 15): time and peak memory against problem size, with the
fitted growth. Run from the repository root::

    python benchmarks/cost_model.py            # writes benchmarks/results/cost_model.{md,json}
    python benchmarks/cost_model.py --quick    # small sizes, printed only (not committed)

The same measurement, one law at a time: ``impactsym bench --law NAME [--sizes 3,4,6] [--json]``
(:mod:`impactsym.cost_model` says which problem family each law is measured on). Each time is the
median of repeated calls in one run (``time.perf_counter``), on a shared 2-core machine (the load
is printed with the results); the exponents, not the absolute times, are what to compare.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from impactsym.cost_model import DEFAULT_SIZES, LAWS, QUICK_SIZES, law_cost, markdown  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def main(quick: bool = False) -> None:
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    results = []
    for law in LAWS:
        r = law_cost(law, (QUICK_SIZES if quick else DEFAULT_SIZES)[law])
        results.append(r)
        print(f"{law:14s} time ~ size^{r['time_exponent']}  memory ~ size^{r['memory_exponent']}", file=sys.stderr)
    head = (f"# Cost model of every law\n\n`python benchmarks/cost_model.py` (one law: `impactsym bench --law NAME`). "
            f"One run on {results[0]['machine']}, load average {load0:.1f} at the start and "
            f"{os.getloadavg()[0]:.1f} at the end (a shared machine: other jobs were running), "
            f"{time.perf_counter() - t0:.0f} s in all. Exact path throughout. The exponent k is the least-squares "
            f"slope of log(cost) against log(size): cost ~ size^k over the sizes measured (for a cradle, size = "
            f"balls = coordinates = contacts + 1; for two surfaces, the reflection count). Times of a few "
            f"milliseconds are noisy on a loaded machine: compare exponents, not absolute times.\n\n")
    text = head + markdown(results) + "\n"
    if quick:
        print(text)
        return
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "cost_model.md").write_text(text)
    (RESULTS / "cost_model.json").write_text(json.dumps({"results": results}, indent=1) + "\n")
    print(f"wrote {RESULTS / 'cost_model.md'} and cost_model.json", file=sys.stderr)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv[1:])
