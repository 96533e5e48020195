"""How cost grows: derivation + codegen time against chain length, kernel time against batch size,
exact-arithmetic cost against the size of the numbers. Used by ``benchmarks/run.py``."""

from __future__ import annotations

import time
from fractions import Fraction

import numpy as np
import sympy as sp


def chain_derivation(n: int) -> dict:
    """Derive the impulse-ratio law of a chain of ``n`` balls (``n − 1`` contacts, symbolic masses,
    velocities, e and ratios) and generate its NumPy and C kernels; seconds of each step."""
    from derivations.codegen import ScalarKernel, kernel_code
    from derivations.impulse_ratio import general_quadratic
    from derivations.impulse_ratio_root import stable_roots, coefficients

    t0 = time.perf_counter()
    m = sp.symbols(f"m1:{n + 1}", positive=True)
    v = sp.symbols(f"v1:{n + 1}", real=True)
    e = sp.Symbol("e", positive=True)
    al = sp.symbols(f"alpha2:{n}", positive=True)
    H = sp.zeros(n - 1, n)
    for i in range(n - 1):
        H[i, i], H[i, i + 1] = -1, 1
    law = general_quadratic(sp.diag(*m), H, sp.Matrix(v), e, list(al))
    A, B, C = coefficients()
    p1 = stable_roots()[0].subs({A: law.A, B: law.B, C: law.C}, simultaneous=True)
    a = sp.Matrix([1, *al])
    w = sp.Matrix(v) + sp.diag(*m).inv() * H.T * a * p1
    t1 = time.perf_counter()
    k = ScalarKernel(f"chain{n}_impulse_ratio", [*m, *v, e, *al], [p1, *[x * p1 for x in al], *w],
                     ["p1", *[f"p{j}" for j in range(2, n)], *[f"w{j}" for j in range(1, n + 1)]], f"chain of {n}")
    numpy_src = kernel_code(k, "numpy")
    c_src = kernel_code(k, "c")
    t2 = time.perf_counter()
    return {"balls": n, "contacts": n - 1, "derive_seconds": t1 - t0, "codegen_seconds": t2 - t1,
            "c_lines": c_src.count("\n") + 1, "numpy_lines": numpy_src.count("\n") + 1}


def batch_scaling(sizes) -> list[dict]:
    """Seconds per evaluation of the chain3 kernel, NumPy and C loop, against batch size."""
    from impactsym import bench as benchmark, kernels as K
    from impactsym.hard_cases import domain_sample

    lib = benchmark.compile_c()
    out = []
    for n in sizes:
        x = domain_sample("chain3_impulse_ratio", n, seed=5)
        reps = max(3, int(2e6 // n))
        reps = min(reps, 2000)
        row = {"batch": n}
        for name, fn in (("numpy", lambda: K.chain3_impulse_ratio(**x)),
                         ("c-loop", lambda: benchmark._c_batch(lib, "chain3_impulse_ratio", x))):
            if name == "c-loop" and lib is None:
                continue
            fn()
            best = float("inf")
            for _ in range(min(reps, 7)):
                t0 = time.perf_counter()
                for _ in range(max(1, reps // 7)):
                    fn()
                best = min(best, (time.perf_counter() - t0) / max(1, reps // 7))
            row[f"{name}_seconds_per_eval"] = best / n
        out.append(row)
    return out


def _digits(d: int, rng) -> Fraction:
    return Fraction(int(rng.integers(1, 10)) * 10 ** (d - 1) + int(rng.integers(0, 10 ** min(d - 1, 18) or 1)),
                    int(rng.integers(1, 10)) * 10 ** (d - 1) + 7)


def exact_scaling(digit_sizes) -> list[dict]:
    """Seconds per exact evaluation of G_u(e) v for n = 2 against the number of digits of the
    rational inputs: the SymPy law (impactsym.reflect), the generated pure-Python kernel on
    Fractions, and the same on python-flint fmpq."""
    import impactsym
    from impactsym.cli.codegen import catalog

    code = next(k for k in catalog()["kernels"] if k["name"] == "reflect_2")["code"]["python"]
    ns: dict = {}
    exec(code, ns)  # the generated pure-Python kernel (only + - * /: exact on Fractions and fmpq)
    reflect_2 = ns["reflect_2"]
    try:
        import flint
    except ImportError:  # pragma: no cover
        flint = None
    rng = np.random.default_rng(0)
    out = []
    for d in digit_sizes:
        m00, m11, u0, u1, v0, v1 = (_digits(d, rng) for _ in range(6))
        m00 += m11  # keep M SPD: m01 = 0 < sqrt(m00 m11)
        m01 = Fraction(0)
        args = (m00, m01, m11, u0, -u1, v0, v1, Fraction(1))
        row = {"digits": d}
        t0 = time.perf_counter()
        impactsym.reflect(sp.Matrix([[sp.Rational(m00), 0], [0, sp.Rational(m11)]]),
                          sp.Matrix([sp.Rational(u0), -sp.Rational(u1)]), sp.Matrix([sp.Rational(v0), sp.Rational(v1)]))
        row["sympy_law_seconds"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        ref = reflect_2(*args)
        row["fraction_kernel_seconds"] = time.perf_counter() - t0
        if flint is not None:
            fargs = [flint.fmpq(x.numerator, x.denominator) for x in args]
            t0 = time.perf_counter()
            got = reflect_2(*fargs)
            row["fmpq_kernel_seconds"] = time.perf_counter() - t0
            assert all(Fraction(int(g.p), int(g.q)) == r for g, r in zip(got, ref))
        row["result_digits"] = max(int(x.denominator.bit_length() * 0.30103) + 1 for x in ref)
        out.append(row)
    return out
