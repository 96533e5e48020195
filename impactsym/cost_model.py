"""How the cost of each law grows with the problem (``impactsym bench --law NAME``; issue 15).

For every law of :data:`impactsym.lawbook.LAWS`, one or more *axes*: a family of problems that
grows along one size (balls of a cradle, dimension of a dense ``M``, digits of the input numbers,
the reflection count of two surfaces). Each problem is solved through the law interface
(:func:`impactsym.lawbook.resolve`) twice:

* the **exact** path: SymPy integers and rationals in, exact out;
* the **float** path: the same problem as float64 arrays (the classical and sequential laws then
  take their float branches; impulse-ratio evaluates the generated kernel
  ``impactsym.kernels.impulse_ratio_root``). The compliant laws (hertz, linear, power,
  hunt-crossley, lzb) integrate an ODE in floats whatever they are given: they have the float
  path only.

Per size and path: the **median time** of repeated calls (``time.perf_counter``; at least three
calls and as many as fit in :data:`MIN_SECONDS`, after a first untimed one; or the first call
alone when it takes longer than :data:`SLOW_CALL` seconds), each after emptying SymPy's cache so
that a repeated call costs what a new problem of that size costs, and the **peak memory** of one
more call under :mod:`tracemalloc` (Python allocations, NumPy arrays included; memory that FLINT/GMP
allocate outside Python's allocator is not seen). Then the fitted growth (:func:`fit_growth`):
the least-squares slope ``k`` of ``log(cost)`` against ``log(size)``, with its standard error and
the root-mean-square of the residuals, over every size and over the largest sizes (where the
constant overhead of a call has stopped dominating), and a named model (``O(1)``, ``O(n)``,
``O(n^2)``, …) only when the fit is good.

A series stops growing when one call takes more than ``max_call`` seconds, or when the next is
predicted to (from the growth between the last two sizes), when a call runs past a hard limit
(``HARD_LIMIT_FACTOR · max_call``; it is interrupted), and when the law refuses a size; the row
says so. A warning raised by a call, or a float outcome holding NaN or infinity, is recorded with
the row. Every problem is built from fixed seeds: the same sizes give the same problems.

Examples
--------
>>> fit = fit_growth([1, 2, 4, 8, 16], [3.0, 6.0, 12.0, 24.0, 48.0])
>>> fit["exponent"], fit["quality"], fit["model"]
(1.0, 'good', 'O(n)')
>>> fit_exponent([2, 4, 8], [4.0, 16.0, 64.0])
2.0
"""

from __future__ import annotations

import math
import os
import platform
import random
import statistics
import time
import tracemalloc
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Callable

__all__ = ["COST_LAWS", "LAWS", "Axis", "fit_growth", "fit_exponent", "check_request", "law_cost", "run", "markdown",
           "plot", "machine", "write_results", "POOR_RMS", "SLOW_CALL"]

#: a fit whose residuals have an rms above this (in natural log: a factor e^0.25 ≈ 1.28) is "poor"
POOR_RMS = 0.25
#: a call slower than this is timed once (plus the warm-up call) instead of three times
SLOW_CALL = 0.5
#: short calls are repeated for at least this long (seconds) and the median taken
MIN_SECONDS = 0.1
#: default cap on one call (seconds): a series stops before a size predicted to take longer
MAX_CALL = 3.0
#: calls faster than this (seconds) are not extrapolated to predict the next size
PREDICT_FROM = 0.02
#: a warm-up call running past this many times the cap is interrupted (SIGALRM)
HARD_LIMIT_FACTOR = 4


