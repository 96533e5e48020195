"""The accuracy check of the generated kernels against the high-precision reference: corner grid
and adversarial search (issue 15).

A generator of every combination of each kernel's extreme corners (:func:`corner_cases`); the
implementations of one kernel in every language (:func:`kernel_implementations`: NumPy, plain
Python, C); the check of every output of every implementation against the bound
``|f̂ − f| ≤ bound · eps · (|f| + Σ_j |x_j ∂f/∂x_j|)`` (:func:`accuracy_check`); and a seeded
adversarial hill-climb on that ratio (:func:`adversarial_search`); random hard wedges for the
two-surface kernels (:func:`wedge_samples`). The general-dimension kernels (``reflect``,
``reflection_map``, ``two_surface_exit_velocity``) are on the grid at n = 2 and 3
(:data:`GENERAL_KERNELS`), against the exact formulas of the closed forms of the same maps. Run by
``tests/test_accuracy_search.py`` and ``benchmarks/accuracy.py``. The fixed hard-case list the
grid complements is :mod:`impactsym.hard_cases`.

The criterion, output by output
-------------------------------
Let ``x`` be the input, ``eps = 2^-52``, ``bound = 64`` and ``N(x)`` the box of inputs ``x'`` with
``|x'_j − x_j| ≤ bound · eps · |x_j|`` for every ``j`` (zeros stay zero).

* **Continuous outputs** (every output except those in :data:`DISCONTINUOUS`): pointwise,
  ``|f̂(x) − f(x)| ≤ bound · eps · (|f(x)| + Σ_j |x_j ∂f/∂x_j(x)|)``, with ``f`` and the
  sensitivity computed from the emitted SymPy formula at ≥ 50 digits, precision-ladder checked
  (:mod:`impactsym.reference_values`). A number where the exact value is NaN (a branch that does
  not exist) and NaN where it is a number are violations. The two-surface exits are continuous
  where their count jumps (the extra reflection acts on a component that is exactly 0 there), but
  NaN off their branch; only where ``N(x)`` certifiably crosses a count boundary or the branch's
  edge (a witness of ``N(x)`` whose certified count differs from the count at ``x``) the value is
  instead held to the bound around the exact value at such a witness
  (:func:`value_in_neighbourhood`, mixed forward-backward). Where ``N(x)`` holds one count nothing
  is relaxed.
* **Where the exact value is not real** (a formula's domain): the kernel must answer NaN, unless
  the exact value is real at some input of ``N(x)`` (sampled corners of the box).
* **Discontinuous outputs** (integer counts ``⌈ψ/β⌉``, :data:`DISCONTINUOUS`): at an input within
  rounding of a count boundary no float evaluation is forward accurate (the count jumps under a
  relative perturbation ``eps``: the condition number is infinite there), so the criterion is
  mixed forward-backward: the kernel's count must be the exact count at *some* input of
  ``N(x)``. Away from every boundary ``N(x)`` holds one count, and the kernel must return it
  exactly. Decided with certainty (:func:`count_in_neighbourhood`): the counts compared are the
  law's certified counts (:data:`COUNT_ORACLES`: Arb enclosures and exact tie tests) at exact
  rational points of ``N(x)``; a count is accepted only when a certified witness in ``N(x)`` has
  it, or it lies between the counts of witnesses joined to ``x`` by segments on which ``ψ/β`` is
  continuous (sign conditions checked exactly along each segment), by the intermediate value
  theorem. ``N(x)`` is componentwise in the kernel's own inputs: a right-angle wedge
  whose ``ψ/β = 2 + 8e-17`` (``s = (1e-12, 1)``, ``g = −6e-23``, ``c = (−1, −1e-12)``, the branch
  that starts with B) is not within rounding of the boundary: the iterate after two reflections
  still violates B by ``1.2e-10``, against ``c_b = −1e-12`` (moving the count takes a relative
  change of order ``1e2`` in an input, not ``eps``), and the kernel must answer 3 there.

Examples
--------
>>> sorted({c.category for c in corner_cases("impulse_ratio_root")})
['corner']
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from flint import fmpq

from .hard_cases import HardCase, _spd

__all__ = ["corner_cases", "CORNER_KERNELS", "GENERAL_KERNELS", "reference", "DISCONTINUOUS", "COUNT_ORACLES", "count_in_neighbourhood",
           "value_in_neighbourhood", "wedge_samples",
           "kernel_implementations", "Verdict", "accuracy_check", "SearchResult", "SEARCH_DOMAIN", "adversarial_search"]


# Issue 15: a fixed list never combined the corners that break a form (masses (1, 1e-12, 1) with
# alpha = 1 - 1e-12 broke chain3 by 1e11 eps). The grid below is every combination of each
# argument's extreme values (kernel by kernel, arguments that only make sense together, such as a
# mass matrix or a wedge, vary as one axis); the search climbs from the worst grid points.

#: outputs that are integers and jump (reflection counts): no condition number bounds their error
#: at a jump; each must be the certified count of some input within ``bound · eps`` (relative) of
#: the given one (:func:`count_in_neighbourhood`), instead of the ratio
DISCONTINUOUS = {"two_surface_reflection_count": ("count_a", "count_b"),
                 "two_surface_resolution": ("count_a", "count_b"),
                 "two_surface_resolution_2": ("count_a", "count_b"),
                 "two_surface_exit_velocity_2": ("count_a", "count_b"),
                 "two_surface_exit_velocity_3": ("count_a", "count_b")}

#: the general-dimension kernels (matrices in, any n) on the grid at a fixed n: grid name ->
#: (kernel, n, the closed-form kernel of the same map at that n, whose exact formulas are the
#: reference and whose corners are the grid). ``two_surface_exit_velocity_3`` is the n = 2 map with a
#: third coordinate decoupled (``M = diag(M_2, m_22)``, ``H``'s third column 0, ``v_2``): the exits'
#: first two components are the n = 2 map's, the third is ``v_2`` (NaN off the branch).
GENERAL_KERNELS = {"reflection_map_general_2": ("reflection_map", 2, "reflection_map_2"),
                   "reflection_map_general_3": ("reflection_map", 3, "reflection_map_3"),
                   "reflect_general_2": ("reflect", 2, "reflect_2"),
                   "reflect_general_3": ("reflect", 3, "reflect_3"),
                   "two_surface_exit_velocity_2": ("two_surface_exit_velocity", 2, "two_surface_resolution_2"),
                   "two_surface_exit_velocity_3": ("two_surface_exit_velocity", 3, "two_surface_resolution_2")}

_TINY, _BIG = 1e-12, 1e12
_NEAR1 = (1 - 1e-12, 1.0, 1 + 1e-12)
_PI = math.pi


def _axis(name, values):
    return [{name: float(v)} for v in values]


def _m2(M) -> dict:
    return {"m_00": float(M[0][0]), "m_01": float(M[0][1]), "m_11": float(M[1][1])}


def _m3(M) -> dict:
    return {f"m_{i}{j}": float(M[i][j]) for i in range(3) for j in range(i, 3)}


def _mass_axis(n, full):
    rs = (_TINY, 1e-6, 1.0, 1e6, _BIG) if full else (_TINY, 1.0, _BIG)
    out = []
    pick = _m2 if n == 2 else _m3
    import itertools

    for diag in itertools.product(rs, repeat=n - 1):
        out.append(pick(np.diag([1.0, *diag])))
    out.append(pick(np.diag([1.0, 1.0 + 2.0**-30] + [1.0] * (n - 2))))
    for kappa in ((1e6, 1e12) if full else (1e12,)):
        out.append(pick(_spd(n, kappa, 5)))
    return out


def _vec_axis(prefix, vecs):
    return [{f"{prefix}_{i}": float(x) for i, x in enumerate(v)} for v in vecs]


def _corner_axes(kernel: str, full: bool) -> list[list[dict]]:
    """The axes of ``kernel``'s corner grid; the grid is their product (dicts merged)."""
    if kernel in GENERAL_KERNELS:
        axes = _corner_axes(GENERAL_KERNELS[kernel][2], full)
        if kernel == "two_surface_exit_velocity_3":
            axes = axes + [[{"m_22": 1e-12, "v_2": 1e12}] + ([{"m_22": 1e12, "v_2": -1.0}] if full else [])]
        return axes
    e_axis = _axis("e", (0.0, 1e-12, 0.5, 1 - 1e-12, 1.0) if full else (0.0, 1 - 1e-12, 1.0))
    ratio = (0.0, _TINY, 1e-6, 0.5, *_NEAR1, 1e6, _BIG) if full else (_TINY, 0.5, *_NEAR1, _BIG)
    if kernel in ("reflect_2", "reflection_map_2", "reflect_3", "reflection_map_3"):
        n = int(kernel[-1])
        us = [[-1.0, 1.0] + [0.0] * (n - 2), [1.0] + [0.0] * (n - 1), [1.0, _TINY] + [0.0] * (n - 2),
              [_TINY, 1.0] + [1.0] * (n - 2), [1.0, -1.0 + 2.0**-40] + [_BIG] * (n - 2)]
        axes = [_mass_axis(n, full), _vec_axis("u", us)]
        if kernel.startswith("reflect_"):
            vs = [[1.0] + [0.0] * (n - 1), [1.0, 1.0 + 1e-12] + [0.0] * (n - 2), [0.0, 1.0] + [-1.0] * (n - 2),
                  [_BIG, _TINY] + [1.0] * (n - 2)]
            axes.append(_vec_axis("v", vs))
        return axes + [e_axis]
    if kernel == "impulse_ratio_root":
        out = []
        for A in (_TINY, 1.0, _BIG):
            for B in (-_BIG, -1.0, -_TINY, _TINY, 1.0):
                for d in (1.0, 1 - 1e-12, 0.5, 1e-6, 1e-12, 0.0, -1e-12):  # D/B^2 = d: C = (1 - d) B^2/(4A)
                    out.append({"A": A, "B": B, "C": (1 - d) * B * B / (4 * A)})
        return [out]
    if kernel == "chain3_impulse_ratio":
        import itertools

        # the law is homogeneous in the masses: the default grid fixes m1 = 1 (ratios m2/m1, m3/m1
        # and m3/m2 still reach 1e-12 ... 1e12, 1e24), the full grid varies all three
        ms = (_TINY, 1e-6, 1.0, 1e6, _BIG) if full else (_TINY, 1.0, _BIG)
        masses = [{"m1": a, "m2": b, "m3": c} for a, b, c in itertools.product(ms if full else (1.0,), ms, ms)]
        vels = [(1.0, 0.0, 0.0), (1.0, 1 - 1e-9, 1 - 2e-9), (0.0, 0.0, -1.0), (1.0, 0.0, -1.0),
                (1.0, 1.0, 1 - 2.0**-40)]
        vel_axis = [{"v1": a, "v2": b, "v3": c} for a, b, c in (vels if full else vels[:3])]
        return [masses, vel_axis, _axis("e", (0.0, 1 / 3, 1 - 1e-12, 1.0) if full else (0.0, 1 - 1e-12, 1.0)),
                _axis("alpha", ratio)]
    if kernel == "chain3_alpha_max":
        return [_axis("e", (math.nextafter(1 / 3, 1.0), 1 / 3 + 1e-12, 1 / 3 + 1e-6, 0.5, 1 - 1e-12, 1.0))]
    thetas = (0.0, 1e-9, _PI / 4, _PI / 2 - 1e-9, _PI / 2, _PI - 1e-9)
    taus = (0.0, 1e-9, _PI / 2 - 1e-9, -(_PI / 2 - 1e-9), _PI / 2 + 1e-9, -1.0)
    if kernel == "pool_impulse_ratio":
        return [_axis("theta", thetas if full else thetas[1:5]), _axis("tau", taus if full else taus[:4]), e_axis,
                _axis("alpha", ratio)]
    if kernel == "bernoulli_impulse_ratio":
        r = (0.0, _TINY, 0.5, 1.0, _BIG)
        return [_axis("tau", taus), e_axis, _axis("alpha", r), _axis("alpha13", r if full else (0.0, 0.5, _BIG))]
    if kernel in ("pool_g", "pool_h"):
        return [_axis("theta", thetas), _axis("alpha", ratio)]
    if kernel in ("two_surface_reflection_count", "two_surface_resolution"):
        out = []
        ss = (_TINY, 1.0, _BIG) if full else (_TINY, 1.0)
        for sa in ss:
            for sb in ss:
                for beta in (1e-6, 1e-3, _PI / 2, _PI - 1e-6):
                    out.append({"s_a": sa, "s_b": sb, "g": -math.cos(beta) * math.sqrt(sa * sb)})
        cs = (-1.0, -_TINY, 0.0, 1.0) if full else (-1.0, -_TINY, 1.0)
        return [out, _axis("c_a", cs), _axis("c_b", cs)]
    if kernel == "two_surface_resolution_2":
        Ms = [_m2(np.eye(2)), _m2(np.diag([1e6, 1e-6])), _m2(np.diag([_BIG, 1.0])), _m2(_spd(2, 1e12, 5))]
        Hs = []
        for beta in ((1e-9, 1e-6, 1e-3, _PI / 2, _PI - 1e-6) if full else (1e-9, 1e-3, _PI / 2)):
            for phi in (0.0, 0.3):
                Hs.append({"h_00": math.cos(phi), "h_01": math.sin(phi),
                           "h_10": -math.cos(phi + beta), "h_11": -math.sin(phi + beta)})
        vs = _vec_axis("v", [(-1.0, 0.5), (-1.0, -0.5), (_TINY, -1.0), (1.0, 1.0)])
        return [Ms if full else Ms[:3], Hs, vs]
    raise KeyError(f"no corner grid for kernel {kernel!r}; known: {', '.join(CORNER_KERNELS)}")


