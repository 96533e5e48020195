"""The hard-case set of the generated float kernels, and uniform samples of their valid domains.

One named, committed list (:data:`HARD_CASES`) reused by the tests (``tests/test_kernels_*.py``)
and the benchmark (``impactsym bench``). Each case names the kernel, the category of difficulty
(:data:`CATEGORIES`), and float inputs; the reference for a case is computed from the exact binary
values of these floats (:mod:`impactsym.reference_values`), never from decimal text. The generated
corner grid, the adversarial search and the accuracy check that run on these cases live in
:mod:`impactsym.accuracy`.

Examples
--------
>>> sorted({c.category for c in HARD_CASES}) == sorted(CATEGORIES)
True
>>> [c.name for c in hard_cases("impulse_ratio_root")][:2]
['delta->0+ D/B^2=1e-08', 'delta->0+ D/B^2=1e-12']
>>> s = domain_sample("impulse_ratio_root", 4, seed=0); sorted(s), s["A"].shape
(['A', 'B', 'C'], (4,))
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["HardCase", "HARD_CASES", "CATEGORIES", "hard_cases", "domain_sample", "DOMAIN_KERNELS"]

#: category -> what makes it hard
CATEGORIES = {
    "delta->0+": "discriminant D = B^2 - 4AC -> 0+: the root's condition number grows like B^2/D",
    "alpha->0": "impulse ratio alpha -> 0 (second contact carries no impulse)",
    "alpha->1": "impulse ratio alpha -> 1",
    "alpha->inf": "impulse ratio alpha -> infinity (primary contact carries almost none)",
    "e-corner": "energetic coefficient / restitution at the corners of its domain (0, 1, and 1/3 for eq. 19)",
    "grazing": "approach velocity -> 0 (u v -> 0, B -> 0-)",
    "theta->pi/2": "pool angle theta -> pi/2",
    "mass-ratio": "mass ratios from 1e-12 to 1e12",
    "nearly-parallel": "nearly parallel constraint gradients (kinetic angle -> pi)",
    "ill-conditioned-M": "mass matrix with condition number 1e8 and 1e12",
    "wedge-angle": "two-surface wedge angle beta down to 1e-9 (reflection counts ~ pi/beta, in the billions)",
    "corner": "a combination of every argument's extreme values (corner_cases)",
    "search": "found by the adversarial search (adversarial_search)",
}


@dataclass(frozen=True)
class HardCase:
    """One hard input of one kernel."""

    kernel: str
    name: str
    category: str
    inputs: dict = field(hash=False)
    note: str = ""


def _spd(n: int, kappa: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    M = (Q * np.geomspace(1.0, 1.0 / kappa, n)) @ Q.T
    return (M + M.T) / 2


def _reflect_inputs(M, u, v, e) -> dict:
    n = len(u)
    d = {f"m_{i}{j}": float(M[i][j]) for i in range(n) for j in range(i, n)}
    d.update({f"u_{i}": float(u[i]) for i in range(n)})
    d.update({f"v_{i}": float(v[i]) for i in range(n)})
    d["e"] = float(e)
    return d


def _reflection_cases() -> list[HardCase]:
    out = []
    for n in (2, 3):
        k = f"reflect_{n}"
        ch = [-1.0, 1.0] + [0.0] * (n - 2)
        v0 = [1.0] + [0.0] * (n - 1)
        for r in (1e-12, 1e-6, 1e6, 1e12):
            M = np.diag([1.0, r] + [1.0] * (n - 2))
            out.append(HardCase(k, f"mass ratio {r:g}", "mass-ratio", _reflect_inputs(M, ch, v0, 1.0)))
        M = np.diag([1.0, 1.0 + 2.0**-30] + [1.0] * (n - 2))
        out.append(HardCase(k, "equal masses + 2^-30 (exchange: w0 ~ 1e-10)", "mass-ratio",
                            _reflect_inputs(M, ch, v0, 1.0), "ill-conditioned by nature: w0 = (m1-m2)/(m1+m2)"))
        for kappa in (1e8, 1e12):
            for seed in (0, 1):
                M = _spd(n, kappa, seed)
                rng = np.random.default_rng(100 + seed)
                out.append(HardCase(k, f"cond(M)={kappa:g} seed {seed}", "ill-conditioned-M",
                                    _reflect_inputs(M, rng.normal(size=n), rng.normal(size=n), 0.5)))
        for e in (0.0, 1.0):
            out.append(HardCase(k, f"e={e:g}", "e-corner", _reflect_inputs(_spd(n, 10.0, 7), [1.0, -2.0, 0.5][:n],
                                                                         [-1.0, 0.25, 2.0][:n], e)))
        for g in (1e-8, 1e-14):
            v = [1.0, 1.0 + g] + [0.0] * (n - 2)
            out.append(HardCase(k, f"grazing u.v={g:g}", "grazing", _reflect_inputs(np.eye(n), ch, v, 1.0)))
    return out


def _root_cases() -> list[HardCase]:
    k = "impulse_ratio_root"
    out = []
    for d in (1e-8, 1e-12, 1e-15):
        # A p^2 + B p + C with B = -2, A = 1: D = 4 - 4C = 4 d  ->  C = 1 - d
        out.append(HardCase(k, f"delta->0+ D/B^2={d:g}", "delta->0+", {"A": 1.0, "B": -2.0, "C": 1.0 - d},
                            "ill-conditioned by nature (kappa ~ 1/d)"))
    for e in (1.0, 1.0 - 1e-12, math.nextafter(1.0 / 3.0, 1.0)):
        # chain at unit speed: A = alpha^2 - alpha + 1 (alpha = 1/2), B = -1, C = (1 - e)/2; D = 0 at e = 1/3
        out.append(HardCase(k, f"chain alpha=1/2 e={e!r}", "e-corner", {"A": 0.75, "B": -1.0, "C": (1.0 - e) / 2}))
    for b in (1e-8, 1e-150):
        out.append(HardCase(k, f"grazing B=-{b:g}, C={b * b / 8:g}", "grazing", {"A": 1.0, "B": -b, "C": b * b / 8}))
    for a in (1e-12, 1e12):
        out.append(HardCase(k, f"alpha->{'0' if a < 1 else 'inf'} (A=1-a+a^2 at a={a:g}, C tiny)",
                            "alpha->0" if a < 1 else "alpha->inf", {"A": 1.0 - a + a * a, "B": -1.0, "C": 1e-30}))
    out.append(HardCase(k, "alpha->1 (A=1-a+a^2 at a=1-2^-40)", "alpha->1",
                        {"A": 1.0 - (1 - 2.0**-40) + (1 - 2.0**-40) ** 2, "B": -1.0, "C": 0.25}))
    return out


def _chain3_cases() -> list[HardCase]:
    k = "chain3_impulse_ratio"
    base = {"m1": 1.0, "m2": 1.0, "m3": 1.0, "v1": 1.0, "v2": 0.0, "v3": 0.0}
    out = []
    for a in (1e-12, 1e-6):
        out.append(HardCase(k, f"alpha={a:g}", "alpha->0", {**base, "e": 1.0, "alpha": a}))
    for a in (1 - 1e-9, 1 + 1e-9, 1.0):
        out.append(HardCase(k, f"alpha={a!r}", "alpha->1", {**base, "e": 1.0, "alpha": a}))
    for a in (1e6, 1e12):
        out.append(HardCase(k, f"alpha={a:g}", "alpha->inf", {**base, "e": 1.0, "alpha": a}))
    for e in (1.0, math.nextafter(1.0 / 3.0, 1.0), 1.0 / 3.0 + 1e-9):
        # alpha = 1/2 is admissible down to e = 1/3 (eq. 19), where D = 0
        out.append(HardCase(k, f"e={e!r} alpha=1/2", "e-corner", {**base, "e": e, "alpha": 0.5}))
    for r in (1e-12, 1e-6, 1e6, 1e12):
        out.append(HardCase(k, f"m2/m1={r:g}", "mass-ratio", {**base, "m2": r, "e": 1.0, "alpha": 0.5}))
        out.append(HardCase(k, f"m3/m1={r:g}", "mass-ratio", {**base, "m3": r, "e": 1.0, "alpha": 0.5}))
    out.append(HardCase(k, "grazing v1=1e-12", "grazing", {**base, "v1": 1e-12, "e": 1.0, "alpha": 0.5}))
    return out


def _two_surface_cases() -> list[HardCase]:
    k = "two_surface_resolution"
    out = []
    for beta in (1e-3, 1e-6, 1e-7):
        # unit-speed gradients (s_a = s_b = 1), kinetic angle pi - beta: g = cos(angle) = -cos(beta).
        # Below beta ~ 1e-8, -cos(beta) rounds to -1.0 and the float inputs (s_a, s_b, g) describe a
        # degenerate wedge (Delta = 0): such wedges are given through M and H instead (below).
        out.append(HardCase(k, f"wedge beta={beta:g}", "wedge-angle",
                            {"s_a": 1.0, "s_b": 1.0, "g": -math.cos(beta), "c_a": -1.0, "c_b": 0.5},
                            "ill-conditioned by nature in (s_a, s_b, g): d beta / d g ~ 1/beta"))
        out.append(HardCase(k, f"nearly parallel, beta={beta:g}, both approaching", "nearly-parallel",
                            {"s_a": 2.0, "s_b": 0.5, "g": -math.cos(beta), "c_a": -1.0, "c_b": -0.25}))
    for beta in (1e-3, 1e-6, 1e-9):
        # M = I, rows (1, 0) and (-cos beta, sin beta): wedge angle beta, representable down to 1e-9
        # (reflection counts ~ pi/beta ~ 3e9)
        h = {"m_00": 1.0, "m_01": 0.0, "m_11": 1.0, "h_00": 1.0, "h_01": 0.0,
             "h_10": -math.cos(beta), "h_11": math.sin(beta)}
        out.append(HardCase("two_surface_resolution_2", f"wedge beta={beta:g} (M, H form)", "wedge-angle",
                            {**h, "v_0": -1.0, "v_1": 0.5}))
        out.append(HardCase("two_surface_resolution_2", f"nearly parallel, beta={beta:g}, M ill-conditioned",
                            "nearly-parallel", {**h, "m_00": 1e6, "m_11": 1e-6, "v_0": -1.0, "v_1": -0.5}))
    return out


def _pool_cases() -> list[HardCase]:
    out = []
    for t in (1e-3, 1e-6, 1e-9):
        out.append(HardCase("pool_impulse_ratio", f"grazing tau=pi/2-{t:g}, theta=pi/4", "grazing",
                            {"theta": math.pi / 4, "tau": math.pi / 2 - t, "e": 1.0, "alpha": 0.5}))
        out.append(HardCase("pool_impulse_ratio", f"theta=pi/2-{t:g}, tau=0", "theta->pi/2",
                            {"theta": math.pi / 2 - t, "tau": 0.0, "e": 1.0, "alpha": 0.5}))
    for a in (1e-9, 1e9):
        out.append(HardCase("pool_impulse_ratio", f"alpha={a:g}, theta=pi/6", "alpha->0" if a < 1 else "alpha->inf",
                            {"theta": math.pi / 6, "tau": 0.0, "e": 1.0, "alpha": a}))
    for e in (0.0, 1.0):
        out.append(HardCase("pool_impulse_ratio", f"e={e:g}, theta=pi/6, alpha=1/4", "e-corner",
                            {"theta": math.pi / 6, "tau": 0.0, "e": e, "alpha": 0.25}))
    for t in (1e-6, 1e-9):
        out.append(HardCase("bernoulli_impulse_ratio", f"grazing tau=pi/2-{t:g}", "grazing",
                            {"tau": -(math.pi / 2 - t), "e": 1.0, "alpha": 0.5, "alpha13": 0.5}))
    return out


def _domain_cases() -> list[HardCase]:
    out = []
    for t in (1e-6, 1e-9):
        out.append(HardCase("pool_g", f"theta=pi/2-{t:g}", "theta->pi/2", {"theta": math.pi / 2 - t, "alpha": 0.5}))
        out.append(HardCase("pool_h", f"theta=pi/2-{t:g}", "theta->pi/2", {"theta": math.pi / 2 - t, "alpha": 0.5}))
    for e in (math.nextafter(1.0 / 3.0, 1.0), 1.0, 1.0 / 3.0 + 1e-12):
        out.append(HardCase("chain3_alpha_max", f"e={e!r}", "e-corner", {"e": e},
                            "sqrt(6e - 2) -> 0 at e = 1/3: ill-conditioned by nature"))
    return out


def _found_cases() -> list[HardCase]:
    """Corners that broke a kernel before issue 15's stable forms, and the search's worst finds,
    pinned so that every test and the bench see them."""
    out = [
        HardCase("chain3_impulse_ratio", "issue 15: masses (1, 1e-12, 1), alpha = 1 - 1e-12", "corner",
                 {"m1": 1.0, "m2": 1e-12, "m3": 1.0, "v1": 1.0, "v2": 0.0, "v3": 0.0, "e": 1.0, "alpha": 1 - 1e-12},
                 "expanded m1 m3 (1 - alpha)^2 gave p1 = 0.999911 (true 1.0000000000005), w1 of the wrong sign"),
        HardCase("chain3_impulse_ratio", "masses (1e-12, 1e-12, 1e12), e = 0, alpha = 1: no solution", "corner",
                 {"m1": 1e-12, "m2": 1e-12, "m3": 1e12, "v1": 1.0, "v2": 0.0, "v3": 0.0, "e": 0.0, "alpha": 1.0},
                 "exact D = -1e-24; the expanded B^2 - 4AC rounded to 0 and answered a number"),
        HardCase("chain3_impulse_ratio", "masses (1e-12, 1e-12, 1e-12), e = 1, alpha = 1e12", "corner",
                 {"m1": 1e-12, "m2": 1e-12, "m3": 1e-12, "v1": 1.0, "v2": 0.0, "v3": 0.0, "e": 1.0, "alpha": 1e12},
                 "D = B^2 exactly at e = 1; a Lagrange-only form 2eA|y|^2 - |x^y|^2 cancelled to < 0"),
        HardCase("pool_impulse_ratio", "theta = pi/2, tau = 1e-9, alpha = 1e-12", "corner",
                 {"theta": math.pi / 2, "tau": 1e-9, "e": 1.0, "alpha": 1e-12},
                 "cos(tau - theta) with the rounded angle difference: 1.9e8 eps of a well-conditioned w1x"),
    ]
    for k in ("reflect_2", "reflection_map_2"):
        x = {"m_00": 1.0, "m_01": 0.0, "m_11": 1e-12, "u_0": -1.0, "u_1": 1.0, "e": 0.0}
        if k == "reflect_2":
            x.update(v_0=1.0, v_1=0.5)
        out.append(HardCase(k, "M = diag(1, 1e-12), u = (-1, 1), e = 0", "corner", x,
                            "diagonal 1 - (1+e) u_i w_i / s cancelled: 1e11 eps"))
    out.append(HardCase("reflect_2", "search seed 1-2 worst (benchmarks/accuracy.py)", "search",
                        {"m_00": 1.0000000001695335, "m_01": 0.0, "m_11": 9.999999999999984e-13,
                         "u_0": -79.90654339251782, "u_1": 1.0000408260648348, "v_0": 1.0000000339631019,
                         "v_1": 1.1159635333570988e-09, "e": 0.9999999999989999}))
    return out


#: every hard case, all kernels
HARD_CASES: list[HardCase] = (_reflection_cases() + _root_cases() + _chain3_cases() + _two_surface_cases()
                              + _pool_cases() + _domain_cases() + _found_cases())


def hard_cases(kernel: str | None = None) -> list[HardCase]:
    """The hard cases of one kernel (all when ``kernel`` is None)."""
    return [c for c in HARD_CASES if kernel is None or c.kernel == kernel]


def _sample_reflect(n: int, size: int, rng) -> dict:
    out = {}
    L = rng.uniform(-1, 1, size=(size, n, n)) + 2 * np.eye(n)
    M = L @ np.swapaxes(L, -1, -2)
    for i in range(n):
        for j in range(i, n):
            out[f"m_{i}{j}"] = M[:, i, j]
    for i in range(n):
        out[f"u_{i}"] = rng.uniform(-1, 1, size)
        out[f"v_{i}"] = rng.uniform(-1, 1, size)
    out["e"] = rng.uniform(0, 1, size)
    return out


def _sample_root(size, rng) -> dict:
    A = rng.uniform(0.1, 10, size)
    B = -rng.uniform(0.1, 10, size)
    C = rng.uniform(0, 1, size) * B * B / (4 * A)  # D >= 0
    return {"A": A, "B": B, "C": C}


def _sample_chain3(size, rng) -> dict:
    m = {f"m{i}": rng.uniform(0.1, 10, size) for i in (1, 2, 3)}
    return {**m, "v1": rng.uniform(0.1, 2, size), "v2": np.zeros(size), "v3": np.zeros(size),
            "e": rng.uniform(0.5, 1, size), "alpha": rng.uniform(0.05, 1.0, size)}


def _sample_two_surface(size, rng) -> dict:
    beta = rng.uniform(0.05, math.pi - 0.05, size)
    return {"s_a": rng.uniform(0.1, 10, size), "s_b": rng.uniform(0.1, 10, size), "g": None, "beta": beta,
            "c_a": -rng.uniform(0.1, 1, size), "c_b": rng.uniform(-1, 1, size)}


def domain_sample(kernel: str, size: int, seed: int = 0) -> dict:
    """A uniform sample of ``kernel``'s valid domain (arrays keyed by argument name).

    Domains: reflection — SPD ``M = LLᵀ`` (``L = 2I + U(−1,1)``), ``u, v ∈ U(−1,1)``, ``e ∈ U(0,1)``;
    impulse-ratio root — ``A ∈ U(0.1,10)``, ``B ∈ −U(0.1,10)``, ``C ∈ U(0,1)·B²/(4A)`` (``D ≥ 0``);
    chain3 — masses ``U(0.1,10)``, ``v1 ∈ U(0.1,2)``, ``v2 = v3 = 0``, ``e ∈ U(0.5,1)``, ``α ∈ U(0.05,1)``;
    two-surface — ``s ∈ U(0.1,10)``, kinetic angle ``π − β`` with ``β ∈ U(0.05, π−0.05)``;
    pool — ``θ ∈ U(0.1,1.2)``, ``τ ∈ U(−0.3,0.3)``, ``e ∈ U(0.8,1)``, ``α ∈ U(0.05,0.6)`` (points outside
    the law's validity domain are answered NaN and left out of the error statistics).
    """
    rng = np.random.default_rng(seed)
    if kernel in ("reflect_2", "reflect_3"):
        return _sample_reflect(int(kernel[-1]), size, rng)
    if kernel in ("impulse_ratio_root", "impulse_ratio_root_naive"):
        return _sample_root(size, rng)
    if kernel == "chain3_impulse_ratio":
        return _sample_chain3(size, rng)
    if kernel == "pool_impulse_ratio":
        return {"theta": rng.uniform(0.1, 1.2, size), "tau": rng.uniform(-0.3, 0.3, size),
                "e": rng.uniform(0.8, 1.0, size), "alpha": rng.uniform(0.05, 0.6, size)}
    if kernel == "two_surface_resolution_2":
        L = rng.uniform(-1, 1, size=(size, 2, 2)) + 2 * np.eye(2)
        M = L @ np.swapaxes(L, -1, -2)
        beta = rng.uniform(0.05, math.pi - 0.05, size)
        phi = rng.uniform(0, 2 * math.pi, size)
        return {"m_00": M[:, 0, 0], "m_01": M[:, 0, 1], "m_11": M[:, 1, 1],
                "h_00": np.cos(phi), "h_01": np.sin(phi), "h_10": -np.cos(phi + beta), "h_11": -np.sin(phi + beta),
                "v_0": rng.uniform(-1, 1, size), "v_1": rng.uniform(-1, 1, size)}
    if kernel == "two_surface_resolution":
        d = _sample_two_surface(size, rng)
        beta = d.pop("beta")
        d["g"] = -np.cos(beta) * np.sqrt(d["s_a"] * d["s_b"])
        return d
    raise KeyError(f"no domain sampler for kernel {kernel!r}; known: {', '.join(DOMAIN_KERNELS)}")


DOMAIN_KERNELS = ("reflect_2", "reflect_3", "impulse_ratio_root", "impulse_ratio_root_naive",
                  "chain3_impulse_ratio", "two_surface_resolution", "two_surface_resolution_2", "pool_impulse_ratio")