# ------------------------------------------------------------------------------------ fitting
def fit_growth(sizes, values, symbol: str = "n") -> dict:
    """Fit ``values ≈ c · sizes^k`` by least squares in log-log, and say how well it fits.

    Parameters
    ----------
    sizes, values : sequences of positive numbers (pairs with a non-positive entry are dropped)
    symbol : the size's letter in the named model (``"n"``, ``"d"``, …)

    Returns
    -------
    dict
        ``exponent`` (k, 3 decimals), ``stderr`` (its standard error; None with two points),
        ``intercept`` (log c), ``rms`` (root-mean-square of the log residuals), ``r2``,
        ``points``, ``quality`` (``"good"``: rms ≤ :data:`POOR_RMS` with at least three points;
        ``"poor"``; ``"too few points"``), ``model`` (``"O(1)"``, ``"O(n)"``, ``"O(n^2)"``, …
        when the fit is good and k is within 0.2 of an integer 0…6; ``"~n^k"`` when good
        otherwise; None when poor), and ``tail``: the same fit over the largest half of the sizes
        (at least three points; None with fewer than five points in all), which is the growth
        once a call's constant overhead no longer dominates. With fewer than two distinct sizes,
        ``exponent`` is None.

    Examples
    --------
    >>> f = fit_growth([10, 20, 40, 80], [1.0, 4.0, 16.0, 64.0], "d")
    >>> f["exponent"], f["model"], f["rms"] < 1e-12
    (2.0, 'O(d^2)', True)
    >>> fit_growth([10, 20, 40], [5.0, 1.0, 9.0])["quality"]
    'poor'
    """
    raw = sorted((s, v) for s, v in zip(sizes, values) if s is not None and v is not None and s > 0 and v > 0)
    pts = [(math.log(s), math.log(v)) for s, v in raw]
    out = _fit(pts, symbol)
    if len(pts) >= 5:
        first = len(pts) - max(3, len(pts) // 2)
        out["tail"] = _fit(pts[first:], symbol)
        out["tail"]["from_size"] = raw[first][0]
    else:
        out["tail"] = None
    return out


def _fit(pts, symbol) -> dict:
    n = len(pts)
    empty = {"exponent": None, "stderr": None, "intercept": None, "rms": None, "r2": None, "points": n,
             "quality": "too few points", "model": None}
    if len({x for x, _ in pts}) < 2:
        return empty
    mx = statistics.fmean(x for x, _ in pts)
    my = statistics.fmean(y for _, y in pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    k = sum((x - mx) * (y - my) for x, y in pts) / sxx
    b = my - k * mx
    res = [y - (b + k * x) for x, y in pts]
    ss_res = sum(r * r for r in res)
    ss_tot = sum((y - my) ** 2 for _, y in pts)
    rms = math.sqrt(ss_res / n)
    stderr = math.sqrt(ss_res / (n - 2) / sxx) if n > 2 else None
    quality = "too few points" if n < 3 else ("good" if rms <= POOR_RMS else "poor")
    model = None
    k = round(k, 3) + 0.0  # + 0.0: no -0.0
    if quality == "good":
        m = round(k)
        if abs(k - m) <= 0.2 and 0 <= m <= 6:
            model = "O(1)" if m == 0 else (f"O({symbol})" if m == 1 else f"O({symbol}^{m})")
        else:
            model = f"~{symbol}^{k:.2f}"
    return {"exponent": k, "stderr": None if stderr is None else round(stderr, 3) + 0.0,
            "intercept": b, "rms": round(rms, 3) + 0.0,
            "r2": None if ss_tot == 0 else round(1 - ss_res / ss_tot, 4) + 0.0,
            "points": n, "quality": quality, "model": model}


def fit_exponent(sizes, values) -> float | None:
    """The least-squares exponent k of ``values ~ sizes^k`` alone (:func:`fit_growth`), rounded to
    2 decimals; None with fewer than two distinct sizes.

    >>> fit_exponent([1, 2, 4, 8], [3.0, 6.0, 12.0, 24.0])
    1.0
    """
    k = fit_growth(sizes, values)["exponent"]
    return None if k is None else round(k, 2) + 0.0


# ---------------------------------------------------------------------------- problem families
def _sp():
    import sympy

    return sympy


def _chain(n):
    """The rows of a chain of ``n`` balls on a line: contact i between balls i and i+1."""
    sp = _sp()
    H = sp.zeros(n - 1, n)
    for i in range(n - 1):
        H[i, i], H[i, i + 1] = -1, 1
    return H


def _rational(rng: random.Random, d: int, below_one: bool = False):
    """A rational ``p/q`` in lowest terms with ``d``-digit numerator and denominator: in (1, 10),
    or in (1/10, 1) with ``below_one``."""
    sp = _sp()
    lo, hi = 10 ** (d - 1), 10 ** d - 1
    while True:
        p, q = rng.randint(lo, hi), rng.randint(lo, hi)
        if p != q and (p < q) == below_one and math.gcd(p, q) == 1:  # coprime: d digits after reduction
            return sp.Rational(p, q)


@dataclass(frozen=True)
class Problem:
    """One exact problem: ``M``, ``H``, ``v`` (SymPy), the restitution (None: elastic), the law's
    options (exact numbers; the float path gets them as floats) and facts about its size."""

    M: object
    H: object
    v: object
    restitution: object = None
    options: dict = field(default_factory=dict)
    facts: dict = field(default_factory=dict)


def one_striker_cradle(n: int) -> Problem:
    """``n`` unit balls touching in a row, the first moving at 1: one contact approaches, and a
    single pulse runs down the chain (``n − 1`` contacts).

    >>> one_striker_cradle(3).v.T
    Matrix([[1, 0, 0]])
    """
    sp = _sp()
    return Problem(sp.eye(n), _chain(n), sp.Matrix([1] + [0] * (n - 1)),
                   facts={"contacts": n - 1, "coordinates": n})


def approaching_cradle(n: int) -> Problem:
    """``n`` unit balls touching in a row with velocities ``n−1, …, 1, 0``: every contact
    approaches (the sequential law's worst case, every ordering of the impacts).

    >>> approaching_cradle(3).H * approaching_cradle(3).v
    Matrix([
    [-1],
    [-1]])
    """
    sp = _sp()
    return Problem(sp.eye(n), _chain(n), sp.Matrix(list(range(n - 1, -1, -1))),
                   facts={"contacts": n - 1, "coordinates": n})


def dense_system(n: int, seed: int = 15) -> Problem:
    """A dense symmetric positive definite ``M = AAᵀ + nI`` (``A`` with integer entries in
    [−3, 3], fixed seed) of dimension ``n``, two integer gradient rows, and the velocity
    ``v = Hᵀ(HHᵀ)⁻¹(−1, −2)`` (both contacts approach): the cost of the linear algebra alone.

    >>> p = dense_system(4)
    >>> p.H * p.v
    Matrix([
    [-1],
    [-2]])
    """
    sp = _sp()
    rng = random.Random(seed * 1000 + n)
    while True:
        A = sp.Matrix(n, n, lambda i, j: rng.randint(-3, 3))
        H = sp.Matrix(2, n, lambda i, j: rng.randint(-2, 2))
        if (H * H.T).det() != 0:
            break
    M = A * A.T + n * sp.eye(n)
    v = H.T * (H * H.T).inv() * sp.Matrix([-1, -2])
    return Problem(M, H, v, facts={"contacts": 2, "coordinates": n})


def digits_chain(d: int, seed: int = 15) -> Problem:
    """Three balls in a row whose masses ``m_i``, approach speeds ``x, y`` (velocities
    ``(x + y, y, 0)``: both contacts approach), restitution ``e = 1 − z/100`` and impulse ratio
    ``α`` are made of rationals with ``d``-digit numerators and denominators (fixed seed; ``m_i``,
    ``x``, ``y``, ``α`` in (1, 10), ``z`` in (1/10, 1), so ``e`` in (0.99, 1) and the impulse-ratio
    law has a real solution at every ``d``).

    >>> p = digits_chain(2)
    >>> [len(str(x.p)) for x in p.M.diagonal()], [w < 0 for w in p.H * p.v]
    ([2, 2, 2], [True, True])
    """
    sp = _sp()
    rng = random.Random(seed * 1000 + d)
    masses = [_rational(rng, d) for _ in range(3)]
    x, y = _rational(rng, d), _rational(rng, d)
    e = 1 - _rational(rng, d, below_one=True) / 100
    ratio = _rational(rng, d)
    return Problem(sp.diag(*masses), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([x + y, y, 0]),
                   e, {"ratios": [ratio]}, {"contacts": 2, "coordinates": 3})


def digits_wall(d: int, seed: int = 15) -> Problem:
    """Two balls against a wall (rows ``[1, 0]``, ``[−1, 1]``) whose masses and approach speeds
    ``x, y`` (velocities ``(−x, −x − y)``) are rationals with ``d``-digit numerators and
    denominators in (1, 10); both contacts approach; elastic.

    >>> digits_wall(1).H
    Matrix([
    [ 1, 0],
    [-1, 1]])
    """
    sp = _sp()
    rng = random.Random(seed * 1000 + d)
    masses = [_rational(rng, d) for _ in range(2)]
    x, y = _rational(rng, d), _rational(rng, d)
    return Problem(sp.diag(*masses), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-x, -x - y]),
                   facts={"contacts": 2, "coordinates": 2})