#: kernels with a corner grid (every closed-form kernel whose accuracy is claimed; the naive
#: root ``impulse_ratio_root_naive`` is the bench's comparison and is not held to the bound)
CORNER_KERNELS = ("reflect_2", "reflection_map_2", "reflect_3", "reflection_map_3", "impulse_ratio_root",
                  "chain3_impulse_ratio", "chain3_alpha_max", "pool_impulse_ratio", "bernoulli_impulse_ratio",
                  "pool_g", "pool_h", "two_surface_reflection_count", "two_surface_resolution",
                  "two_surface_resolution_2", *GENERAL_KERNELS)


def _closed_form(kernel: str) -> str:
    """The closed-form kernel whose formulas are ``kernel``'s reference (itself, or the general
    kernel's closed form at its n)."""
    return GENERAL_KERNELS[kernel][2] if kernel in GENERAL_KERNELS else kernel


_EMBEDDED: dict = {}


def reference(kernel: str):
    """The checked high-precision reference of a grid kernel (:mod:`impactsym.reference_values`):
    the closed form's emitted formulas; for ``two_surface_exit_velocity_3`` those of the n = 2 map
    with the decoupled third coordinate's exits (``v_2``, NaN where the branch does not exist).

    >>> reference("reflect_general_2").names == reference("reflect_2").names
    True
    """
    from .reference_values import Reference, kernel_reference

    if kernel != "two_surface_exit_velocity_3":
        return kernel_reference(_closed_form(kernel))
    if kernel not in _EMBEDDED:
        import sympy as sp

        base = kernel_reference("two_surface_resolution_2")
        m22, v2 = sp.symbols("m_22 v_2", real=True)
        outs = list(base.outputs)
        # count = Piecewise((0, valid), (m, c_first < 0), (-1, True)): the branch exists under the first two
        third = [sp.Piecewise((v2, outs[k].args[0].cond), (v2, outs[k].args[1].cond), (sp.nan, True)) for k in (0, 3)]
        if not all(outs[k].args[2].expr == -1 for k in (0, 3)):  # pragma: no cover - a changed derivation
            raise RuntimeError("two_surface_resolution_2's counts no longer end in (-1, True)")
        _EMBEDDED[kernel] = Reference([*base.args, m22, v2], outs[:3] + [third[0]] + outs[3:] + [third[1]])
    return _EMBEDDED[kernel]


