"""The laws on a dense 60×60 mass matrix (issue 15: "reflect and the laws on a dense 60×60 M in
under 1 s").

Run from the repository root::

    python benchmarks/dense.py            # writes benchmarks/results/dense.md

The system: ``M = AᵀA + 60·I`` with ``A`` a 60×60 matrix of random integers in ``[−3, 3]``
(seed 15; every entry non-zero in practice, entries up to a few hundred), one or two dense
random integer gradient rows in ``[−2, 2]``, and a velocity of random fractions ``p/q``
(``|p| ≤ 9``, ``q ≤ 7``) signed so that every contact approaches. Everything exact.

Three times per law: the library call alone (the law's function on the text input, in the
running interpreter), ``resolve`` through the CLI in the running interpreter (reading the
text, the law, the one JSON schema), and the whole ``python -m impactsym resolve ... --json``
process (interpreter start and imports included), and that process again with the code of
another checkout (``IMPACTSYM_BASELINE``, default ``/work/main``) in the same run. Medians of
repeated calls.
"""

from __future__ import annotations

import contextlib
import io
import os
import platform
import random
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

N = 60
#: the checkout measured side by side (the code before this change)
BASELINE = os.environ.get("IMPACTSYM_BASELINE", "/work/main")


def system(seed=15, n=N):
    rng = random.Random(seed)
    A = [[rng.randint(-3, 3) for _ in range(n)] for _ in range(n)]
    M = [[sum(A[k][i] * A[k][j] for k in range(n)) + (n if i == j else 0) for j in range(n)] for i in range(n)]
    H = [[rng.randint(-2, 2) for _ in range(n)] for _ in range(2)]
    from fractions import Fraction

    v = [Fraction(rng.randint(-9, 9), rng.randint(1, 7)) for _ in range(n)]
    if sum(h * x for h, x in zip(H[0], v)) > 0:
        v = [-x for x in v]
    text = {
        "M": ";".join(",".join(map(str, r)) for r in M),
        "H1": ",".join(map(str, H[0])),
        "H2": ";".join(",".join(map(str, r)) for r in H),
        "v": ",".join(str(x) for x in v),
    }
    return text


def median_time(fn, repeat=5, budget=6.0):
    times, start = [], time.perf_counter()
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
        if time.perf_counter() - start > budget and len(times) >= 2:
            break
    return statistics.median(times)


def library_call(law, s, rows):
    from impactsym.laws import classical
    from impactsym.laws.impulse_ratio import impulse_ratio_law
    from impactsym.laws.sequential import resolve_sequential
    from impactsym.laws.two_surface import resolve_two_surfaces

    M, H, v = s["M"], s[rows], s["v"]
    return {
        "sequential": lambda: resolve_sequential(M, H, v),
        "two-surface": lambda: resolve_two_surfaces(M, H, v),
        "newton": lambda: classical.newton_moreau(M, H, v),
        "poisson": lambda: classical.poisson(M, H, v),
        "energetic": lambda: classical.energetic(M, H, v, ratios=None if rows == "H1" else ["1"]),
        "impulse-ratio": lambda: impulse_ratio_law(M, H, v, ratios=None if rows == "H1" else ["1"]),
    }[law]


def cli_args(law, s, rows):
    args = ["resolve", "--law", law, "--mass-matrix", s["M"], "--gradients", s[rows], "--velocity", s["v"], "--json"]
    if rows == "H2" and law in ("energetic", "impulse-ratio"):
        args += ["--ratios", "1"]
    return args


def cli_in_process(args):
    from impactsym.cli import main

    def run():
        with contextlib.redirect_stdout(io.StringIO()):
            try:
                main(args)
            except SystemExit as exc:
                if exc.code not in (0, None):
                    raise RuntimeError(f"exit {exc.code}") from None
    return run


def cli_process(args, root=ROOT):
    env = dict(os.environ, PYTHONPATH=str(root))

    def run():
        subprocess.run([sys.executable, "-m", "impactsym", *args], check=True, capture_output=True, env=env)
    return run


def main() -> str:
    s = system()
    lines = ["# The laws on a dense 60×60 mass matrix", "",
             f"Python {platform.python_version()} on {platform.machine()}, load average at start "
             f"{os.getloadavg()[0]:.2f} (2 cores, shared with other jobs). Command: `python benchmarks/dense.py`.",
             "", "`M = AᵀA + 60·I` (A: random integers in [−3, 3], seed 15), dense integer gradient rows, a "
             "rational velocity with every contact approaching; exact throughout. Medians, seconds.", "",
             "| law | contacts | library call | CLI in-process | CLI process | under 1 s (in-process) "
             f"| CLI process, `{BASELINE}` at run time (without this branch) |",
             "|---|---|---|---|---|---|---|"]
    for rows, k in (("H1", 1), ("H2", 2)):
        for law in ("sequential", "two-surface", "newton", "poisson", "energetic", "impulse-ratio"):
            if law == "two-surface" and k != 2:
                lines.append(f"| {law} | {k} | — | — | — | not applicable (exactly two contacts) | — |")
                continue
            tl = median_time(library_call(law, s, rows))
            args = cli_args(law, s, rows)
            ti = median_time(cli_in_process(args))
            tp = median_time(cli_process(args), repeat=3)
            try:
                tb = f"{median_time(cli_process(args, BASELINE), repeat=3):.2f}" if Path(BASELINE).is_dir() else "—"
            except subprocess.CalledProcessError:
                tb = "error"
            lines.append(f"| {law} | {k} | {tl:.3f} | {ti:.3f} | {tp:.2f} | {'yes' if ti < 1 else 'no'} | {tb} |")
            print(lines[-1], flush=True)
    lines += ["", "The library call is the law itself. The in-process CLI adds reading the text (SymPy "
              "parsing of 3,600 entries), the System and the JSON of the resolution (the dense M printed in "
              "full); the process adds the interpreter and imports (see `benchmarks/results/startup.md`)."]
    return "\n".join(lines)


if __name__ == "__main__":
    text = main()
    (Path(__file__).resolve().parent / "results" / "dense.md").write_text(text + "\n")
    print(text)
