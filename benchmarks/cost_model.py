"""The cost model of every law (issue 15): time and peak memory against problem size (balls,
dimension of a dense M, digits of the numbers, reflection count), exact and float paths, with the
fitted growth. Run from the repository root::

    python benchmarks/cost_model.py                 # every law -> benchmarks/results/cost_model.md,
                                                    #   cost_model.json, cost_model/<law>.png
    python benchmarks/cost_model.py --law newton    # some laws only (repeatable): their tables and plots
                                                    #   there replaced, the other laws' kept
    python benchmarks/cost_model.py --quick         # small sizes, printed only (nothing written)
    python benchmarks/cost_model.py --out DIR       # write into DIR instead

One law from the command line: ``impactsym bench --law NAME [--quick] [--axis A --sizes N,N]
[--out DIR] [--json]``. :mod:`impactsym.cost_model` says which problems each law is measured on and
how. Every problem comes from a fixed seed; the measurement goes through
``impactsym.lawbook.resolve``, so faster laws show here without a change. A series stops before a
call predicted to take more than ``--max-call`` seconds (default 4), which bounds the run (about 5
minutes on the shared 2-core machine).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from impactsym.cost_model import COST_LAWS, MAX_CALL, markdown, read_results, run, write_results  # noqa: E402
from impactsym.errors import ImpactInputError  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--law", action="append", choices=list(COST_LAWS), help="only this law (repeatable)")
    ap.add_argument("--quick", action="store_true", help="small sizes; printed, not written (unless --out)")
    ap.add_argument("--out", type=Path, help=f"write here instead of {RESULTS}")
    ap.add_argument("--max-call", type=float, default=MAX_CALL, help="seconds: stop a series before a call "
                                                                     "predicted to take longer")
    args = ap.parse_args(argv)
    if args.max_call <= 0:
        ap.error(f"--max-call must be > 0, got {args.max_call}")
    out = args.out or (None if args.quick else RESULTS)
    if out is not None:
        try:
            read_results(out)  # a cost_model.json there that is not a cost model: refused before the work
        except ImpactInputError as exc:
            ap.error(f"--out: {exc.condition}")
    report = run(args.law, quick=args.quick, max_call=args.max_call, progress=lambda s: print(s, file=sys.stderr))
    if out is None:
        print(markdown(report))
        return 0
    command = "python benchmarks/cost_model.py" + "".join(f" --law {x}" for x in args.law or ()) + (
        " --quick" if args.quick else "")
    for path in write_results(report, out, command):
        print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
