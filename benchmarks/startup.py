"""Start-up and audit cost of the command line (issue 15 targets), measured side by side in one run.

Run from the repository root::

    python benchmarks/startup.py                 # start-up medians -> benchmarks/results/startup.md
    python benchmarks/startup.py --reproduce     # also `impactsym reproduce` at -j 1 and -j 2 (minutes)

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


def main(reproduce: bool) -> None:
    load0 = os.getloadavg()[0]
    samples = {k: [] for k in COMMANDS}
    with tempfile.TemporaryDirectory() as cwd:
        for _ in range(N):
            for label, argv in COMMANDS.items():
                samples[label].append(_time(argv, cwd))
        rows = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in samples.items()}
        if reproduce:
            for jobs in ("1", "2"):
                rows[f"impactsym reproduce -j {jobs} (one run)"] = _time(["-m", "impactsym", "reproduce", "-j", jobs], cwd)
    base = rows["python -c 'import numpy'"][0]
    lines = ["# Start-up and audit cost of the command line", "",
             f"`python benchmarks/startup.py{' --reproduce' if reproduce else ''}`: medians of {N} interleaved runs "
             f"(reproduce: one run each), load average {load0:.1f} at the start and {os.getloadavg()[0]:.1f} at the "
             f"end on a shared 2-core machine. CPU = user + sys of the process and its workers.", "",
             "| command | wall (s) | CPU (s) | wall / `import numpy` |", "|---|---:|---:|---:|"]
    for label, (wall, cpu) in rows.items():
        lines.append(f"| {label} | {wall:.2f} | {cpu:.2f} | {wall / base:.1f} |")
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "startup.md").write_text(text)


if __name__ == "__main__":
    main("--reproduce" in sys.argv[1:])
