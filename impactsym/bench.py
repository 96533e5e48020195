"""Speed versus error of every evaluation path of the closed-form laws (``impactsym bench``).

For each formula (a generated closed-form kernel) and each backend

* ``sympy-evalf``    — SymPy ``subs`` of 53-bit Floats, then ``evalf`` (15 digits);
* ``sympy-exact``    — SymPy with the exact binary inputs (``Rational``), exact result, then ``float``;
* ``mpmath-50``      — the same formulas lambdified to mpmath at 50 digits;
* ``lambdify-naive`` — plain ``sympy.lambdify`` (NumPy) of the *naive* formula (no stable forms, no CSE);
* ``numpy-batched``  — the generated NumPy kernel on arrays of ``batch`` inputs;
* ``numpy-scalar``   — the generated NumPy kernel called once per input with Python floats;
* ``c-loop``         — the generated C kernel's ``_batch`` loop (gcc -O2), one call over the batch;

it measures the throughput (evaluations per second) and the median and maximum relative error
against the checked mpmath reference (:mod:`impactsym.reference_values`), on a uniform sample of the
valid domain and on the hard-case set (:mod:`impactsym.hard_cases`). The relative error of one
evaluation is the largest over its output components of ``|f̂ − f| / |f|`` (``|f̂ − f|`` where
``f = 0``). ``max_error_ratio`` is the largest error in units of ``eps · (|f| + Σ|x ∂f|)``,
the quantity the stable-form target bounds (by 64 here).
"""

from __future__ import annotations

import ctypes
import json
import math
import shutil
import statistics
import subprocess
import tempfile
import time
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import mpmath
import numpy as np
import sympy as sp

from . import kernels as K
from .hard_cases import domain_sample, hard_cases
from .reference_values import OutsideDomain, error_ratio, kernel_reference

__all__ = ["FORMULAS", "BACKENDS", "run", "naive_outputs", "compile_c", "check_targets", "table", "plot"]

KERNEL_DIR = Path(__file__).resolve().parent / "kernels"
FORMULAS = ("chain3_impulse_ratio", "impulse_ratio_root", "reflect_2", "reflect_3", "pool_impulse_ratio",
            "two_surface_resolution", "two_surface_resolution_2")
QUICK_FORMULAS = ("chain3_impulse_ratio", "impulse_ratio_root", "reflect_2")
BACKENDS = ("sympy-evalf", "sympy-exact", "mpmath-50", "lambdify-naive", "numpy-batched", "numpy-scalar", "c-loop")


@lru_cache(maxsize=None)
def _catalog() -> dict:
    data = json.loads((KERNEL_DIR / "catalog.json").read_text())
    return {k["name"]: k for k in data["kernels"]}


def _exprs(name):
    ref = kernel_reference(name)
    return ref.args, ref.outputs


@lru_cache(maxsize=None)
def naive_outputs(name: str):
    """``(args, outputs)`` of the naive formula: the quadratic formula for the impulse-ratio root
    (chain3: ``p₁ = (−B + √D)/(2A)``), the emitted expressions otherwise.

    >>> args, outs = naive_outputs("impulse_ratio_root")
    >>> [str(a) for a in args], outs[1]
    (['A', 'B', 'C'], (-B - sqrt(-4*A*C + B**2))/(2*A))
    """
    args, outs = _exprs(name)
    if name == "impulse_ratio_root":
        return _exprs("impulse_ratio_root_naive")
    if name == "chain3_impulse_ratio":
        # the quadratic formula with the derived coefficients, committed by derivations/chain3.py
        from .committed import committed_expressions

        data = committed_expressions("chain3_naive")
        sym, naive = data["args"], data["outputs"]
        # rename to the kernel's argument symbols (same names, possibly other assumptions)
        sub = {s: a for s in sym for a in args if str(a) == str(s)}
        return args, [sp.sympify(x).subs(sub) for x in naive]
    return args, outs


#: the warning flags :func:`compile_c` builds with (they change no generated code: the library is
#: the one ``-std=c99 -O2`` alone builds, byte for byte); the compiler's diagnostics are kept in
#: :data:`C_DIAGNOSTICS` (the tests hold them empty: the kernels compile cleanly as C99 with these)
C_WARNING_FLAGS = ("-pedantic", "-Wall", "-Wextra")
#: the compiler and its stderr text of :func:`compile_c`'s build (filled by the first call)
C_DIAGNOSTICS: dict = {}