def _outputs(kernel: str) -> list:
    """Output names of a grid kernel, in the order its implementations return them."""
    from .bench import _catalog

    if kernel == "two_surface_exit_velocity_3":
        return ["count_a", "v0_a", "v1_a", "v2_a", "count_b", "v0_b", "v1_b", "v2_b"]
    return list(_catalog()[_closed_form(kernel)]["outputs"])


def _args(kernel: str) -> list:
    return reference(kernel).names


_C_LIBRARY: list = []


def _c_library():
    """The generated C kernels compiled once per process (:func:`impactsym.bench.compile_c`)."""
    if not _C_LIBRARY:
        from .bench import compile_c

        _C_LIBRARY.append(compile_c())
    return _C_LIBRARY[0]


def _matrix(inputs: dict, prefix: str, n: int):
    """The symmetric ``n × n`` matrix of the upper-triangle inputs ``prefix_ij`` (absent ones 0)."""
    return np.array([[float(inputs.get(f"{prefix}_{min(i, j)}{max(i, j)}", 0.0)) for j in range(n)]
                     for i in range(n)])


def _general_implementations(kernel: str, languages) -> dict:
    """``language -> f(inputs) -> list[float]`` for a general-dimension kernel at its grid's n: NumPy
    (the committed kernel; its plain-Python text is the same function) and C where generated."""
    name, n, _ = GENERAL_KERNELS[kernel]
    out = {}
    for lang in languages:
        if lang == "numpy":
            from . import kernels as K

            f = getattr(K, name)
            if name == "two_surface_exit_velocity":
                def call(x, f=f):
                    H = np.array([[float(x.get(f"h_{i}{j}", 0.0)) for j in range(n)] for i in range(2)])
                    v = np.array([float(x[f"v_{j}"]) for j in range(n)])
                    with np.errstate(all="ignore"):
                        try:
                            counts, exits = f(_matrix(x, "m", n), H, v)
                        except np.linalg.LinAlgError:  # a singular Gram matrix: no number
                            return [math.nan] * (2 + 2 * n)
                    return [float(counts[0]), *map(float, exits[0]), float(counts[1]), *map(float, exits[1])]
            else:
                def call(x, f=f, name=name):
                    u = np.array([float(x[f"u_{j}"]) for j in range(n)])
                    args = (_matrix(x, "m", n), u) + ((np.array([float(x[f"v_{j}"]) for j in range(n)]),)
                                                      if name == "reflect" else ())
                    with np.errstate(all="ignore"):
                        try:
                            r = f(*args, float(x["e"]))
                        except np.linalg.LinAlgError:
                            return [math.nan] * (n * n if name == "reflection_map" else n)
                    return [float(y) for y in np.ravel(r)]
        elif lang == "c":
            from .bench import _catalog

            lib = _c_library()
            if lib is None or not _catalog()[name]["code"].get("c"):
                continue
            import ctypes

            f = getattr(lib, name)
            f.restype = ctypes.c_int
            dp = ctypes.POINTER(ctypes.c_double)

            def call(x, f=f, name=name):
                M = np.ascontiguousarray(_matrix(x, "m", n))
                u = np.array([float(x[f"u_{j}"]) for j in range(n)])
                size = n * n if name == "reflection_map" else n
                res = np.empty(size)
                vec = (np.array([float(x[f"v_{j}"]) for j in range(n)]),) if name == "reflect" else ()
                status = f(ctypes.c_size_t(n), *[a.ctypes.data_as(dp) for a in (M, u, *vec)],
                           ctypes.c_double(float(x["e"])), res.ctypes.data_as(dp))
                return [math.nan] * size if status != 0 else [float(y) for y in res]
        elif lang == "python":
            continue  # the same function text as NumPy's (the catalog's python code is the NumPy kernel)
        else:
            raise ValueError(f"languages: unknown language {lang!r} (numpy, python, c)")
        out[lang] = call
    return out


def corner_cases(kernel: str, full: bool = False):
    """Every combination of ``kernel``'s extreme corners, as :class:`HardCase` (a generator).

    ``full=False`` is the grid the default tests run (each axis at its most extreme values);
    ``full=True`` adds the intermediate corners (1e-6, 1e6, ...) for the bench.

    Examples
    --------
    >>> cases = list(corner_cases("chain3_impulse_ratio"))
    >>> len(cases), cases[0].category
    (486, 'corner')
    >>> len(list(corner_cases("chain3_impulse_ratio", full=True)))
    22500
    """
    import itertools

    axes = _corner_axes(kernel, full)
    for combo in itertools.product(*axes):
        inputs: dict = {}
        for part in combo:
            inputs.update(part)
        name = ", ".join(f"{k}={v:.17g}" for k, v in inputs.items())
        yield HardCase(kernel, name, "corner", inputs)


def kernel_implementations(kernel: str, languages=("numpy", "python", "c")) -> dict:
    """``language -> f(inputs: dict) -> list[float]`` for one generated closed-form kernel.

    ``numpy`` is the committed NumPy kernel (called with 0-d arrays, so that it takes the NumPy path:
    Python scalars are dispatched to the plain-Python form), ``python`` what a call with Python floats
    runs: the module's plain-Python (``math``) form, and the NumPy path where that raises (a math-domain
    error, a division by zero, an overflow), ``c`` the
    committed C kernel compiled with gcc (left out when no compiler is found).

    >>> f = kernel_implementations("impulse_ratio_root", ("numpy", "python"))
    >>> f["numpy"]({"A": 1.0, "B": -3.0, "C": 2.0}) == f["python"]({"A": 1.0, "B": -3.0, "C": 2.0}) == [2.0, 1.0]
    True
    """
    from .bench import _catalog

    if kernel in GENERAL_KERNELS:
        return _general_implementations(kernel, languages)
    entry = _catalog()[kernel]
    args, n_out = entry["args"], len(entry["outputs"])
    out = {}
    for lang in languages:
        if lang == "numpy":
            from . import kernels as K

            f = getattr(K, kernel)

            def call(inputs, f=f):  # 0-d arrays: the NumPy path (Python scalars go to the Python form)
                with np.errstate(all="ignore"):
                    r = f(**{a: np.asarray(float(inputs[a])) for a in args})
                return [float(x) for x in (r if isinstance(r, tuple) else (r,))]
        elif lang == "python":
            import sys

            from . import kernels as K

            fk = getattr(K, kernel)
            fpy = getattr(sys.modules[fk.__module__], f"_{kernel}_python")

            def call(inputs, fpy=fpy, fk=fk):
                xs = [float(inputs[a]) for a in args]
                try:
                    r = fpy(*xs)
                except (ValueError, ZeroDivisionError, OverflowError):  # what the kernel does: its NumPy path
                    with np.errstate(all="ignore"):
                        r = fk(*[np.asarray(x) for x in xs])
                return [float(x) for x in (r if isinstance(r, tuple) else (r,))]
        elif lang == "c":
            lib = _c_library()
            if lib is None or not entry["code"].get("c"):
                continue
            import ctypes

            f = getattr(lib, kernel)
            f.restype = None

            def call(inputs, f=f):
                outs = [ctypes.c_double() for _ in range(n_out)]
                f(*[ctypes.c_double(float(inputs[a])) for a in args], *[ctypes.byref(o) for o in outs])
                return [o.value for o in outs]
        else:
            raise ValueError(f"languages: unknown language {lang!r} (numpy, python, c)")
        out[lang] = call
    return out