def two_surface_count(d: int) -> Problem:
    """Two balls and a wall with masses ``1 : 100^d`` (the reflection count is ``⌊π·10^d⌋`` or
    one more): the two-surface law's size is the count itself.

    >>> two_surface_count(1).M
    Matrix([
    [1,   0],
    [0, 100]])
    """
    sp = _sp()
    return Problem(sp.diag(1, 100 ** d), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, -2]),
                   facts={"contacts": 2, "coordinates": 2, "mass_ratio": f"1:100^{d}"})


@dataclass(frozen=True)
class Axis:
    """One direction in which a law's problem grows.

    ``build(size) -> Problem``; ``x``: which number the fit is against (``"size"``, or a fact the
    law reports, such as ``"reflections"``); ``also``: another reported fact to fit the time
    against (``"states"`` for the sequential search); ``limits``: the sizes accepted."""

    name: str
    symbol: str
    description: str
    build: Callable[[int], Problem]
    sizes: tuple
    quick: tuple
    limits: tuple = (1, 10 ** 9)
    x: str = "size"
    also: str | None = None


_BALLS = Axis("balls", "n", "one-striker cradle of n unit balls (n − 1 contacts, one approaching)",
              one_striker_cradle, (4, 8, 16, 32, 64), (3, 4, 6), (2, 200))
_DIM = Axis("dimension", "n", "dense n×n M = AAᵀ + nI (integer A, fixed seed), two contacts, both approaching",
            dense_system, (4, 8, 16, 32, 64), (3, 4, 6), (2, 200))
_DIGITS = Axis("digits", "d", "three balls, two approaching contacts; masses, approach speeds, restitution "
                              "(in (0.99, 1)) and the impulse ratio are rationals with d-digit numerators and "
                              "denominators (fixed seed)",
               digits_chain, (1, 4, 16, 64, 256, 1024), (1, 2, 4), (1, 5000))


def _with(axis: Axis, **kw) -> Axis:
    from dataclasses import replace

    return replace(axis, **kw)


@dataclass(frozen=True)
class LawCost:
    """A law's axes, its options (``options(problem) -> dict`` of exact values), whether it has
    an exact path, and a note on its float path."""

    axes: tuple
    exact: bool = True
    float_note: str = "the law's float branch (float64 input)"
    options: Callable[[Problem], dict] = lambda p: {}


def _ratio_options(p: Problem) -> dict:
    ratios = p.options.get("ratios") or [1] * (p.H.shape[0] - 1)
    return {"ratios": ratios, "allow_invalid": True}


_COMPLIANT_NOTE = "float only: the law integrates an ODE (DOP853) in floats whatever it is given"
_CLASSICAL_AXES = (_BALLS, _DIM, _DIGITS)

COST_LAWS: dict[str, LawCost] = {
    "sequential": LawCost((
        _BALLS,
        Axis("approaching", "n", "n unit balls, velocities n−1, …, 0: every contact approaches (n! states "
                                 "today: no power of n describes it; the time is also fitted against the states "
                                 "the search visits)",
             approaching_cradle, (3, 4, 5, 6, 7, 8, 9, 10), (3, 4, 5), (2, 12), also="states"),
        _DIM, _DIGITS),
        float_note="the float search (resolve_sequential exact=False; signs re-decided exactly when unsure)"),
    "two-surface": LawCost((
        Axis("reflections", "N", "two balls and a wall, masses 1 : 100^d (size d; fitted against the reflection "
                                 "count N ≈ π·10^d)", two_surface_count, (1, 2, 4, 8, 16, 32, 64), (1, 2, 4),
             (1, 200), x="reflections"),
        _DIM,
        _with(_DIGITS, description="two balls and a wall, masses and approach speeds rationals with d-digit "
                                   "numerators and denominators (elastic)", build=digits_wall)),
        float_note="the closed form in floats (float64 input)"),
    "newton": LawCost(_CLASSICAL_AXES),
    "poisson": LawCost(_CLASSICAL_AXES),
    "energetic": LawCost(_CLASSICAL_AXES),
    "han-gilmore": LawCost((_with(_BALLS, sizes=(3, 4, 5, 6, 7), quick=(3, 4), limits=(2, 12)), _DIM, _DIGITS)),
    "impulse-ratio": LawCost(_CLASSICAL_AXES, options=_ratio_options,
                             float_note="float branch: the generated kernel impulse_ratio_root (validity "
                                        "still decided exactly); allow_invalid, so an invalid outcome is timed "
                                        "too"),
    "hertz": LawCost((_BALLS, _DIM), exact=False, float_note=_COMPLIANT_NOTE),
    "linear": LawCost((_BALLS, _DIM), exact=False, float_note=_COMPLIANT_NOTE),
    "power": LawCost((_BALLS, _DIM), exact=False, float_note=_COMPLIANT_NOTE + "; exponent 2",
                     options=lambda p: {"exponent": 2}),
    "hunt-crossley": LawCost((_BALLS, _DIM), exact=False, float_note=_COMPLIANT_NOTE + "; elastic (e = 1)"),
    "lzb": LawCost((_BALLS, _DIM), exact=False, float_note=_COMPLIANT_NOTE + "; elastic (e = 1)"),
}
#: the law names (the order of :data:`impactsym.lawbook.LAWS`)
LAWS = COST_LAWS