@lru_cache(maxsize=1)
def compile_c() -> ctypes.CDLL | None:
    """All generated C kernels in one shared library (``gcc -std=c99 -O2``), or None without a compiler."""
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        return None
    out = Path(tempfile.mkdtemp(prefix="impactsym-bench-")) / "libk.so"
    srcs = sorted(str(p) for p in (KERNEL_DIR / "c").glob("*.c"))
    cmd = [cc, "-std=c99", *C_WARNING_FLAGS, "-O2", "-fPIC", "-shared", "-o", str(out), *srcs, "-lm"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    C_DIAGNOSTICS.update(compiler=cc, stderr=res.stderr)
    if res.stderr:  # (shown, as the compiler's own output would be)
        import sys

        sys.stderr.write(res.stderr)
    if res.returncode != 0:
        raise subprocess.CalledProcessError(res.returncode, cmd, res.stdout, res.stderr)
    return ctypes.CDLL(str(out))


def c_batch(lib, name, inputs: dict) -> list[np.ndarray]:
    """Call the generated C loop ``<name>_batch`` of a compiled kernel library through ctypes.

    ``inputs`` maps each argument name to an array (broadcast to the first argument's shape);
    returns one float array per output. Shared by the bench and the C kernel tests.
    """
    k = _catalog()[name]
    arrs = [np.ascontiguousarray(np.broadcast_to(np.asarray(inputs[a], dtype=float), np.shape(inputs[k["args"][0]])))
            for a in k["args"]]
    n = arrs[0].size
    outs = [np.empty(n) for _ in k["outputs"]]
    f = getattr(lib, name + "_batch")
    f.restype = None
    ptr = ctypes.POINTER(ctypes.c_double)
    f(ctypes.c_size_t(n), *[a.ctypes.data_as(ptr) for a in arrs], *[o.ctypes.data_as(ptr) for o in outs])
    return outs


def _as_tuple(x):
    return x if isinstance(x, tuple) else (x,)


def _rel_error(ref, computed) -> float:
    worst = 0.0
    with mpmath.workdps(ref.dps):
        for v, c in zip(ref.values, computed):
            c = float(c)
            if mpmath.isnan(v) and math.isnan(c):  # "no such branch" in both
                continue
            if not math.isfinite(c):
                return float("inf")
            d = abs(mpmath.mpf(c) - v)
            worst = max(worst, float(d / abs(v)) if v != 0 else float(d))
    return worst


@dataclass
class _Inputs:
    arrays: dict  # name -> ndarray (batch)
    points: list  # list of dicts (error sample, in domain), with their references
    refs: list


def _inputs(name: str, case_set: str, batch: int, n_err: int, seed: int) -> _Inputs:
    ref = kernel_reference(name)
    if case_set == "uniform":
        arrays = domain_sample(name, batch, seed=seed)
        cand = [{a: float(v[i]) for a, v in arrays.items()} for i in range(min(batch, 4 * n_err))]
    else:
        cand = [c.inputs for c in hard_cases(name)]
    points, refs = [], []
    for p in cand:
        try:
            refs.append(ref.evaluate(p))
            points.append(p)
        except OutsideDomain:
            continue
        if len(points) >= n_err:
            break
    if case_set != "uniform":
        reps = max(1, batch // max(1, len(points)))
        arrays = {a: np.tile(np.array([p[a] for p in points]), reps) for a in ref.names}
    return _Inputs(arrays, points, refs)


#: the wall time (seconds) over which each batched measurement repeats its call, at least 3 calls
#: after one untimed call: ``--quick`` and the full run
MIN_TIME_QUICK, MIN_TIME = 0.05, 0.3


def _timeit(fn, min_time: float) -> float:
    """Seconds per call of ``fn`` (best of repeated runs lasting at least ``min_time`` in all)."""
    fn()
    best, total, reps = float("inf"), 0.0, 0
    while total < min_time or reps < 3:
        t0 = time.perf_counter()
        fn()
        dt = time.perf_counter() - t0
        best, total, reps = min(best, dt), total + dt, reps + 1
    return best


def _measure(name, backend, inp: _Inputs, min_time: float, slow_n: int):
    args, outs = _exprs(name)
    names = [str(a) for a in args]
    batch = len(next(iter(inp.arrays.values())))
    pts = inp.points
    if backend == "numpy-batched":
        f = getattr(K, name)
        dt = _timeit(lambda: f(**inp.arrays), min_time)
        res = f(**{a: np.array([p[a] for p in pts]) for a in names})
        comp = [[float(np.asarray(r)[i]) if np.ndim(r) else float(r) for r in _as_tuple(res)] for i in range(len(pts))]
        return batch / dt, comp
    if backend == "c-loop":
        lib = compile_c()
        if lib is None:
            return None
        dt = _timeit(lambda: c_batch(lib, name, inp.arrays), min_time)
        res = c_batch(lib, name, {a: np.array([p[a] for p in pts]) for a in names})
        return batch / dt, [[float(r[i]) for r in res] for i in range(len(pts))]
    if backend == "lambdify-naive":
        nargs, nouts = naive_outputs(name)
        f = sp.lambdify(nargs, nouts, modules="numpy")
        call = lambda arr: f(*[arr[a] for a in names])  # noqa: E731
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            dt = _timeit(lambda: call(inp.arrays), min_time)
            res = call({a: np.array([p[a] for p in pts]) for a in names})
        res = [np.broadcast_to(np.asarray(r, dtype=float), (len(pts),)) for r in res]
        return batch / dt, [[float(r[i]) for r in res] for i in range(len(pts))]
    if backend == "numpy-scalar":
        f = getattr(K, name)
        sub = pts[: max(1, min(len(pts), 200))] * max(1, 200 // max(1, len(pts)))
        t0 = time.perf_counter()
        for p in sub:
            f(**p)
        rate = len(sub) / (time.perf_counter() - t0)
        return rate, [[float(x) for x in _as_tuple(f(**p))] for p in pts]
    if backend == "mpmath-50":
        from .reference_values import _mpmath_printer

        fm = sp.lambdify(args, outs, modules="mpmath", printer=_mpmath_printer())
        t0 = time.perf_counter()
        comp = []
        with mpmath.workdps(50):
            for p in pts:
                comp.append([float(mpmath.re(x)) for x in fm(*[mpmath.mpf(p[a]) for a in names])])
        return len(pts) / (time.perf_counter() - t0), comp
    if backend == "sympy-evalf":
        sub_pts = pts[:slow_n]
        t0 = time.perf_counter()
        comp = []
        for p in sub_pts:
            s = {a: sp.Float(p[str(a)], 15) for a in args}
            comp.append([float(sp.re(o.subs(s).evalf())) for o in outs])
        return len(sub_pts) / (time.perf_counter() - t0), comp
    if backend == "sympy-exact":
        sub_pts = pts[: max(1, slow_n // 4)]
        t0 = time.perf_counter()
        comp = []
        for p in sub_pts:
            s = {a: sp.Rational(p[str(a)]) for a in args}
            comp.append([float(sp.re(o.subs(s)).evalf(30)) for o in outs])
        return len(sub_pts) / (time.perf_counter() - t0), comp
    raise KeyError(backend)


def run(quick: bool = False, formulas=None, backends=BACKENDS, progress=None) -> dict:
    """Measure every (formula, backend, case set); returns ``{"results": [...], "targets": [...]}``."""
    formulas = formulas or (QUICK_FORMULAS if quick else FORMULAS)
    batch = 100_000 if quick else 1_000_000  # --quick: "smaller batches" (impactsym bench --help)
    n_err = 60 if quick else 300
    slow_n = 4 if quick else 20
    min_time = MIN_TIME_QUICK if quick else MIN_TIME
    results = []
    for name in formulas:
        for case_set in ("uniform", "hard"):
            inp = _inputs(name, case_set, batch, n_err, seed=2026)
            for backend in backends:
                got = _measure(name, backend, inp, min_time, slow_n)
                if got is None:
                    continue
                rate, comp = got
                errs = [_rel_error(r, c) for r, c in zip(inp.refs, comp)]
                ratios = [max(error_ratio(r, c)) for r, c in zip(inp.refs, comp)]
                row = {"formula": name, "backend": backend, "case_set": case_set,
                       "evals_per_second": float(rate),
                       "median_rel_error": float(statistics.median(errs)) if errs else None,
                       "max_rel_error": float(max(errs)) if errs else None,
                       "max_error_ratio": float(max(ratios)) if ratios else None,
                       "n_error_points": len(errs), "batch": batch if backend in ("numpy-batched", "c-loop",
                                                                                 "lambdify-naive") else None}
                results.append(row)
                if progress:
                    progress(row)
    return {"quick": quick, "results": results, "targets": check_targets(results)}


def table(result: dict) -> str:
    """The results as a Markdown table (one row per formula, case set and backend).

    >>> row = {"formula": "f", "case_set": "hard", "backend": "c-loop", "evals_per_second": 1e8,
    ...        "median_rel_error": 1e-16, "max_rel_error": 2e-16, "max_error_ratio": 0.5}
    >>> print(table({"results": [row], "targets": []}).splitlines()[2])
    | f | hard | c-loop | 1e+08 | 1e-16 | 2e-16 | 0.5 |
    """
    def g(x):
        return "-" if x is None else f"{x:.3g}"

    lines = ["| formula | case set | backend | evals/s | median rel. error | max rel. error | max err / (eps(1+cond)) |",
             "|---|---|---|---:|---:|---:|---:|"]
    for r in result["results"]:
        lines.append(f"| {r['formula']} | {r['case_set']} | {r['backend']} | {g(r['evals_per_second'])} | "
                     f"{g(r['median_rel_error'])} | {g(r['max_rel_error'])} | {g(r['max_error_ratio'])} |")
    lines += ["", "| target (chain3, this run) | value | required | met |", "|---|---:|---|---|"]
    for t in result["targets"]:
        lines.append(f"| {t['target']} | {g(t['value'])} | {t['required']} | {t['met']} |")
    return "\n".join(lines)


def plot(result: dict, path) -> None:
    """Log-log plot of throughput against max relative error (one marker per formula and backend)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharey=True)
    markers = dict(zip(BACKENDS, "os^vDPX"))
    formulas = sorted({r["formula"] for r in result["results"]})
    colors = dict(zip(formulas, plt.cm.tab10.colors))
    floor = 1e-18
    for ax, case_set in zip(axes, ("uniform", "hard")):
        for r in result["results"]:
            if r["case_set"] != case_set or r["max_rel_error"] is None:
                continue
            ax.scatter(r["evals_per_second"], max(r["max_rel_error"], floor), marker=markers[r["backend"]],
                       color=colors[r["formula"]], s=50, alpha=0.85)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("throughput (evaluations / s)")
        ax.set_title(f"{case_set} {'sample of the valid domain' if case_set == 'uniform' else 'case set'}")
        ax.axhline(np.finfo(float).eps, color="grey", lw=0.8, ls=":")
        ax.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel(f"max relative error vs 50-digit reference (floored at {floor:g})")
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], marker=markers[b], ls="", color="k", label=b) for b in BACKENDS]
    handles += [Line2D([], [], marker="o", ls="", color=colors[f], label=f) for f in formulas]
    axes[1].legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.suptitle("impactsym: speed versus error of every evaluation path")
    from .figures._common import tight_layout_once

    tight_layout_once(fig).savefig(path, dpi=110)
    plt.close(fig)


def _rate(results, formula, backend, case_set="uniform"):
    for r in results:
        if (r["formula"], r["backend"], r["case_set"]) == (formula, backend, case_set):
            return r["evals_per_second"]
    return None


def check_targets(results) -> list[dict]:
    """The issue's targets for chain3, as ratios from this run (met or missed, with the numbers).

    >>> rows = [{"formula": "chain3_impulse_ratio", "backend": b, "case_set": "uniform", "evals_per_second": r,
    ...          "max_error_ratio": 1.0} for b, r in (("numpy-batched", 2e7), ("sympy-evalf", 20.0),
    ...                                               ("mpmath-50", 4e3), ("c-loop", 6e7))]
    >>> [(t["target"], t["met"]) for t in check_targets(rows)][:3]
    [('numpy-batched / sympy-evalf', True), ('numpy-batched / mpmath-50', True), ('c-loop / numpy-batched', True)]
    """
    f = "chain3_impulse_ratio"
    nb, ev, mp, c = (_rate(results, f, b) for b in ("numpy-batched", "sympy-evalf", "mpmath-50", "c-loop"))
    out = []

    def add(name, value, target, ok):
        out.append({"target": name, "value": value, "required": target, "met": bool(ok) if value is not None else None})

    add("numpy-batched / sympy-evalf", nb / ev if nb and ev else None, ">= 1000", nb and ev and nb / ev >= 1000)
    add("numpy-batched / mpmath-50", nb / mp if nb and mp else None, ">= 50", nb and mp and nb / mp >= 50)
    add("c-loop / numpy-batched", c / nb if c and nb else None, "<= 10", c and nb and c / nb <= 10)
    add("numpy-batched evals/s (one core)", nb, ">= 1e7", nb and nb >= 1e7)
    worst = max((r["max_error_ratio"] for r in results
                 if r["backend"] in ("numpy-batched", "c-loop") and r["max_error_ratio"] is not None),
                default=None)
    add("max error / (eps (1 + cond)), generated float kernels, every formula", worst, "<= 64",
        worst is not None and worst <= 64)
    return out