@dataclass
class Verdict:
    """The accuracy of every implementation of one kernel at one input.

    ``ratio[lang]`` is the largest error ratio (:func:`impactsym.reference_values.error_ratio`) over the
    continuous outputs (with ``screen``, an upper bound, ``|f̂ − f| / (eps |f|)``, where that bound
    already shows the point within ``bound``; an exit accepted by :func:`value_in_neighbourhood`
    counts with its ratio against the witness); ``output[lang]`` names the output where it occurs. ``problems`` lists
    every violation: a ratio above the bound, a number where the exact value is not real, or a
    reflection count that no input within ``bound · eps`` (relative, per input) has, certified
    (:func:`count_in_neighbourhood`).
    """

    kernel: str
    inputs: dict
    ratio: dict
    output: dict
    problems: list
    outside_domain: bool = False

    @property
    def worst(self) -> float:
        return max(self.ratio.values(), default=0.0)


def _near_domain(ref, inputs, bound, seed=0) -> bool:
    """Whether the exact formula is real at some input moved by ``± bound · eps`` (relative)."""
    from .reference_values import EPS, OutsideDomain

    rng = np.random.default_rng(seed)
    names = ref.names
    patterns = [np.ones(len(names)), -np.ones(len(names))] + [rng.choice([-1.0, 1.0], len(names)) for _ in range(16)]
    for pat in patterns:
        try:
            ref.values({n: float(inputs[n]) * (1 + s * bound * EPS) for n, s in zip(names, pat)})
            return True
        except OutsideDomain:
            continue
    return False


def _counts_from_law(kernel: str, x: dict):
    """``(count_a, count_b)`` of a two-surface kernel at the exact rational inputs ``x`` (name ->
    Fraction), certified by :func:`impactsym.laws.two_surface.branch_counts` (Arb enclosures of
    ``ψ/β`` at rising precision, exact tie tests), in the kernel's convention (0: valid, -1: the
    branch does not exist); ``None`` where the law refuses the inputs (parallel rows, M not
    positive definite).

    The ``(s, g, c)`` kernels are the law at ``M = Γ⁻¹``, ``H = I``, ``v = c`` (then
    ``H M⁻¹ Hᵀ = Γ`` and ``H v = c``).
    """
    names = _LAW_INPUTS[0] if "s_a" in x else _LAW_INPUTS[1]
    key = tuple(x[n] for n in names)
    if key not in _LAW_COUNTS:
        if len(_LAW_COUNTS) >= 8192:
            _LAW_COUNTS.pop(next(iter(_LAW_COUNTS)))
        _LAW_COUNTS[key] = _law_counts(dict(zip(names, key)))
    return _LAW_COUNTS[key]


#: the inputs a two-surface count depends on: the (s, g, c) kernels' and the (M, H, v) kernels' (the
#: n = 3 kernel's decoupled third coordinate moves no count)
_LAW_INPUTS = (("s_a", "s_b", "g", "c_a", "c_b"), ("m_00", "m_01", "m_11", "h_00", "h_01", "h_10", "h_11", "v_0", "v_1"))
#: exact point -> certified counts (the witnesses of one box are met again by each language, each
#: wrong count and each kernel that shares the closed form's grid)
_LAW_COUNTS: dict = {}


def _law_counts(x: dict):
    from flint import fmpq

    from .errors import ImpactInputError, UndecidableSign
    from .laws.two_surface import branch_counts

    q = {k: fmpq(v.numerator, v.denominator) for k, v in x.items()}  # (exact: the law reads fmpq as it is)
    if "s_a" in q:
        D = q["s_a"] * q["s_b"] - q["g"] ** 2
        if not (q["s_a"] > 0 and D > 0):
            return None
        M = [[q["s_b"] / D, -q["g"] / D], [-q["g"] / D, q["s_a"] / D]]
        H, v = [[fmpq(1), fmpq(0)], [fmpq(0), fmpq(1)]], [q["c_a"], q["c_b"]]
    else:
        M = [[q["m_00"], q["m_01"]], [q["m_01"], q["m_11"]]]
        H = [[q["h_00"], q["h_01"]], [q["h_10"], q["h_11"]]]
        v = [q["v_0"], q["v_1"]]
    try:
        found = branch_counts(M, H, v)
    except (ImpactInputError, UndecidableSign):  # refused, or a count the law cannot certify: no witness
        return None
    c = [H[i][0] * v[0] + H[i][1] * v[1] for i in (0, 1)]
    if c[0] >= 0 and c[1] >= 0:
        return (0, 0)
    return tuple(found.get(i, -1) for i in (0, 1))


#: kernel -> its certified oracle of the discontinuous outputs (in :data:`DISCONTINUOUS` order)
COUNT_ORACLES = {k: _counts_from_law for k in DISCONTINUOUS}


def _branch_polynomials(x: dict, i: int) -> list:
    """The quantities whose signs make the branch of count output ``i`` (0: starts with A, 1: with
    B) exist with a proper wedge, as ``(value, sign)``: each value is a polynomial of degree ≤ 2 in
    the inputs (so of degree ≤ 2 along a segment), ``sign`` +1 (must be > 0) or -1 (< 0). Where all
    hold, ``ψ/β`` is continuous (``ψ = atan2(y, ·)`` with ``y = −c_first √Δ > 0``,
    ``β = atan2(√Δ, −g)``, ``Δ > 0``)."""
    if "s_a" in x:
        return [(x["s_a"], 1), (x["s_a"] * x["s_b"] - x["g"] ** 2, 1), (x["c_a"] if i == 0 else x["c_b"], -1)]
    det_h = x["h_00"] * x["h_11"] - x["h_01"] * x["h_10"]
    row = ("h_00", "h_01") if i == 0 else ("h_10", "h_11")
    return [(x["m_00"], 1), (x["m_00"] * x["m_11"] - x["m_01"] ** 2, 1), (det_h, 1 if det_h > 0 else -1),
            (x[row[0]] * x["v_0"] + x[row[1]] * x["v_1"], -1)]


def _on_branch(x: dict, i: int) -> bool:
    return all(v * sg > 0 for v, sg in _branch_polynomials(x, i))


def _point(x: dict, y: dict, lam) -> dict:
    return {k: x[k] + lam * (y[k] - x[k]) for k in x}


def _continuous_on_segment(x: dict, y: dict, i: int) -> bool:
    """Certified (exact rationals): every quantity of :func:`_branch_polynomials` keeps its sign on
    the whole segment ``[x, y]``. Each is a quadratic ``q(λ)`` along it, recovered exactly from three
    values; its extreme on ``[0, 1]`` is at an end or at the vertex ``−b/(2a)``."""
    x, y = _as_fmpq(x), _as_fmpq(y)  # (the same exact arithmetic as Fraction's, in C)
    half = fmpq(1, 2)
    at = [_branch_polynomials(_point(x, y, lam), i) for lam in (fmpq(0), half, fmpq(1))]
    for k, (_, sg) in enumerate(at[0]):
        q0, qh, q1 = (sg * at[j][k][0] for j in range(3))
        # q(λ) = a λ² + b λ + c from q(0), q(1/2), q(1)
        c, a = q0, 2 * (q1 - 2 * qh + q0)
        b = q1 - q0 - a
        vals = [q0, q1]
        if a > 0 and 0 < -b / (2 * a) < 1:
            lam = -b / (2 * a)
            vals.append(a * lam * lam + b * lam + c)
        if min(vals) <= 0:
            return False
    return True