# -------------------------------------------------------------------------------- measurement
def _system(law: str, p: Problem, path: str):
    """The exact or float :class:`~impactsym.resolution.System` of a problem, and the law's
    options on that path."""
    import numpy as np
    import sympy as sp

    from .resolution import System

    spec = COST_LAWS[law]
    opts = {**spec.options(p)}
    if law == "impulse-ratio" and "ratios" not in opts:
        opts.update(_ratio_options(p))
    if path == "exact":
        return System.from_matrices(p.M, p.H, p.v, p.restitution), opts

    def fl(x):
        return np.array(np.array(x.tolist()), dtype=np.float64) if isinstance(x, sp.MatrixBase) else float(x)

    e = None if p.restitution is None else float(p.restitution)
    floats = System.from_matrices(fl(p.M), fl(p.H), fl(p.v).reshape(-1), e)
    return floats, {k: ([float(x) for x in v] if k == "ratios" else v) for k, v in opts.items()}


def _result_facts(res) -> dict:
    """What the law reports about its own work (states of the sequential search, the two-surface
    reflection count, steps of an integration), and ``finite: False`` when a float outcome holds a
    NaN or an infinity."""
    import numpy as np

    d = res.details or {}
    out = {}
    counts = d.get("counts") or {}
    if counts.get("states_visited") is not None:
        out["states"] = int(counts["states_visited"])
    if res.law == "two-surface":
        out["reflections"] = max(int(o.details["reflections"]) for o in res.outcomes)
    if "steps" in d:
        out["steps"] = int(d["steps"])
    for o in res.outcomes:
        if isinstance(o.velocity, np.ndarray) and not np.all(np.isfinite(o.velocity)):
            out["finite"] = False
    return out


class CallTimeout(Exception):
    """One call ran past the hard limit (:func:`_hard_limit`)."""


@contextmanager
def _hard_limit(seconds: float):
    """Interrupt the call after ``seconds`` (SIGALRM; main thread on Unix only, elsewhere no limit):
    a size whose growth the prediction underestimated cannot hold the run for long."""
    import signal
    import threading

    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        yield
        return

    def _raise(signum, frame):
        raise CallTimeout(f"a call ran past the hard limit of {seconds:g} s")

    old = signal.signal(signal.SIGALRM, _raise)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _clear_caches() -> None:
    """Empty SymPy's global cache, so that a repeated call on the same input is not a cache hit
    (each timed call costs what a new problem of that size costs)."""
    from sympy.core.cache import clear_cache

    clear_cache()


def _measure(call, repeats: int, max_call: float = MAX_CALL, min_seconds: float | None = None,
             warm_up: bool = True) -> dict:
    """Time and peak memory of ``call``.

    Every call starts after :func:`_clear_caches`. The first call's result and warnings are kept.
    With ``warm_up`` (the first size of a series: imports and lazy set-up happen there) it is not
    timed; otherwise, when it takes more than :data:`SLOW_CALL`, it is the one timing. Else timed
    calls follow: at least ``repeats`` and for at least ``min_seconds`` (at most 100), and the
    median is reported. Then one call under :mod:`tracemalloc` gives the peak. A first call slower
    than ``max_call`` is the only call: its time is reported and memory is not measured.
    ``min_seconds`` defaults to :data:`MIN_SECONDS` as it is when called."""
    import warnings

    if min_seconds is None:
        min_seconds = MIN_SECONDS

    with warnings.catch_warnings(record=True) as caught, _hard_limit(max(1.0, HARD_LIMIT_FACTOR * max_call)):
        warnings.simplefilter("always")
        _clear_caches()
        t0 = time.perf_counter()
        res = call()
        first = time.perf_counter() - t0
    out: dict = {}
    if first > max_call:
        out = {"seconds": first, "calls": 1, "peak_kib": None,
               "memory": f"not measured (one call only: it took {first:.3g} s, above the cap of {max_call:g} s)"}
    else:
        times: list = [first] if first > SLOW_CALL and not warm_up else []
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            while not times or (times[0] <= SLOW_CALL and (len(times) < repeats or time.perf_counter() - start
                                                           < min_seconds) and len(times) < 100):
                _clear_caches()
                t0 = time.perf_counter()
                call()
                times.append(time.perf_counter() - t0)
            _clear_caches()
            tracemalloc.start()
            try:
                call()
                peak = tracemalloc.get_traced_memory()[1]
            finally:
                tracemalloc.stop()
        out = {"seconds": statistics.median(times), "calls": len(times), "peak_kib": round(peak / 1024, 1)}
    out.update(_result_facts(res))
    msgs = sorted({f"{w.category.__name__}: {w.message}" for w in caught})
    if msgs:
        out["warnings"] = msgs
    return out


