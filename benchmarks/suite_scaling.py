"""How ``impactsym suite export`` scales from 1 to 2 Dask workers (a LocalCluster of processes).

    python benchmarks/suite_scaling.py [--random 10000] [--seed 1] [--workers 1,2]
        # -> benchmarks/results/suite_scaling.{json,md}

Each run is one ``python -m impactsym suite export DIR --scenes none --random N --seed S --workers W
--json`` (cluster start-up and the writing of the files included); the exported directories of
every run are compared byte for byte (they must be identical). Wall-clock seconds on this 2-core
machine shared with other jobs; never asserted in tests.
"""

from __future__ import annotations

import argparse
import filecmp
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _same_tree(a: Path, b: Path) -> bool:
    fa = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    fb = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    return fa == fb and all(filecmp.cmp(a / f, b / f, shallow=False) for f in fa)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--random", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--workers", default="1,2")
    ap.add_argument("--out", default=str(HERE / "results" / "suite_scaling"))
    a = ap.parse_args(argv)
    tmp = Path(tempfile.mkdtemp(prefix="impactsym-suite-"))
    runs = []
    try:
        for w in [int(x) for x in a.workers.split(",")]:
            d = tmp / f"w{w}"
            cmd = [sys.executable, "-m", "impactsym", "suite", "export", str(d), "--scenes", "none", "--random",
                   str(a.random), "--seed", str(a.seed), "--workers", str(w), "--json"]
            t = time.perf_counter()
            p = subprocess.run(cmd, capture_output=True, text=True)
            secs = time.perf_counter() - t
            if p.returncode != 0:
                raise SystemExit(f"{' '.join(cmd)} failed: {p.stderr[-2000:]}")
            summary = json.loads(p.stdout)
            size = sum(f.stat().st_size for f in d.rglob("*") if f.is_file())
            runs.append({"workers": w, "seconds": round(secs, 2), "cases_per_second": round(a.random / secs, 2),
                         "bytes": size, "laws": summary["laws"]})
        identical = all(_same_tree(tmp / f"w{runs[0]['workers']}", tmp / f"w{r['workers']}") for r in runs[1:])
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    base = runs[0]["seconds"]
    for r in runs:
        r["speedup"] = round(base / r["seconds"], 2)
    result = {"command": f"python benchmarks/suite_scaling.py --random {a.random} --seed {a.seed} --workers {a.workers}",
              "machine": f"{platform.machine()}, {os.cpu_count()} CPUs (shared with other jobs), "
                         f"Python {platform.python_version()}",
              "random": a.random, "seed": a.seed, "runs": runs, "byte_identical": identical}
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
    md = ["# `impactsym suite export`: 1 against 2 Dask workers", "",
          f"Command: `{result['command']}` ({result['machine']}).", "",
          "| workers | cases | seconds | cases/s | speed-up | MB written |", "| ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in runs:
        md.append(f"| {r['workers']} | {a.random} | {r['seconds']} | {r['cases_per_second']} | {r['speedup']} | "
                  f"{r['bytes'] / 1e6:.1f} |")
    md += ["", f"Exported files byte-identical across the runs: {identical}.",
           "Each run includes the LocalCluster's start-up and writing the files. Wall-clock seconds on a 2-core "
           "machine shared with other jobs while it ran; never asserted in tests.", ""]
    out.with_suffix(".md").write_text("\n".join(md))
    print("\n".join(md))
    return 0


if __name__ == "__main__":
    sys.exit(main())