def _last_on_branch(x: dict, y: dict, i: int, steps: int = 64):
    """The point of ``[x, y]`` nearest ``y`` that bisection finds on the branch (``x`` on it, ``y``
    not), exact (rounding it to floats would move ``Δ`` by about an ulp of ``s_a s_b``, as much as
    ``Δ`` itself where the box crosses ``Δ = 0``)."""
    from fractions import Fraction

    xq, yq = _as_fmpq(x), _as_fmpq(y)  # (bisection in fmpq: the same exact points as in Fraction)
    lo, hi = fmpq(0), fmpq(1)
    for _ in range(steps):
        mid = (lo + hi) / 2
        if _on_branch(_point(xq, yq, mid), i):
            lo = mid
        else:
            hi = mid
    return {k: Fraction(int(v.p), int(v.q)) for k, v in _point(xq, yq, lo).items()}


def _as_fmpq(x: dict) -> dict:
    """A point of exact rationals (``Fraction`` or ``fmpq``) as ``fmpq``."""
    return {k: v if isinstance(v, fmpq) else fmpq(v.numerator, v.denominator) for k, v in x.items()}


def _in_domain(x: dict) -> bool:
    """Exact: the wedge is proper (``Δ > 0``; for the ``(M, H, v)`` kernel ``M`` positive definite
    and ``det H ≠ 0``), where the two-surface formulas are real."""
    return all(v * sg > 0 for v, sg in _branch_polynomials(x, 0)[:-1])


_JUMP_QUANTITIES: dict = {}


def _jump_quantities(ref, i: int) -> list:
    """The quantities output ``i`` of ``ref`` jumps with (the argument of each ``ceiling``, ``lhs − rhs``
    of each condition), each compiled once per reference (``f(*xs)`` in mpmath)."""
    key = (id(ref), i)
    hit = _JUMP_QUANTITIES.get(key)
    if hit is not None and hit[0] is ref:
        return hit[1]
    import sympy as sp

    from .reference_values import _DagEvaluator, _mpmath_printer

    expr = sp.sympify(ref.outputs[i])
    args = [c.args[0] for c in expr.atoms(sp.ceiling)]
    args += [rel.lhs - rel.rhs for rel in expr.atoms(sp.core.relational.Relational)]
    fs = []
    for a in sorted(set(args), key=sp.default_sort_key):
        dag = _DagEvaluator.compile(ref.args, [a])
        fs.append((lambda *xs, dag=dag: dag(*xs)[0]) if dag is not None else
                  sp.lambdify(ref.args, a, modules="mpmath", printer=_mpmath_printer()))
    _JUMP_QUANTITIES[key] = (ref, fs)
    return fs


def _witness_vertices(ref, inputs: dict, i: int, r) -> list:
    """Vertices of the box ``|x'_j − x_j| ≤ r|x_j|`` (rounded to floats) that push each quantity the
    discontinuous output ``i`` jumps with (the argument of each ``ceiling``, ``lhs − rhs`` of each
    condition) down and up the most (signs of ``x_j ∂a/∂x_j`` at 60 digits, inside their own
    precision block), plus the two diagonal vertices."""
    key = (tuple(float(inputs[n]) for n in ref.names), i, r)
    memo = _WITNESS_VERTICES.setdefault(id(ref), (ref, {}))
    if memo[0] is not ref:  # (a reference since collected: its id reused)
        memo = _WITNESS_VERTICES[id(ref)] = (ref, {})
    if key not in memo[1]:
        if len(memo[1]) >= 1024:
            memo[1].pop(next(iter(memo[1])))
        memo[1][key] = _witness_vertices_of(ref, inputs, i, r)
    return [dict(v) for v in memo[1][key]]


#: id(reference) -> (reference, {(inputs, output, radius): vertices}): a box's vertices are asked for
#: again by each wrong count and each exit judged at the same input
_WITNESS_VERTICES: dict = {}


def _witness_vertices_of(ref, inputs: dict, i: int, r) -> list:
    from fractions import Fraction

    import mpmath

    names = ref.names
    fx = {n: Fraction(float(inputs[n])) for n in names}
    signs = [[1] * len(names), [-1] * len(names)]
    for f in _jump_quantities(ref, i):
        with mpmath.workdps(60):
            h = mpmath.mpf(10) ** -30
            xs = [mpmath.mpf(float(inputs[n])) for n in names]
            grad = []
            for j in range(len(names)):
                up, dn = list(xs), list(xs)
                up[j], dn[j] = xs[j] * (1 + h), xs[j] * (1 - h)
                try:
                    d = f(*up) - f(*dn)
                    d = d.real if isinstance(d, mpmath.mpc) else d
                    grad.append(1 if d > 0 else -1 if d < 0 else 0)
                except (ZeroDivisionError, ValueError, TypeError, AttributeError):
                    grad.append(0)
        signs += [grad, [-s for s in grad]]
    out, seen = [], set()
    for sg in signs:
        key = tuple(sg)
        if key in seen:
            continue
        seen.add(key)
        # rounded to floats (the reference reads floats): within (r + eps/2) |x_j| of x_j
        out.append({n: float(fx[n] * (1 + s * r)) for n, s in zip(names, sg)})
    return out


def _certified_witnesses(kernel, ref, inputs, i, bound, branch_from=None):
    """``(point, certified counts)`` at the witness points of count output ``i`` in the box of
    relative radius ``bound · eps``: the vertices of :func:`_witness_vertices` (radius
    ``(bound − 1) · eps`` before rounding to floats, so that they stay in the box) and, with
    ``branch_from`` (the exact input, on the branch), the last point on the branch towards each
    vertex that leaves it. Points are exact Fractions (the vertices of floats; the edges not);
    points the law refuses are left out."""
    from fractions import Fraction

    from .reference_values import EPS

    oracle = COUNT_ORACLES[kernel]
    k = list(DISCONTINUOUS[kernel]).index(_catalog_outputs(kernel)[i])
    for vx in _witness_vertices(ref, inputs, i, Fraction(bound - 1) * Fraction(EPS)):
        y = {n: Fraction(v) for n, v in vx.items()}
        pts = [y]
        if branch_from is not None and not _on_branch(y, k):  # the branch or the wedge ends in the box
            pts.append(_last_on_branch(branch_from, y, k))
        for pt in pts:
            c = oracle(kernel, pt)
            if c is not None:
                yield pt, c


def _branch_output_pairs(kernel: str) -> dict:
    """Continuous output name -> the count output of its branch (``ca_a`` -> ``count_a``): outputs
    that are NaN where their branch does not exist, and so jump at the branch's edge."""
    counts = DISCONTINUOUS.get(kernel, ())
    out = {}
    for name in _catalog_outputs(kernel):
        for c in counts:
            if name not in counts and name.endswith("_" + c.rsplit("_", 1)[1]):
                out[name] = c
    return out