def _series(law: str, axis: Axis, sizes, path: str, repeats: int, max_call: float, progress=None) -> list[dict]:
    """One path of one axis: a dict per size (``seconds``, ``peak_kib``, …, or ``stopped``).

    Before each size after the first, the time is predicted from the last one and the growth
    between the last two (an exponent of at least 1); a size predicted to take more than
    ``max_call`` is skipped, and so is everything after it. Calls under :data:`PREDICT_FROM`
    seconds are not extrapolated, nor is growth measured from one (linear growth is assumed
    then: the time of such a call is mostly fixed overhead and noise). A call that
    runs past ``HARD_LIMIT_FACTOR · max_call`` (at least 1 s) anyway is interrupted and ends the
    series."""
    from .lawbook import REFUSALS, resolve

    rows = []
    for i, size in enumerate(sizes):
        if rows and "seconds" in rows[-1] and rows[-1]["seconds"] >= PREDICT_FROM:
            last = rows[-1]
            prev = rows[-2] if len(rows) >= 2 and "seconds" in rows[-2] else None
            k = 1.0
            if prev and prev["seconds"] >= PREDICT_FROM and last["size"] != prev["size"]:
                k = max(1.0, math.log(last["seconds"] / prev["seconds"]) / math.log(last["size"] / prev["size"]))
            predicted = last["seconds"] * (size / last["size"]) ** k
            if predicted > max_call:
                rows.append({"size": size, "stopped": f"skipped: predicted {predicted:.3g} s a call, above the "
                                                      f"cap of {max_call:g} s"})
                break
        system, opts = _system(law, axis.build(size), path)
        try:
            row = {"size": size, **_measure(lambda: resolve(law, system, **opts), repeats, max_call=max_call,
                                            warm_up=not rows)}
        except REFUSALS as exc:
            rows.append({"size": size, "stopped": f"refused: {type(exc).__name__}: {_short(exc)}"})
            break
        except CallTimeout as exc:
            rows.append({"size": size, "stopped": f"stopped: {exc}"})
            break
        except (ValueError, ArithmeticError, MemoryError, RecursionError) as exc:
            rows.append({"size": size, "stopped": f"failed: {type(exc).__name__}: {_short(exc)}"})
            break
        rows.append(row)
        if progress:
            mem = "-" if row["peak_kib"] is None else f"{row['peak_kib']:.4g} KiB"
            progress(f"  {law:14s} {axis.name:11s} {path:5s} {size:>6} {row['seconds']:.3g} s {mem}")
        if row["seconds"] > max_call:
            if i + 1 < len(sizes):
                rows.append({"size": sizes[i + 1], "stopped": f"skipped: the call at size {size} took "
                                                              f"{row['seconds']:.3g} s, above the cap of "
                                                              f"{max_call:g} s"})
            break
    return rows


def _short(exc, n: int = 160) -> str:
    s = " ".join(str(exc).split())
    return s if len(s) <= n else s[: n - 1] + "…"


def check_request(law: str, axes=None, sizes=None) -> list:
    """The axes of ``law`` to measure (all, or those named in ``axes``); refuses an unknown law
    or axis, sizes with more than one axis, and a size outside the axis' limits.

    >>> [a.name for a in check_request("two-surface")]
    ['reflections', 'dimension', 'digits']
    >>> check_request("newton", ["balls"], [1])
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: sizes: newton, axis balls: sizes must lie in [2, 200], got 1
    """
    from .errors import ImpactInputError

    if law not in COST_LAWS:
        raise ImpactInputError("law", f"unknown {law!r}; known: {', '.join(COST_LAWS)}, or all")
    spec = COST_LAWS[law]
    known = [a.name for a in spec.axes]
    for a in axes or ():
        if a not in known:
            raise ImpactInputError("axis", f"{law} has no axis {a!r}; its axes: {', '.join(known)}")
    chosen = [a for a in spec.axes if not axes or a.name in axes]
    if sizes is not None:
        if len(chosen) != 1:
            raise ImpactInputError("sizes", f"{law} has axes {', '.join(known)}: name one with --axis to give sizes")
        lo, hi = chosen[0].limits
        bad = [s for s in sizes if not lo <= s <= hi]
        if bad:
            raise ImpactInputError("sizes", f"{law}, axis {chosen[0].name}: sizes must lie in [{lo}, {hi}], "
                                            f"got {bad[0]}")
    return chosen


