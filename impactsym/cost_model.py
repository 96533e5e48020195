"""How the cost of each law grows with the problem (``impactsym bench --law NAME``).

For each law, a family of problems of growing size, the time of one exact call (median of
``repeats``) and its peak Python memory (``tracemalloc``, one separate call), and the fitted growth:
the least-squares slope of ``log(time)`` (and of ``log(memory)``) against ``log(size)``, so
``time ~ size^k``. The sizes and what they count:

=============== ===================================== ======================================
law             problem                               size
=============== ===================================== ======================================
sequential      a cradle of n balls, one striker       n (coordinates; n − 1 contacts)
two-surface     two balls and a wall, masses 1 : 100^d the reflection count (≈ π·10^d)
newton          the same cradle                        n
poisson         the same cradle                        n
energetic       the same cradle                        n
han-gilmore     the same cradle                        n
impulse-ratio   the same cradle, every ratio 1         n
=============== ===================================== ======================================

Times depend on the machine and its load; the exponents are what to compare. Nothing here is
asserted about speed in the tests (they check the shape of the result and the fit).

Examples
--------
>>> fit_exponent([1, 2, 4, 8], [3.0, 6.0, 12.0, 24.0])
1.0
"""

from __future__ import annotations

import math
import platform
import statistics
import time
import tracemalloc
from dataclasses import dataclass
from typing import Callable

__all__ = ["LAWS", "DEFAULT_SIZES", "QUICK_SIZES", "law_cost", "fit_exponent", "markdown"]


@dataclass(frozen=True)
class LawProblem:
    """One law's family of problems: ``make(size) -> (call, facts)``; ``call()`` solves it once,
    ``facts`` describe it (contacts, coordinates, and for two surfaces the reflection count)."""

    size_name: str
    make: Callable[[int], tuple]
    description: str


def _cradle(n):
    from .models.seghete_murphey import cradle

    return cradle(n, 1)


def _facts(sc) -> dict:
    return {"contacts": int(sc.H.shape[0]), "coordinates": int(sc.M.shape[0])}


def _classical(name):
    def make(n):
        from .laws import classical

        sc = _cradle(n)
        law = getattr(classical, name)
        return (lambda: law(sc.M, sc.H, sc.v, 1)), _facts(sc)

    return make


def _sequential(n):
    from .laws.sequential import resolve_sequential

    sc = _cradle(n)
    return (lambda: resolve_sequential(sc.M, sc.H, sc.v)), _facts(sc)


def _impulse_ratio(n):
    from .laws.impulse_ratio import impulse_ratio_law

    sc = _cradle(n)
    ratios = [1] * (sc.H.shape[0] - 1)
    return (lambda: impulse_ratio_law(sc.M, sc.H, sc.v, 1, ratios)), _facts(sc)


def _two_surface(d):
    from .laws.two_surface import resolve_two_surfaces
    from .models.seghete_murphey import two_balls_wall

    sc = two_balls_wall(masses=(1, 100 ** d))
    r = resolve_two_surfaces(sc.M, sc.H, sc.v)
    count = max(int(o.reflections) for o in r.outcomes)
    return (lambda: resolve_two_surfaces(sc.M, sc.H, sc.v)), {**_facts(sc), "mass_ratio": f"1:100^{d}",
                                                              "reflections": count}


LAWS: dict[str, LawProblem] = {
    "sequential": LawProblem("balls", _sequential, "resolve_sequential on a one-striker cradle of n balls"),
    "two-surface": LawProblem("reflections", _two_surface, "resolve_two_surfaces on two balls and a wall, "
                                                            "masses 1 : 100^d (π·10^d reflections)"),
    "newton": LawProblem("balls", _classical("newton_moreau"), "newton_moreau on a one-striker cradle"),
    "poisson": LawProblem("balls", _classical("poisson"), "poisson on a one-striker cradle"),
    "energetic": LawProblem("balls", _classical("energetic"), "energetic on a one-striker cradle"),
    "han-gilmore": LawProblem("balls", _classical("han_gilmore"), "han_gilmore on a one-striker cradle"),
    "impulse-ratio": LawProblem("balls", _impulse_ratio, "impulse_ratio_law on a one-striker cradle, every ratio 1"),
}

#: the sizes of the committed run (``benchmarks/cost_model.py``); for two surfaces, d of 1 : 100^d
DEFAULT_SIZES = {"two-surface": (1, 2, 4, 8, 16, 32)}
DEFAULT_SIZES.update({law: (3, 4, 6, 8, 12, 16, 24, 32) for law in LAWS if law not in ("two-surface", "han-gilmore")})
DEFAULT_SIZES["han-gilmore"] = (3, 4, 5, 6)
#: small sizes (``impactsym bench --law NAME --quick``, and the tests)
QUICK_SIZES = {"two-surface": (1, 2, 4)}
QUICK_SIZES.update({law: (3, 4, 6) for law in LAWS if law not in ("two-surface", "han-gilmore")})
QUICK_SIZES["han-gilmore"] = (3, 4)