def value_in_neighbourhood(kernel: str, inputs: dict, i: int, got: float, ref=None, bound: float = 64.0):
    """The mixed criterion for a continuous output ``i`` of a branch (a two-surface exit) where the box
    ``N(x)`` crosses a count boundary or the branch's edge: whether ``got`` is within
    ``bound · eps · (|f| + Σ_j |y_j ∂f/∂y_j|)`` of the exact output ``f(y)`` at a witness ``y`` of
    ``N(x)`` whose certified count differs from the count at ``inputs`` (a certified crossing;
    where the box holds one count, nothing is relaxed); NaN where a vertex of ``N(x)`` lies off the
    formula's domain (``Δ ≤ 0`` exactly: there the exact value is not real). Returns ``(accepted, how, ratio)``, ``ratio``
    the error ratio against that witness.

    >>> x = dict(m_00=6475250.422021984, m_01=0.006475250421957788, m_11=6.41958116266222e-05,
    ...          h_00=-7.282075233607068e-06, h_01=5.2319443147251045e-06, h_10=34347.544377025006,
    ...          h_11=-8053.65760667581, v_0=-0.008159842593245486, v_1=-0.011357266836951626)
    >>> value_in_neighbourhood("two_surface_resolution_2", x, 1, float("nan"))[0]   # c_a = H_0 v cancels
    True
    """
    from fractions import Fraction

    from .reference_values import EPS, ReferenceUnstable, error_ratio

    ref = ref or reference(kernel)
    names = _catalog_outputs(kernel)
    pairs = _branch_output_pairs(kernel)
    if names[i] not in pairs:
        return False, "not an output of a branch", math.inf
    ci = names.index(pairs[names[i]])
    k = list(DISCONTINUOUS[kernel]).index(pairs[names[i]])
    fx = {n: Fraction(float(inputs[n])) for n in ref.names}
    at_x = COUNT_ORACLES[kernel](kernel, fx)
    if at_x is None:
        return False, "the law refuses the input", math.inf
    if math.isnan(got):  # NaN is the answer wherever the formula is not real: a point of the box off its domain
        for vx in _witness_vertices(ref, inputs, ci, Fraction(bound - 1) * Fraction(EPS)):
            if not _in_domain({n: Fraction(v) for n, v in vx.items()}):
                return True, "the exact value is not real at a point of the box (a degenerate wedge)", 0.0
    for y, c in _certified_witnesses(kernel, ref, inputs, ci, bound, fx if _on_branch(fx, k) else None):
        if c[k] == at_x[k]:
            continue
        yf = {n: float(v) for n, v in y.items()}  # the reference reads floats: the rounded point's own count
        if Fraction(bound) * Fraction(EPS) < max(abs(Fraction(yf[n]) - fx[n]) / abs(fx[n]) for n in fx if fx[n]) or \
                (COUNT_ORACLES[kernel](kernel, {n: Fraction(v) for n, v in yf.items()}) or at_x)[k] == at_x[k]:
            continue
        try:
            ry = ref.evaluate(yf)
        except (ReferenceUnstable, ArithmeticError):
            continue
        ratio = error_ratio(ry, [got if j == i else 0.0 for j in range(len(names))])[i]
        if ratio <= bound:
            return True, f"the exact value at a point of the box with count {c[k]} (count {at_x[k]} at the input)", ratio
    return False, "no point of the box across a count boundary has it", math.inf


def count_in_neighbourhood(kernel: str, inputs: dict, i: int, got: float, ref=None, bound: float = 64.0):
    """Whether the count ``got`` of discontinuous output ``i`` is the exact count at some input
    within ``bound · eps`` (relative, per input) of ``inputs``: the mixed forward-backward criterion
    of a jump (see :func:`accuracy_check`). Returns ``(accepted, how)``.

    Certified: the counts compared are the law's certified counts (:data:`COUNT_ORACLES`) at exact
    rational points of the box (``inputs`` itself, then the vertices of :func:`_witness_vertices`);
    ``got`` is accepted when one of them has that count, or when it lies between the counts of
    points joined to ``inputs`` by segments on which the branch exists and ``ψ/β`` is continuous
    (:func:`_continuous_on_segment`: every sign condition is a quadratic along a segment, checked
    exactly), by the intermediate value theorem along the path through ``inputs``. Where a vertex
    leaves the branch (``Δ`` or ``c_first`` changes sign inside the box: a nearly degenerate
    wedge), the last point on the branch towards it (bisection) is a witness too.

    Examples
    --------
    At ``(s_a, s_b, g, c_a, c_b) = (1, 1, -1/2, -1, -1)`` (a wedge of 60 degrees) the A-first
    branch needs 3 reflections at every input within 64 eps. With ``g = 1/2`` (120 degrees) the
    velocity after one reflection, ``c_b − 2 g c_a/s_a = 0``, grazes B: the count is 1 there and 2
    at inputs as near as one ulp:

    >>> count_in_neighbourhood("two_surface_reflection_count", dict(s_a=1.0, s_b=1.0, g=-0.5, c_a=-1.0, c_b=-1.0), 0, 4.0)
    (False, 'no input within 64 eps has count 4 (counts seen: [3])')
    >>> count_in_neighbourhood("two_surface_reflection_count", dict(s_a=1.0, s_b=1.0, g=0.5, c_a=-1.0, c_b=-1.0), 0, 2.0)
    (True, 'the certified count at a point of the box')
    """
    from fractions import Fraction

    ref = ref or reference(kernel)
    oracle = COUNT_ORACLES[kernel]
    k = list(DISCONTINUOUS[kernel]).index(_catalog_outputs(kernel)[i])
    if not math.isfinite(got) or got != int(got):
        return False, f"not an integer: {got}"
    got = int(got)
    fx = {n: Fraction(float(inputs[n])) for n in ref.names}
    at_x = oracle(kernel, fx)
    if at_x is not None and at_x[k] == got:
        return True, "the certified count at the input"
    seen = [] if at_x is None else [at_x[k]]
    # counts of points joined to x by a segment on which psi/beta is continuous (certified)
    joined = [at_x[k]] if at_x is not None and at_x[k] >= 1 and _on_branch(fx, k) else []
    for y, c in _certified_witnesses(kernel, ref, inputs, i, bound, fx if joined else None):
        if c[k] == got:
            return True, "the certified count at a point of the box"
        seen.append(c[k])
        if joined and c[k] >= 1 and _continuous_on_segment(fx, y, k):
            joined.append(c[k])
    if got >= 1 and joined and min(joined) <= got <= max(joined):
        return True, "between the certified counts of two points of the box joined through the input " \
                     "by segments on which psi/beta is continuous"
    return False, f"no input within {bound:g} eps has count {got} (counts seen: {sorted(set(seen))})"


def _catalog_outputs(kernel: str) -> list:
    return _outputs(kernel)


def _exact_float(v, c: float) -> bool:
    """Whether the float ``c`` is the reference value ``v`` exactly (both NaN: no such branch)."""
    import mpmath

    if mpmath.isnan(v):
        return math.isnan(c)
    return math.isfinite(c) and v == c


def _screenable(v, c: float) -> bool:
    """Whether output value ``c`` is screened against the reference value ``v`` by its relative error
    (both NaN: no such branch; otherwise a finite number against a non-zero exact value)."""
    import mpmath

    if mpmath.isnan(v):
        return math.isnan(c)
    return math.isfinite(c) and v != 0