def law_cost(law: str, quick: bool = False, axes=None, sizes=None, repeats: int = 3, max_call: float = MAX_CALL,
             progress=None) -> dict:
    """Measure ``law`` along its axes.

    Parameters
    ----------
    law : a name of :data:`COST_LAWS`
    quick : the small sizes (``Axis.quick``)
    axes : restrict to these axis names (default: every axis of the law)
    sizes : the sizes, with exactly one axis
    repeats : timed calls per size (one when a call is slower than :data:`SLOW_CALL`)
    max_call : a series stops before a call predicted to take longer (seconds)

    Returns
    -------
    dict
        ``law``, ``title``, ``paths`` (``["exact", "float"]`` or ``["float"]``), ``float_note``,
        ``axes``: per axis ``axis``, ``symbol``, ``description``, ``x``, ``also``, ``rows`` (per
        size: ``size``, the problem's facts, and per path ``seconds``, ``calls``, ``peak_kib`` and
        what the law reported (``states``, ``reflections``, ``steps``), or ``stopped`` with the
        reason), ``fits`` (per path: ``time`` and ``memory``, :func:`fit_growth` against ``x``,
        and ``time_vs_<also>``).

    Raises
    ------
    ImpactInputError
        an unknown law or axis, sizes with several axes, a size outside the axis' limits.
    """
    from .lawbook import LAWS as LAWBOOK

    chosen = check_request(law, axes, sizes)
    spec = COST_LAWS[law]
    t_start = time.perf_counter()
    paths = ["exact", "float"] if spec.exact else ["float"]
    out_axes = []
    for axis in chosen:
        sz = tuple(sizes) if sizes is not None else (axis.quick if quick else axis.sizes)
        per_path = {p: _series(law, axis, sz, p, repeats, max_call, progress) for p in paths}
        rows = []
        for size in sz:
            here = {p: next((r for r in per_path[p] if r["size"] == size), None) for p in paths}
            if all(v is None for v in here.values()):
                continue
            facts = axis.build(size).facts
            row = {"size": size, **facts, **{p: {k: v for k, v in r.items() if k != "size"}
                                             for p, r in here.items() if r is not None}}
            if axis.x != "size":  # a property of the problem: the exact path's count when there is one
                row[axis.x] = next((row[p][axis.x] for p in paths if p in row and axis.x in row[p]), None)
            rows.append(row)
        fits = {}
        for p in paths:
            done = [r for r in rows if p in r and "seconds" in r[p]]
            xs = [r[axis.x] if axis.x != "size" else r["size"] for r in done]
            fits[p] = {"time": fit_growth(xs, [r[p]["seconds"] for r in done], axis.symbol),
                       "memory": fit_growth(xs, [r[p]["peak_kib"] for r in done], axis.symbol)}
            if axis.also:
                fits[p][f"time_vs_{axis.also}"] = fit_growth([r[p].get(axis.also) for r in done],
                                                             [r[p]["seconds"] for r in done], axis.also)
        out_axes.append({"axis": axis.name, "symbol": axis.symbol, "description": axis.description, "x": axis.x,
                         "also": axis.also, "rows": rows, "fits": fits})
    return {"law": law, "title": LAWBOOK[law].title, "paths": paths, "float_note": spec.float_note,
            "axes": out_axes, "seconds": round(time.perf_counter() - t_start, 1)}


def run(laws=None, quick: bool = False, progress=None, max_call: float = MAX_CALL, axes=None, sizes=None) -> dict:
    """Every law (or ``laws``; ``axes`` and ``sizes`` as in :func:`law_cost`), with the machine
    and the load before and after."""
    laws = list(laws or COST_LAWS)
    for law in laws:
        check_request(law, axes, sizes)
    start = machine()
    date = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    t0 = time.perf_counter()
    results = [law_cost(law, quick=quick, axes=axes, sizes=sizes, progress=progress, max_call=max_call)
               for law in laws]
    return {"machine": start, "date": date, "load_end": _load(), "seconds": round(time.perf_counter() - t0, 1),
            "quick": quick,
            "max_call": max_call, "memory": "tracemalloc peak of one call (Python allocations incl. NumPy; "
                                            "FLINT/GMP memory outside Python's allocator not seen)",
            "results": results}


# ----------------------------------------------------------------------------------- machine
def _load():
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover
        return None