def fit_exponent(sizes, values) -> float | None:
    """Least-squares slope of ``log(values)`` against ``log(sizes)`` (``values ~ sizes^k``), rounded
    to 2 decimals; None with fewer than two distinct sizes or a non-positive value."""
    pts = [(math.log(s), math.log(v)) for s, v in zip(sizes, values) if s and s > 0 and v and v > 0]
    if len({x for x, _ in pts}) < 2:
        return None
    mx = statistics.fmean(x for x, _ in pts)
    my = statistics.fmean(y for _, y in pts)
    k = sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)
    return round(k, 2) + 0.0  # + 0.0: no -0.0


def law_cost(law: str, sizes=None, repeats: int = 3, min_seconds: float = 0.2) -> dict:
    """Measure ``law`` on its problem family at ``sizes`` (default :data:`DEFAULT_SIZES`).

    Returns
    -------
    dict
        ``law``, ``description``, ``size_name``, ``rows`` (per size: ``size``, ``contacts``,
        ``coordinates``, ``seconds`` (median of at least ``repeats`` calls, and of as many as fit in
        ``min_seconds``), ``peak_kib`` (tracemalloc peak of one call), for two surfaces ``reflections``
        and ``mass_ratio``; a size at which the law raises ``NonTermination`` is the last row, with
        ``stopped`` and no time), ``time_exponent`` and
        ``memory_exponent`` (the fitted growth against the size: reflections for two surfaces,
        balls otherwise), ``exact`` (True: every call is on the exact path), ``machine``.

    Raises
    ------
    KeyError
        an unknown law.
    """
    from .errors import NonTermination

    problem = LAWS[law]
    sizes = tuple(sizes or DEFAULT_SIZES[law])
    rows = []
    for size in sizes:
        call, facts = problem.make(size)
        try:
            call()  # warm caches (imports, generated kernels)
        except NonTermination as exc:  # the law gives up at this size: say so, stop growing
            rows.append({"size": size, **facts, "seconds": None, "peak_kib": None, "stopped": str(exc)})
            break
        times, start = [], time.perf_counter()
        while len(times) < repeats or (time.perf_counter() - start < min_seconds and len(times) < 1000):
            t0 = time.perf_counter()
            call()
            times.append(time.perf_counter() - t0)
        tracemalloc.start()
        try:
            call()
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        rows.append({"size": size, **facts, "seconds": statistics.median(times), "peak_kib": peak / 1024})
    done = [r for r in rows if r["seconds"] is not None]
    x = [r.get("reflections") or r["size"] for r in done] if law == "two-surface" else [r["size"] for r in done]
    return {"law": law, "description": problem.description, "size_name": problem.size_name, "exact": True,
            "rows": rows, "time_exponent": fit_exponent(x, [r["seconds"] for r in done]),
            "memory_exponent": fit_exponent(x, [r["peak_kib"] for r in done]),
            "machine": f"{platform.machine()}, {platform.python_implementation()} {platform.python_version()}, "
                       f"{_cpus()} CPUs"}


def _cpus() -> int:
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover
        return os.cpu_count() or 1


def markdown(results: list[dict]) -> str:
    """One table per law and a summary of the fitted growth.

    >>> r = {"law": "newton", "description": "d", "size_name": "balls", "rows": [{"size": 3, "contacts": 2,
    ...      "coordinates": 3, "seconds": 0.01, "peak_kib": 10.0}], "time_exponent": None,
    ...      "memory_exponent": None, "machine": "m"}
    >>> print(markdown([r]).splitlines()[2])
    | newton | balls | - | - |
    """
    def g(x):
        return "-" if x is None else f"{x + 0.0:.3g}"  # + 0.0: no "-0"

    out = ["| law | size | time ~ size^k | peak memory ~ size^k |", "|---|---|---:|---:|"]
    for r in results:
        out.append(f"| {r['law']} | {r['size_name']} | {g(r['time_exponent'])} | {g(r['memory_exponent'])} |")
    for r in results:
        out += ["", f"### {r['law']}: {r['description']}", ""]
        extra = "reflections" if r["law"] == "two-surface" else None
        head = "| size | contacts | coordinates |" + (" reflections |" if extra else "") + " seconds | peak KiB |"
        out += [head, "|" + "---:|" * (head.count("|") - 1)]
        for row in r["rows"]:
            out.append(f"| {row['size']} | {row['contacts']} | {row['coordinates']} |"
                       + (f" {row.get('reflections')} |" if extra else "")
                       + f" {g(row['seconds'])} | {g(row['peak_kib'])} |")
        stopped = [row for row in r["rows"] if row.get("stopped")]
        if stopped:
            out += ["", f"Stopped at size {stopped[0]['size']}: {stopped[0]['stopped']}"]
    return "\n".join(out)