def accuracy_check(kernel: str, inputs: dict, impls: dict, bound: float = 64.0, ref=None,
                   screen: bool = True) -> Verdict:
    """Check every output of every implementation of ``kernel`` at ``inputs`` against the
    ladder-checked mpmath reference: ``|f̂ − f| ≤ bound · eps · (|f| + Σ_j |x_j ∂f/∂x_j|)``; a
    discontinuous output (a count) must be the certified count of some input within ``bound · eps``
    (relative, per input) of ``inputs`` (the criterion is stated in the module docstring).

    With ``screen`` (the default), the condition numbers (``2n + 1`` reference evaluations per
    rung) are computed only where the relative error exceeds ``bound · eps``; the ratio reported
    there is the upper bound ``|f̂ − f| / (eps |f|)``. ``screen=False`` gives the exact ratio.

    Examples
    --------
    >>> impls = kernel_implementations("chain3_impulse_ratio", ("numpy",))
    >>> v = accuracy_check("chain3_impulse_ratio", dict(m1=1.0, m2=1e-12, m3=1.0, v1=1.0, v2=0.0, v3=0.0,
    ...                                                 e=1.0, alpha=1 - 1e-12), impls)
    >>> v.problems, v.worst < 1
    ([], True)
    """
    import mpmath

    from .reference_values import TARGET_DPS, OutsideDomain, ReferenceUnstable, ReferenceValue, error_ratio

    ref = ref or reference(kernel)
    names = _outputs(kernel)
    jumps = [i for i, n in enumerate(names) if n in DISCONTINUOUS.get(kernel, ())]
    smooth = [i for i in range(len(names)) if i not in jumps]
    got = {lang: f(inputs) for lang, f in impls.items()}
    problems: list = []
    try:
        vals, dps = ref.values(inputs)
    except OutsideDomain as exc:
        near = None  # a number is acceptable where an input within bound * eps has a real value
        for lang, g in got.items():
            bad = [names[i] for i in exc.nonreal if not math.isnan(g[i])]
            if bad:
                near = _near_domain(ref, inputs, bound) if near is None else near
                if not near:
                    problems.append(f"{lang}: a number where the exact value is not real ({', '.join(bad)}), "
                                    f"and at every input within {bound:g} eps")
        return Verdict(kernel, dict(inputs), {}, {}, problems, outside_domain=True)
    except ReferenceUnstable:
        vals, dps = None, None
    ratios: dict = {}
    mixed: dict = {}
    full = None
    judged: dict = {}  # (full is None, the continuous outputs) -> their ratios: languages that agree are judged once
    for lang, g in got.items():
        state = (full is None, tuple(g[i] for i in smooth))
        r = judged.get(state)
        if r is not None:
            r = list(r)
        else:
            screened = None
            if vals is not None and all(_screenable(vals[i], g[i]) for i in smooth):
                # |f^ - f| / (eps |f|): the ratio without the sensitivity (an upper bound of the ratio)
                er = error_ratio(ReferenceValue(vals, [mpmath.mpf(0)] * len(vals), [], dps, 0.0), g)
                screened = [er[i] for i in smooth]
            if screen and screened is not None and max(screened, default=0.0) <= bound:
                r = screened
            elif full is None and dps == 2 * TARGET_DPS and all(_exact_float(vals[i], g[i]) for i in smooth):
                # every output is the exact value (or NaN where that is NaN): error_ratio is 0 whatever the
                # sensitivity, and evaluate's ladder stops at this first rung (its agreement test divides by
                # at least as much), with these values
                r = [0.0] * len(smooth)
            else:
                if full is None:
                    full = ref.evaluate(inputs)
                    vals, dps = full.values, full.dps
                er = error_ratio(full, g)
                r = [er[i] for i in smooth]
            # (under the state it was judged in: once evaluate has run, a screen reads its values)
            judged[state] = list(r)
        k = int(np.argmax(r)) if r else 0
        ratios[lang] = (float(r[k]) if r else 0.0, names[smooth[k]] if r else None)
        over = [j for j, x in enumerate(r) if not x <= bound]
        if over and jumps:  # an exit where the box crosses a count boundary or its branch's edge
            r = list(r)
            for j in list(over):
                at = (smooth[j], g[smooth[j]])
                if at not in mixed:  # (each output's value judged once, whichever language gave it)
                    mixed[at] = value_in_neighbourhood(kernel, inputs, smooth[j], g[smooth[j]], ref, bound)
                ok, _, ratio = mixed[at]
                if ok:  # judged (and reported) against the witness
                    r[j] = ratio
                    over.remove(j)
            k = int(np.argmax(r))
            ratios[lang] = (float(r[k]), names[smooth[k]])
        if over:
            j = max(over, key=lambda j: r[j])
            problems.append(f"{lang}: {names[smooth[j]]} off by {r[j]:.3g} eps (1 + cond) > {bound:g}")
    if jumps and vals is not None:
        with mpmath.workdps(dps or 50):
            exact = {i: float(vals[i]) for i in jumps}
        decided: dict = {}
        for lang, g in got.items():
            for i in jumps:
                if g[i] == exact[i] or (math.isnan(g[i]) and math.isnan(exact[i])):
                    continue
                key = (i, g[i])
                if key not in decided:
                    decided[key] = count_in_neighbourhood(kernel, inputs, i, g[i], ref, bound)
                ok, how = decided[key]
                if not ok:
                    problems.append(f"{lang}: count {names[i]} = {g[i]:g} (exact {exact[i]:g}): {how}")
    return Verdict(kernel, dict(inputs), {k: v[0] for k, v in ratios.items()}, {k: v[1] for k, v in ratios.items()},
                   problems)


def wedge_samples(kernel: str, n: int, seed: int = 0):
    """Random inputs of a two-surface kernel where its float angles are hardest: wedge openings
    ``β`` near ``π/2``, ``π/3 … π/8``, ``π`` and down to ``1e-9``, velocity angles ``ψ`` near ``π``,
    ``π/2`` and multiples of ``β`` (count boundaries), scales ``1e-12 … 1e12`` (a generator of
    input dicts; the corner grid fixes a few of each, the search climbs from those).

    >>> xs = list(wedge_samples("two_surface_resolution", 3, seed=1))
    >>> len(xs), sorted(xs[0])
    (3, ['c_a', 'c_b', 'g', 's_a', 's_b'])
    """
    rng = np.random.default_rng(seed)
    pi = math.pi

    def tiny():
        return float(rng.choice([-1, 1])) * 10.0 ** -rng.uniform(3, 17)

    made = 0
    while made < n:
        kind = rng.integers(4)
        beta = (pi / 2 * (1 + tiny()) if kind == 0 else pi / int(rng.integers(3, 9)) * (1 + tiny()) if kind == 1
                else pi * (1 - 10.0 ** -rng.uniform(1, 12)) if kind == 2 else 10.0 ** -rng.uniform(0, 9))
        if _closed_form(kernel) != "two_surface_resolution_2":
            pk = rng.integers(4)
            if pk == 0:
                psi = pi * (1 - 10.0 ** -rng.uniform(1, 16))
            elif pk == 1:
                psi = pi / 2 * (1 + tiny())
            elif pk == 2:
                j = int(rng.integers(1, max(2, min(50, int(pi / beta)) + 1)))
                psi = min(j * beta * (1 + tiny()), pi * (1 - 1e-16))
            else:
                psi = rng.uniform(0, pi)
            sa, sb = 10.0 ** rng.uniform(-12, 12), 10.0 ** rng.uniform(-12, 12)
            r = 10.0 ** rng.uniform(-6, 6)
            g, ca, cb = -math.cos(beta) * math.sqrt(sa * sb), -math.sqrt(sa) * r * math.sin(psi), \
                math.sqrt(sb) * r * math.sin(beta + psi)
            if rng.integers(2):
                sa, sb, ca, cb = sb, sa, cb, ca
            x = dict(s_a=sa, s_b=sb, g=g, c_a=ca, c_b=cb)
        else:
            a, b = 10.0 ** rng.uniform(-12, 12, size=2)
            rot = float(rng.choice([0.0, rng.uniform(0, pi), 1e-9]))
            R = np.array([[math.cos(rot), -math.sin(rot)], [math.sin(rot), math.cos(rot)]])
            M = np.diag([a, b]) if rng.integers(3) == 0 else R @ np.diag([a, b]) @ R.T
            phi = rng.uniform(0, 2 * pi)
            sc = 10.0 ** rng.uniform(-6, 6, size=2)
            th = float(rng.choice([rng.uniform(0, 2 * pi), phi + pi / 2 * (1 + tiny()), phi + beta + tiny(),
                                   phi + pi + tiny()]))
            sp_ = 10.0 ** rng.uniform(-6, 6)
            x = dict(m_00=M[0, 0], m_01=(M[0, 1] + M[1, 0]) / 2, m_11=M[1, 1], h_00=sc[0] * math.cos(phi),
                     h_01=sc[0] * math.sin(phi), h_10=-sc[1] * math.cos(phi + beta), h_11=-sc[1] * math.sin(phi + beta),
                     v_0=sp_ * math.cos(th), v_1=sp_ * math.sin(th))
            if kernel == "two_surface_exit_velocity_3":  # the decoupled third coordinate
                x.update(m_22=10.0 ** rng.uniform(-12, 12), v_2=float(rng.choice([-1, 1])) * 10.0 ** rng.uniform(-12, 12))
        x = {k: float(v) for k, v in x.items()}
        if _in_search_domain(kernel, x):
            made += 1
            yield x


