"""Throughput of ``impactsym batch`` (one process) against one process per request.

    python benchmarks/batch.py [--requests 1000] [--sample 20]   # -> benchmarks/results/batch.{json,md}

The request mix cycles through ``resolve --law newton|sequential|poisson`` and ``check`` on the
built-in scenes chain3, two-balls-wall, three-ball-cradle, cradle and balls-against-wall (cheap,
exact), so that the measurement is of the interpreter start-up against the laws. The batch runs all
``--requests`` in one ``python -m impactsym batch``; one process per request is measured on the
first ``--sample`` requests, each its own ``python -m impactsym …`` (the mix's first requests cover
every kind), and extrapolated to ``--requests`` (labelled as such in the results). Wall-clock
seconds on this shared 2-core machine; never asserted in tests.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENES = ["chain3", "two-balls-wall", "three-ball-cradle", "cradle", "balls-against-wall"]
OBSERVED = {"chain3": "0,0,1", "two-balls-wall": "-1,0", "three-ball-cradle": "0,0,1", "cradle": "0,0,1",
            "balls-against-wall": "-1,-1"}


def requests(n: int) -> list[dict]:
    out = []
    kinds = ["newton", "sequential", "check", "poisson"]
    for i in range(n):
        scene = SCENES[i % len(SCENES)]
        kind = kinds[(i // len(SCENES)) % len(kinds)]
        if kind == "check":
            argv = ["check", "--scene", scene, "--observed", OBSERVED[scene], "--laws", "newton,sequential,poisson"]
        else:
            argv = ["resolve", "--law", kind, "--scene", scene]
        out.append({"id": i, "argv": argv})
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--requests", type=int, default=1000)
    ap.add_argument("--sample", type=int, default=20)
    ap.add_argument("--out", default=str(HERE / "results" / "batch"))
    a = ap.parse_args(argv)
    reqs = requests(a.requests)
    env = dict(os.environ)
    text = "".join(json.dumps(r) + "\n" for r in reqs)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "impactsym", "batch"], input=text, capture_output=True, text=True,
                          env=env, check=True)
    batch_s = time.perf_counter() - t0
    answers = [json.loads(line) for line in proc.stdout.splitlines()]
    if len(answers) != len(reqs):
        raise SystemExit(f"batch answered {len(answers)} of {len(reqs)} requests")
    statuses = {}
    for ans in answers:
        statuses[str(ans["exit_status"])] = statuses.get(str(ans["exit_status"]), 0) + 1
    sample = reqs[:a.sample]
    per = []
    for r in sample:
        t = time.perf_counter()
        p = subprocess.run([sys.executable, "-m", "impactsym", *r["argv"], "--json"], capture_output=True, text=True,
                           env=env)
        per.append(time.perf_counter() - t)
        if p.returncode not in (0, 3):
            raise SystemExit(f"request {r} failed: {p.stderr}")
    mean = sum(per) / len(per)
    result = {
        "command": f"python benchmarks/batch.py --requests {a.requests} --sample {a.sample}",
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs (shared with other jobs), Python {platform.python_version()}",
        "requests": a.requests,
        "batch": {"seconds": round(batch_s, 3), "requests_per_second": round(a.requests / batch_s, 2),
                  "exit_statuses": statuses, "note": "one `python -m impactsym batch` process, start-up included"},
        "process_per_request": {
            "sampled": len(sample), "sample_seconds": [round(x, 3) for x in per], "mean_seconds": round(mean, 3),
            "requests_per_second": round(1 / mean, 3),
            "extrapolated_seconds_for_all": round(mean * a.requests, 1),
            "note": f"measured on {len(sample)} processes (`python -m impactsym ARGV --json`), extrapolated "
                    f"linearly to {a.requests}: NOT measured at {a.requests}"},
        "speedup": round(mean * a.requests / batch_s, 1),
    }
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
    md = [
        "# `impactsym batch` against one process per request",
        "",
        f"Command: `{result['command']}` ({result['machine']}).",
        "",
        "| mode | requests | seconds | requests/s |",
        "| --- | ---: | ---: | ---: |",
        f"| `impactsym batch` (one process) | {a.requests} | {result['batch']['seconds']} | "
        f"{result['batch']['requests_per_second']} |",
        f"| one process per request, measured | {len(sample)} | {round(sum(per), 3)} | "
        f"{result['process_per_request']['requests_per_second']} |",
        f"| one process per request, **extrapolated** from {len(sample)} | {a.requests} | "
        f"{result['process_per_request']['extrapolated_seconds_for_all']} | "
        f"{result['process_per_request']['requests_per_second']} |",
        "",
        f"Speed-up of the batch: {result['speedup']}x. Exit statuses of the batch's answers: {statuses} "
        "(3: a `check` that matched no law is a finding, not an error).",
        "Wall-clock seconds on a 2-core machine shared with other jobs; never asserted in tests.",
        "",
    ]
    out.with_suffix(".md").write_text("\n".join(md))
    print("\n".join(md))
    return 0


if __name__ == "__main__":
    sys.exit(main())
