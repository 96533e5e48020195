"""Random scale sweep of the float integrations (issue 15): does a law give the unit problem's outcome
in any units its ranges admit?

Run from the repository root::

    python benchmarks/scale_sweep.py                      # 200 s per group -> results/scale_sweep.{md,json}
    python benchmarks/scale_sweep.py --seconds 30 --no-write

Each case is a random 3-ball chain: masses ``10^U(−1, 1)``, each row of ``H`` scaled by
``10^U(−0.5, 0.5)``, stiffnesses ``10^U(−1, 1)``, ``v⁻ = (1, U(−½, ½), −U(0, 1))``. It is run once as
it is (the unit run) and once with ``M``, ``H`` and ``v`` times ``10^a``, ``10^b`` and ``10^c``,
``a, b, c ~ U(−170, 170)``: the same problem in other units (scaling ``H``'s rows is scaling each
``K_i`` by ``10^{b(p+1)}``, to which the outcome relative to ``v`` is blind; Hunt–Crossley's ``D`` is
divided by ``10^{b+c}``, which keeps ``D δ̇``). A scaled run is *refused* when ``T⁻`` or an effective
mass leaves the law's range (``ImpactInputError``, by name), *ok* when its velocity over ``10^c`` is
within 1e-6 of the unit run's, and otherwise a failure: *off* (returned, wrong), *raised* (any other
exception) or *late* (over 10 s). Laws: hertz, linear, Hunt–Crossley (``D = 0.3``) and LZB
(``e = 0.8``, Hertz exponent). The seeds are fixed; the cases are a sample, not a proof.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import signal
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from impactsym.compliant import compliant_impact  # noqa: E402
from impactsym.cost_model import machine  # noqa: E402
from impactsym.errors import ImpactInputError  # noqa: E402
from impactsym.lzb import lzb_impact  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
GROUPS = {"time domain (hertz, linear, hunt-crossley)": (("hertz", "linear", "hunt-crossley"), 1),
          "LZB": (("lzb",), 5)}
LATE = 10


def _late(_signum, _frame):
    raise TimeoutError


def run(law, M, H, v, K, D):
    """The law's post-impact velocity, or a string saying how it ended."""
    signal.alarm(LATE)
    try:
        if law == "lzb":
            return lzb_impact(M, H, v, K, 1.5, 0.8).velocity
        if law == "hunt-crossley":
            return compliant_impact(M, H, v, K, 1.5, hunt_crossley=D).velocity
        return compliant_impact(M, H, v, K, 1.0 if law == "linear" else 1.5).velocity
    except TimeoutError:
        return "late"
    except ImpactInputError:
        return "refused"
    except Exception as ex:  # noqa: BLE001 - every other end is a finding, reported by its type
        return "raised " + type(ex).__name__
    finally:
        signal.alarm(0)


def sweep(laws, seed, seconds):
    rng = np.random.default_rng(seed)
    counts = {law: {} for law in laws}
    worst = {law: (0.0, None) for law in laws}
    findings = []
    t0 = time.time()
    cases = 0
    while time.time() - t0 < seconds:
        cases += 1
        M0 = np.diag(10.0 ** rng.uniform(-1, 1, 3))
        H0 = np.array([[-1.0, 1, 0], [0, -1, 1]]) * 10.0 ** rng.uniform(-0.5, 0.5, (2, 1))
        v0 = np.array([1.0, rng.uniform(-0.5, 0.5), -rng.uniform(0, 1)])
        K = 10.0 ** rng.uniform(-1, 1, 2)
        a, b, c = rng.uniform(-170, 170, 3)
        for law in laws:
            base = run(law, M0, H0, v0, K, 0.3)
            if isinstance(base, str):
                status, err = "unit run " + base, None
            else:
                out = run(law, M0 * 10**a, H0 * 10**b, v0 * 10**c, K, 0.3 / 10 ** (b + c))
                if isinstance(out, str):
                    status, err = out, None
                else:
                    err = float(np.max(np.abs(out / 10**c - base)))
                    status = "ok" if err <= 1e-6 else "off"
                    if err > worst[law][0]:
                        worst[law] = (err, [round(float(x), 2) for x in (a, b, c)])
            counts[law][status] = counts[law].get(status, 0) + 1
            if status not in ("ok", "refused"):
                findings.append(dict(law=law, status=status, error=err, case=cases,
                                     masses=np.diag(M0).tolist(), rows=[float(-H0[0, 0]), float(-H0[1, 1])],
                                     v=v0.tolist(), K=K.tolist(), exponents=[float(a), float(b), float(c)]))
    return dict(seed=seed, seconds=seconds, cases=cases, counts=counts,
                worst={law: dict(error=e, exponents=x) for law, (e, x) in worst.items()}, findings=findings)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=200.0, help="time per group (default 200)")
    parser.add_argument("--no-write", action="store_true", help="print only; do not write results/")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    signal.signal(signal.SIGALRM, _late)
    load = os.getloadavg()[0]
    groups = {name: sweep(laws, seed, args.seconds) for name, (laws, seed) in GROUPS.items()}
    lines = ["# Random scale sweep of the float integrations", "",
             f"Python {platform.python_version()} on {platform.machine()} ({machine()['cpu']}), load average at start "
             f"{load:.2f}. "
             f"Command: `python benchmarks/scale_sweep.py --seconds {args.seconds:g}`. A sample, not a proof "
             "(the module docstring says what a case is).", "",
             "| group | seed | cases | law | ok | refused | failures | worst error (exponents a, b, c) |",
             "|---|---|---|---|---|---|---|---|"]
    for name, g in groups.items():
        for law, cnt in g["counts"].items():
            fails = {k: v for k, v in cnt.items() if k not in ("ok", "refused")}
            w = g["worst"][law]
            lines.append(f"| {name} | {g['seed']} | {g['cases']} | {law} | {cnt.get('ok', 0)} | "
                         f"{cnt.get('refused', 0)} | {', '.join(f'{k}: {v}' for k, v in fails.items()) or '0'} | "
                         f"{w['error']:.1e} at {w['exponents']} |")
    lines.append("")
    for name, g in groups.items():
        for f in g["findings"]:
            lines.append(f"- {f['law']}, case {f['case']}: {f['status']}"
                         + (f" ({f['error']:.1e})" if f["error"] is not None else "")
                         + f"; masses {f['masses']}, row scales {f['rows']}, v {f['v']}, K {f['K']}, "
                         f"exponents {f['exponents']}")
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "scale_sweep.md").write_text(text)
        (RESULTS / "scale_sweep.json").write_text(json.dumps(groups, indent=1) + "\n")


if __name__ == "__main__":
    main()