@dataclass
class SearchResult:
    """What :func:`adversarial_search` found: the worst verdict, every verdict with a problem,
    and how many points it evaluated."""

    kernel: str
    worst: Verdict
    failures: list
    evaluations: int


_CORNER_VALUES = (0.0, 1.0, -1.0, 1e-12, 1e12, 0.5, 1 / 3, _PI / 2)

#: where the search may go: argument -> (low, high), closed (the laws' domains: e in [0, 1],
#: masses, ratios and Gram diagonals positive; points outside are not the kernels' inputs)
SEARCH_DOMAIN = {"e": (0.0, 1.0), "alpha": (0.0, math.inf), "alpha13": (0.0, math.inf),
                 "m1": (1e-300, math.inf), "m2": (1e-300, math.inf), "m3": (1e-300, math.inf),
                 "m_00": (1e-300, math.inf), "m_11": (1e-300, math.inf), "m_22": (1e-300, math.inf),
                 "A": (1e-300, math.inf), "s_a": (1e-300, math.inf), "s_b": (1e-300, math.inf)}


def _in_search_domain(kernel: str, x: dict) -> bool:
    """Inside :data:`SEARCH_DOMAIN`, with a positive definite Gram matrix ``(s_a, g; g, s_b)``
    and mass matrix (leading minors of the upper triangle ``m_ij``), and non-zero gradient rows
    ``h_i*`` (the two-surface law refuses a zero covector)."""
    if "s_a" in x and not x["s_a"] * x["s_b"] - x["g"] ** 2 > 0:
        return False
    rows = [[v for k, v in x.items() if k.startswith(f"h_{i}")] for i in (0, 1)]
    if any(r and not any(r) for r in rows):  # a zero gradient row: the law refuses it (ImpactInputError)
        return False
    if "m_00" in x:
        n = 3 if "m_22" in x else 2
        M = _matrix(x, "m", n)
        if not all(np.linalg.det(M[:k, :k]) > 0 for k in range(1, n + 1)):
            return False
    lo_e = 1 / 3 if kernel == "chain3_alpha_max" else 0.0
    for k, v in x.items():
        lo, hi = SEARCH_DOMAIN.get(k, (-math.inf, math.inf))
        if k == "e":
            lo = lo_e
        if not (math.isfinite(v) and lo <= v <= hi):
            return False
    return True


def _mutate(x: dict, rng, frozen=()) -> dict:
    y = dict(x)
    keys = [k for k in y if k not in frozen]
    k = keys[rng.integers(len(keys))]
    move = rng.integers(4)
    if move == 0 or y[k] == 0.0 and move != 3:  # relative nudge, tiny to large
        y[k] = y[k] * (1 + rng.choice([-1, 1]) * 10.0 ** -rng.uniform(1, 16)) if y[k] != 0 else \
            rng.choice([-1, 1]) * 10.0 ** -rng.uniform(0, 14)
    elif move == 1:  # change of scale
        y[k] = y[k] * 10.0 ** rng.uniform(-4, 4)
    elif move == 2:  # a few ulps
        for _ in range(int(rng.integers(1, 64))):
            y[k] = math.nextafter(y[k], rng.choice([-math.inf, math.inf]))
    else:  # jump to a corner value, nudged
        c = float(rng.choice(_CORNER_VALUES))
        y[k] = c * (1 + rng.choice([-1, 1]) * 10.0 ** -rng.uniform(6, 16)) if c != 0 else 0.0
    return {a: float(b) for a, b in y.items()}


def adversarial_search(kernel: str, budget: int = 100, seed: int = 0, starts=None, impls=None,
                       bound: float = 64.0, frozen=()) -> SearchResult:
    """Hill-climb on the error ratio of every implementation of ``kernel``, from ``starts``.

    Each point is judged with exact ratios (``accuracy_check(..., screen=False)``). Each step
    mutates one argument of the current point (a relative nudge ``1 ± 10^-k``, a change
    of scale, a few ulps, or a jump to a corner value) and keeps the new point when its worst ratio
    (over implementations and outputs, see :func:`accuracy_check`) does not decrease; every point
    with a problem is kept in ``failures``. Deterministic for a given ``seed``. Points outside the
    formula's domain must give NaN (a problem otherwise) and score 0.

    Parameters
    ----------
    kernel : name of a closed-form kernel in :data:`CORNER_KERNELS`
    budget : number of points evaluated (each one reference evaluation, ~2-250 ms)
    seed : the random seed (the tests fix it; the bench runs more)
    starts : starting inputs (default: the corner grid's points, best first after screening
        ``budget // 4`` of them)
    impls : :func:`kernel_implementations` of the kernel (default NumPy, Python and C)
    frozen : arguments never mutated

    Examples
    --------
    >>> r = adversarial_search("impulse_ratio_root", budget=20, seed=0,
    ...                        impls=kernel_implementations("impulse_ratio_root", ("numpy",)))
    >>> r.evaluations, r.failures
    (20, [])
    """
    from .reference_values import ReferenceUnstable

    rng = np.random.default_rng(seed)
    impls = impls if impls is not None else kernel_implementations(kernel)
    ref = reference(kernel)
    pool = [c.inputs for c in corner_cases(kernel)] if starts is None else [dict(s) for s in starts]
    order = rng.permutation(len(pool))
    failures: list = []
    evaluations = 0

    def check(x):
        nonlocal evaluations
        evaluations += 1
        try:
            v = accuracy_check(kernel, x, impls, bound, ref, screen=False)
        except (ReferenceUnstable, OverflowError, ValueError):
            return None
        if v.problems:
            failures.append(v)
        return v

    scored = []
    for i in order[: max(1, min(len(pool), budget // 4))]:
        v = check(pool[i])
        if v is not None:
            scored.append(v)
    if not scored:
        raise ValueError(f"starts: no point of {kernel!r} could be evaluated")
    scored.sort(key=lambda v: -v.worst)
    worst = scored[0]
    climbers = scored[: max(1, min(4, len(scored)))]
    ci = 0
    while evaluations < budget:
        cur = climbers[ci % len(climbers)]
        cand = _mutate(cur.inputs, rng, frozen)
        if not _in_search_domain(kernel, cand):
            evaluations += 1
            continue
        v = check(cand)
        if v is not None and not v.outside_domain and v.worst >= cur.worst:
            climbers[ci % len(climbers)] = v
            if v.worst > worst.worst:
                worst = v
        ci += 1
    return SearchResult(kernel, worst, failures, evaluations)
