"""Start-up and audit cost of the command line (issue 15 targets), measured side by side in one run.

Run from the repository root::

    python benchmarks/startup.py                 # start-up medians -> benchmarks/results/startup.md
    python benchmarks/startup.py --reproduce     # also `impactsym reproduce` at -j 1 and -j 2, and its phases

Each command runs in a fresh interpreter (this checkout first on ``PYTHONPATH``, from a neutral
working directory so that no other checkout shadows it), interleaved, ``N`` times; the table gives
the median wall time and the median CPU time (user + sys of the process and its children), and the
wall-time ratio to ``python -c "import numpy"``, the issue's yardstick (targets: ``--help`` within 2x,
``reflect`` on a 2x2 system within 3x). The machine is shared: the load is printed with the results.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "results"
N = 7

COMMANDS = {
    "python -c 'import numpy'": ["-c", "import numpy"],
    "impactsym --help": ["-m", "impactsym", "--help"],
    "impactsym codegen --list": ["-m", "impactsym", "codegen", "--list"],
    "impactsym reflect (2x2, exact, --json)": ["-m", "impactsym", "reflect", "--mass-matrix", "2,0;0,1",
                                               "--gradient", "-1,1", "--velocity", "1,0", "--json"],
}


def _time(argv, cwd) -> tuple[float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, *argv], cwd=cwd, env={**os.environ, "PYTHONPATH": str(ROOT)},
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


PHASES = r"""
import json, time
t = time.process_time()
from paper_checks import framework as fw
from paper_checks.audit import derivation_summary
from paper_checks.crosscheck import run_crosschecks
fw.load_all()
out = {"imports and registration": time.process_time() - t}
for paper in ("seghete-murphey", "acary-taha"):
    t = time.process_time()
    for cid, reg in fw.REGISTRY.items():
        if reg.paper == paper:
            fw.evaluate(cid)
    out[f"claims of {paper}"] = time.process_time() - t
t = time.process_time(); derivation_summary(); out["G_u derivation summary (after the claims)"] = time.process_time() - t
t = time.process_time(); run_crosschecks(); out["cross-check"] = time.process_time() - t
print(json.dumps(out))
"""


def _phases(cwd) -> dict:
    """CPU seconds of each phase of a serial audit in one fresh process (``-j 1``'s work, in the
    order it runs: the claims share memoized derivations, so a later phase may reuse an earlier's)."""
    import json

    out = subprocess.run([sys.executable, "-c", PHASES], cwd=cwd, env={**os.environ, "PYTHONPATH": str(ROOT)},
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def main(reproduce: bool) -> None:
    load0 = os.getloadavg()[0]
    samples = {k: [] for k in COMMANDS}
    with tempfile.TemporaryDirectory() as cwd:
        for _ in range(N):
            for label, argv in COMMANDS.items():
                samples[label].append(_time(argv, cwd))
        rows = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in samples.items()}
        phases = {}
        if reproduce:
            for jobs in ("1", "2"):
                rows[f"impactsym reproduce -j {jobs} (one run)"] = _time(["-m", "impactsym", "reproduce", "-j", jobs], cwd)
            phases = _phases(cwd)
    base = rows["python -c 'import numpy'"][0]
    lines = ["# Start-up and audit cost of the command line", "",
             f"`python benchmarks/startup.py{' --reproduce' if reproduce else ''}`: medians of {N} interleaved runs "
             f"(reproduce: one run each), load average {load0:.1f} at the start and {os.getloadavg()[0]:.1f} at the "
             f"end on a shared 2-core machine. CPU = user + sys of the process and its workers.", "",
             "| command | wall (s) | CPU (s) | wall / `import numpy` |", "|---|---:|---:|---:|"]
    for label, (wall, cpu) in rows.items():
        lines.append(f"| {label} | {wall:.2f} | {cpu:.2f} | {wall / base:.1f} |")
    if phases:
        lines += ["", "Phases of the serial audit (`-j 1`'s work, one process, CPU seconds; the default `-j 2` runs "
                  "Seghete & Murphey's claims with the G_u summary in one worker and Acary & Taha's with the "
                  "cross-check in the other, so it costs about the same CPU):", "",
                  "| phase | CPU (s) |", "|---|---:|"]
        lines += [f"| {k} | {v:.2f} |" for k, v in phases.items()]
        lines.append(f"| total | {sum(phases.values()):.2f} |")
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "startup.md").write_text(text)


if __name__ == "__main__":
    main("--reproduce" in sys.argv[1:])