def machine() -> dict:
    """The CPU model (``/proc/cpuinfo``), cores, load average, Python and library versions."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:  # pragma: no cover
        pass
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover
        usable = os.cpu_count()
    versions = {}
    from importlib import metadata

    for pkg in ("sympy", "numpy", "mpmath", "python-flint", "scipy", "matplotlib"):
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            versions[pkg] = None
    return {"cpu": cpu, "cores": os.cpu_count(), "usable_cores": usable, "load_start": _load(),
            "python": f"{platform.python_implementation()} {platform.python_version()}",
            "platform": platform.platform(), "versions": versions}


# ---------------------------------------------------------------------------------- rendering
def _g(x, digits=3):
    return "-" if x is None else f"{x + 0.0:.{digits}g}"


def _size_text(x) -> str:
    return str(x) if x < 1e6 else f"{x:.3g}"


def _fit_text(f: dict | None) -> str:
    if not f or f.get("exponent") is None:
        return "-"
    se = "" if f["stderr"] is None else f" ± {f['stderr']:.2f}"
    return f"{f['exponent']:.2f}{se} (rms {f['rms']:.2f})"


def _growth(f: dict) -> str:
    """The named growth: from the largest sizes when that fit is good, else from all of them."""
    t = f.get("tail")
    if t and t["quality"] == "good":
        return f"{t['model']} (sizes ≥ {_size_text(t['from_size'])})"
    if f["quality"] == "good":
        return f["model"]
    return "poor fit" if f["quality"] == "poor" else "too few points"


def markdown(report: dict) -> str:
    """The summary of the fitted growth (every law, axis and path), then one table per law.

    >>> row = {"size": 3, "contacts": 2, "coordinates": 3, "float": {"seconds": 0.01, "peak_kib": 10.0, "calls": 3}}
    >>> f = fit_growth([3], [0.01])
    >>> r = {"law": "hertz", "title": "t", "paths": ["float"], "float_note": "n", "axes": [{"axis": "balls",
    ...      "symbol": "n", "description": "d", "x": "size", "also": None, "rows": [row],
    ...      "fits": {"float": {"time": f, "memory": f}}}]}
    >>> print(markdown({"results": [r]}).splitlines()[2])
    | hertz | balls | float | - | - | too few points | - |
    """
    out = ["| law | axis | path | time ~ size^k, all sizes (k ± s.e., rms of log residuals) | time ~ size^k, "
           "largest sizes | growth | peak memory ~ size^k |", "|---|---|---|---|---|---|---|"]
    for r in report["results"]:
        for a in r["axes"]:
            for p in r["paths"]:
                f = a["fits"][p]
                x = "reflections" if a["x"] == "reflections" else a["axis"]
                out.append(f"| {r['law']} | {x} | {p} | {_fit_text(f['time'])} | {_fit_text(f['time'].get('tail'))} | "
                           f"{_growth(f['time'])} | {_fit_text(f['memory'])} |")
                if a["also"]:
                    g = f[f"time_vs_{a['also']}"]
                    out.append(f"| {r['law']} | {a['axis']}: time against {a['also']} | {p} | {_fit_text(g)} | "
                               f"{_fit_text(g.get('tail'))} | {_growth(g)} | - |")
    for r in report["results"]:
        took = f" Measured in {r['seconds']:.0f} s." if r.get("seconds") is not None else ""
        out += ["", f"### {r['law']}", "", f"{r['title']}. Float path: {r['float_note']}.{took}", ""]
        for a in r["axes"]:
            out.append(f"- **{a['axis']}**: {a['description']}.")
        paths = r["paths"]
        extra = sorted({k for a in r["axes"] for row in a["rows"] for p in paths if p in row
                        for k in ("states", "reflections", "steps") if k in row[p]})
        head = "| axis | size | contacts | coordinates |" + "".join(f" {k} |" for k in extra)
        head += "".join(f" {p} s | {p} peak KiB |" for p in paths)
        out += ["", head, "|---|" + "---:|" * (head.count("|") - 2)]
        notes = []
        for a in r["axes"]:
            for row in a["rows"]:
                cells = [a["axis"], str(row["size"]), str(row.get("contacts", "-")), str(row.get("coordinates", "-"))]
                for k in extra:
                    v = row.get(k, next((row[p][k] for p in paths if p in row and k in row[p]), None))
                    cells.append("-" if v is None else str(v))
                for p in paths:
                    c = row.get(p)
                    if c is None or "seconds" not in c:
                        cells += ["-", "-"]
                        if c is not None:
                            notes.append(f"{a['axis']} {row['size']}, {p}: {c['stopped']}")
                        continue
                    flag = " (!)" if c.get("finite") is False or c.get("warnings") else ""
                    cells += [_g(c["seconds"]) + flag, _g(c["peak_kib"])]
                    where = f"{a['axis']} {row['size']}, {p}"
                    if c.get("finite") is False:
                        notes.append(f"{where}: the outcome holds NaN or infinity (returned without an error)")
                    for w in c.get("warnings", ()):
                        notes.append(f"{where}: warning {_short(w, 120)}")
                    if c.get("memory"):
                        notes.append(f"{where}: memory {c['memory']}")
                out.append("| " + " | ".join(cells) + " |")
        if notes:
            out += [""] + [f"- {n}" for n in notes]
        out += ["", f"![{r['law']}](cost_model/{r['law']}.png)"]
    return "\n".join(out)


def plot(result: dict, path) -> None:
    """One law's plot: per axis, time (top) and peak memory (bottom) against the size, log-log,
    one series per path, with the fitted line over the sizes of the growth it reports."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    axes = result["axes"]
    fig, grid = plt.subplots(2, len(axes), figsize=(4.2 * len(axes), 7), squeeze=False)
    style = {"exact": ("C0", "o"), "float": ("C1", "s")}
    for j, a in enumerate(axes):
        for i, (what, key, unit) in enumerate((("time", "seconds", "s"), ("memory", "peak_kib", "KiB"))):
            ax = grid[i][j]
            xs_all: set = set()
            for p in result["paths"]:
                pts = [(row.get(a["x"]) if a["x"] != "size" else row["size"], row[p][key])
                       for row in a["rows"] if p in row and key in row[p]]
                pts = [(x, y) for x, y in pts if x and y and x > 0 and y > 0]
                if not pts:
                    continue
                color, marker = style[p]
                f = a["fits"][p][what]
                use = f["tail"] if f.get("tail") and f["tail"]["quality"] == "good" else f
                label = p if use.get("exponent") is None else f"{p}: k = {use['exponent']:.2f}" + (
                    f" (sizes ≥ {use['from_size']:g})" if "from_size" in use else "")
                if use.get("quality") == "poor":
                    label = f"{p}: poor fit (k = {use['exponent']:.2f})"
                xs_all.update(x for x, _ in pts)
                ax.loglog([x for x, _ in pts], [y for _, y in pts], marker=marker, color=color, ls="-", lw=1,
                          label=label)
                if use.get("exponent") is not None and use.get("quality") != "poor":
                    lo = use["from_size"] if use is f.get("tail") else min(x for x, _ in pts)
                    xs = [x for x, _ in pts if x >= lo]
                    ax.loglog(xs, [math.exp(use["intercept"]) * x ** use["exponent"] for x in xs], color=color,
                              ls="--", lw=0.8)
            if xs_all and max(xs_all) / min(xs_all) < 1e5:  # label the sizes themselves, no minor labels
                ax.set_xticks(sorted(xs_all))
                ax.xaxis.set_major_formatter(ScalarFormatter())
                ax.xaxis.set_minor_formatter(NullFormatter())
            xl = "reflection count N" if a["x"] == "reflections" else f"{a['axis']} ({a['symbol']})"
            ax.set_xlabel(xl)
            ax.set_ylabel(f"{'median time' if what == 'time' else 'peak memory (tracemalloc)'} [{unit}]")
            if i == 0:
                ax.set_title(a["axis"])
            ax.grid(True, which="major", alpha=0.3)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=8)
    fig.suptitle(f"impactsym cost model: {result['law']} (dashed: fitted size^k)")
    from .figures._common import tight_layout_once

    tight_layout_once(fig).savefig(path, dpi=90)
    plt.close(fig)


def header(report: dict, command: str) -> str:
    """The markdown header: the command, the machine, the load, what is measured and how."""
    m = report["machine"]
    v = ", ".join(f"{k} {x}" for k, x in m["versions"].items() if x)
    ls, le = m["load_start"], report["load_end"]
    load = "unknown" if not ls else f"{ls[0]:.2f} at the start and {le[0]:.2f} at the end (1-minute)"
    when = f" on {report['date']}" if report.get("date") else ""
    mine = report.get("measured") or [r["law"] for r in report["results"]]
    kept = [r for r in report["results"] if r["law"] not in mine]
    earlier = ""
    if kept:
        earlier = (f"That run measured {', '.join(mine)}; the other laws' tables were kept from earlier runs "
                   "(a run of some laws replaces only theirs):\n\n" + "".join(
                       f"- {r['law']}: {_run_text(r.get('run'))}\n" for r in kept) + "\n")
    return (f"# Cost model of every law\n\n`{command}`{when} (one law: `impactsym bench --law NAME [--quick]`). "
            f"Taken on {m['cpu']}, {m['cores']} cores ({m['usable_cores']} usable), {m['platform']}; "
            f"{m['python']}; {v}. Load average {load}: a shared machine, other jobs were running. "
            f"{report['seconds']:.0f} s in all{' (quick sizes)' if report['quick'] else ''}.\n\n{earlier}"
            f"Each time is the median of at least three calls, and of as many as fit in {MIN_SECONDS} s (one call, "
            f"the first at that size, when it takes over {SLOW_CALL} s), each after emptying SymPy's cache (so "
            f"that a repeated call costs what a new problem of that size costs), through "
            f"`impactsym.lawbook.resolve`, after one warm-up call at the first size of each series; memory is "
            f"the {report['memory']}. "
            f"Exact path: SymPy integers and rationals in; float path: the same problem as float64 arrays. "
            f"k is the least-squares slope of log(cost) against log(size) (cost ~ size^k) with its standard "
            f"error and the rms of the log residuals; a fit with rms above {POOR_RMS} is called poor, and no "
            f"growth is named from it. \"Largest sizes\" fits the upper half of the sizes only (at least three), "
            f"where the fixed cost of a call no longer dominates; the growth column names it when that fit is "
            f"good. A series stops at a size whose call is predicted to exceed {report['max_call']:g} s, or that "
            f"the law refuses (listed under the law's table); a time marked (!) has a note there too (a warning "
            f"raised by the call, or an outcome that is not finite). Compare the exponents, not the absolute "
            f"times.\n\n")


def _run_record(report: dict, command: str | None) -> dict:
    """What measured a result: the command, the date, the machine, the load and the run's settings."""
    return {"command": command, "date": report.get("date"), "machine": report["machine"],
            "load_end": report.get("load_end"), "seconds": report.get("seconds"), "quick": report.get("quick"),
            "max_call": report.get("max_call")}


def _run_text(run: dict | None) -> str:
    if not run:
        return "an earlier run (not recorded)"
    m, ls, le = run["machine"], run["machine"].get("load_start"), run.get("load_end")
    load = "" if not ls or not le else f", load {ls[0]:.2f} to {le[0]:.2f}"
    when = f" on {run['date']}" if run.get("date") else ""
    quick = " (quick sizes)" if run.get("quick") else ""
    command = f"`{run['command']}`" if run.get("command") else "a run whose command and date were not recorded"
    return f"{command}{when}, {m['cpu']}{load}{quick}"


def read_results(out_dir) -> dict | None:
    """The cost model in ``out_dir/cost_model.json`` (None if there is none), each result with the
    run that measured it (``run``; results written before runs were recorded get their file's).

    Raises
    ------
    ImpactInputError
        (argument ``out``) the file is not a cost model this module wrote: it is not overwritten.
    """
    import json
    from pathlib import Path

    from .errors import ImpactInputError

    path = Path(out_dir) / "cost_model.json"
    if not path.exists():
        return None
    try:
        old = json.loads(path.read_text())
        results = old["results"]
        if not all(isinstance(r, dict) and isinstance(r["law"], str) and "axes" in r for r in results):
            raise ValueError("a result without its law or axes")
        base = _run_record(old, old.get("command")) if "machine" in old else None
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ImpactInputError("out", f"{path} is not a cost model written by impactsym "
                                      f"({type(exc).__name__}: {exc}); move it away or choose another directory")
    return dict(old, results=[r if "run" in r else dict(r, run=base) for r in results])


def write_results(report: dict, out_dir, command: str) -> list:
    """Write ``cost_model.md``, ``cost_model.json`` and ``cost_model/<law>.png`` into ``out_dir``.

    Each result records the run that measured it (``run``: ``command``, date, machine, load). If
    ``out_dir`` already holds a cost model (:func:`read_results`), the laws this report measured
    replace theirs and the others are kept, with their runs (named in the markdown's header) and
    plots, so that a run of one law updates that law alone. Returns the paths written.
    """
    import json
    from pathlib import Path

    out = Path(out_dir)
    old = read_results(out)
    measured = [r["law"] for r in report["results"]]
    report = dict(report, command=command, measured=measured,
                  results=[dict(r, run=r.get("run") or _run_record(report, command)) for r in report["results"]])
    if old is not None:
        order = list(COST_LAWS)
        results = report["results"] + [r for r in old["results"] if r["law"] not in measured]
        results.sort(key=lambda r: order.index(r["law"]) if r["law"] in order else len(order))
        report = dict(report, results=results)
    (out / "cost_model").mkdir(parents=True, exist_ok=True)
    written = []
    for r in report["results"]:
        if r["law"] not in measured:
            continue  # kept from an earlier run: its plot too
        p = out / "cost_model" / f"{r['law']}.png"
        plot(r, p)
        written.append(p)
    (out / "cost_model.md").write_text(header(report, command) + markdown(report) + "\n")
    (out / "cost_model.json").write_text(json.dumps(report, indent=1, default=_json_default) + "\n")
    return [out / "cost_model.md", out / "cost_model.json", *written]


def _json_default(x):
    return str(x)
