"""``impactsym codegen NAME --lang LANG`` prints a unit that compiles or runs as printed, and
``--out DIR`` writes it with ``BUILD``, a command that builds it there: checked for every kernel in
every language whose toolchain this machine has (C, Python, NumPy, Fortran, Rust, Octave; Julia is
not installed here and is skipped with that reason). The Python unit gives the NumPy kernel's values,
nan included, on every hard case of its kernel."""

from __future__ import annotations

import contextlib
import io
import json
import math
import shutil
import subprocess

import numpy as np
import pytest

from impactsym import kernels as K
from impactsym.cli import main
from impactsym.cli.codegen import LANGS, catalog
from impactsym.hard_cases import HARD_CASES

KERNELS = catalog()["kernels"]
CC = shutil.which("gcc") or shutil.which("cc")


def printed(name: str, lang: str, *extra: str) -> str:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["codegen", name, "--lang", lang, *extra]) == 0
    return buf.getvalue()


def _with(lang):
    return [k for k in KERNELS if k["code"].get(lang) is not None]


@pytest.mark.skipif(CC is None, reason="no C compiler (gcc/cc) on PATH")
@pytest.mark.parametrize("k", _with("c"), ids=lambda k: k["codegen_name"])
def test_printed_c_compiles_alone_with_warnings_as_errors(k, tmp_path):
    src = tmp_path / "printed.c"
    src.write_text(printed(k["codegen_name"], "c"))
    res = subprocess.run([CC, "-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror", "-c", str(src),
                          "-o", str(tmp_path / "printed.o")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


@pytest.mark.skipif(CC is None, reason="no C compiler (gcc/cc) on PATH")
def test_out_dir_c_header_declares_every_function_and_build_line_links(tmp_path):
    """The written header declares every function of the unit (-Wmissing-prototypes with the header
    forced in), BUILD builds a shared library there, and the library gives the NumPy kernel's value."""
    import ctypes

    out = printed("chain3-impulse-ratio", "c", "--out", str(tmp_path))
    assert (tmp_path / "chain3_impulse_ratio.c").read_text() == out
    res = subprocess.run([CC, "-std=c99", "-Wall", "-Werror", "-Wmissing-prototypes", "-include",
                          str(tmp_path / "chain3_impulse_ratio.h"), "-c", str(tmp_path / "chain3_impulse_ratio.c"),
                          "-o", str(tmp_path / "t.o")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    build = (tmp_path / "BUILD").read_text().strip()
    res = subprocess.run(build, shell=True, cwd=tmp_path, capture_output=True, text=True)
    assert res.returncode == 0, (build, res.stderr)
    lib = ctypes.CDLL(str(next(tmp_path.glob("*.so"))))
    args = (1.0, 2.0, 3.0, 1.0, 0.0, -0.5, 0.9, 0.5)
    outs = [ctypes.c_double() for _ in range(5)]
    lib.chain3_impulse_ratio.restype = None
    lib.chain3_impulse_ratio(*map(ctypes.c_double, args), *map(ctypes.byref, outs))
    want = K.chain3_impulse_ratio(*args)
    assert np.allclose([o.value for o in outs], want, rtol=1e-14, atol=0)


def _exec(code: str, name: str):
    ns: dict = {}
    exec(compile(code, f"<printed {name}>", "exec"), ns)
    return ns[name]


@pytest.mark.parametrize("lang", ["python", "numpy"])
@pytest.mark.parametrize("k", [k for k in KERNELS if k["kind"] == "closed form"], ids=lambda k: k["codegen_name"])
def test_printed_python_runs_and_equals_the_kernel_on_every_hard_case(k, lang):
    """Run as printed (its own imports), on each hard case of the kernel and on a sample point: the
    value of the package's kernel, and nan exactly where it gives nan (D < 0 gives nan, not an
    exception)."""
    f = _exec(printed(k["codegen_name"], lang), k["name"])
    kernel = getattr(K, k["name"])
    cases = [c.inputs for c in HARD_CASES if c.kernel == k["name"]]
    cases.append({a: 0.4 + 0.05 * i for i, a in enumerate(k["args"])})
    for inputs in cases:
        with np.errstate(all="ignore"):
            want = kernel(**{a: float(x) for a, x in inputs.items()})
            try:
                got = f(**{a: float(x) for a, x in inputs.items()})
            except ZeroDivisionError:  # Python's float division raises where C gives inf
                if any(not math.isfinite(float(x)) for x in np.atleast_1d(want)):
                    continue
                raise
        want, got = np.atleast_1d(np.asarray(want, dtype=float)), np.atleast_1d(np.asarray(got, dtype=float))
        assert np.array_equal(np.isnan(got), np.isnan(want)), (inputs, got, want)
        ok = ~np.isnan(want)
        assert np.allclose(got[ok], want[ok], rtol=1e-13, atol=0), (inputs, got, want)


def test_printed_python_gives_nan_where_the_discriminant_is_negative():
    """The issue's case: the standalone Python form took sqrt(D) before the branch and raised for D < 0."""
    f = _exec(printed("chain3-impulse-ratio", "python"), "chain3_impulse_ratio")
    args = (1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.5, 5.0)  # alpha = 5: no real root
    with np.errstate(invalid="ignore"):
        want = K.chain3_impulse_ratio(*args)
    assert math.isnan(want[0])
    got = f(*args)
    assert all(math.isnan(x) for x in got[:2])


@pytest.mark.parametrize("k", [k for k in KERNELS if k["kind"] != "closed form"], ids=lambda k: k["codegen_name"])
def test_printed_array_kernels_run_as_printed(k):
    f = _exec(printed(k["codegen_name"], "python"), k["name"])
    M, u, v = np.array([[2.0, 1.0], [1.0, 3.0]]), np.array([1.0, -1.0]), np.array([0.5, -1.0])
    H = np.array([[1.0, -1.0], [0.0, 1.0]])
    args = {"reflection_map": (M, u), "reflect": (M, u, v), "two_surface_exit_velocity": (M, H, v)}[k["name"]]
    got, want = f(*args), getattr(K, k["name"])(*args)
    for g, w in zip(got, want) if isinstance(want, tuple) else [(got, want)]:
        assert np.allclose(g, w, rtol=1e-15, atol=0, equal_nan=True)


@pytest.mark.skipif(shutil.which("gfortran") is None, reason="gfortran not on PATH")
def test_printed_fortran_units_compile(tmp_path):
    """Every printed Fortran unit (a module with its iso_c_binding) compiles with -std=f2008 -Wall -Werror,
    all in one file (each is its own module)."""
    src = tmp_path / "all.f90"
    src.write_text("\n".join(printed(k["codegen_name"], "fortran") for k in _with("fortran")))
    res = subprocess.run(["gfortran", "-std=f2008", "-Wall", "-Werror", "-c", str(src), "-J", str(tmp_path),
                          "-o", str(tmp_path / "all.o")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


@pytest.mark.skipif(shutil.which("rustc") is None, reason="rustc not on PATH")
def test_printed_rust_units_compile(tmp_path):
    """Every printed Rust unit compiles as a library (each in its own module of one crate, so one rustc run)."""
    ks = _with("rust")
    src = tmp_path / "all.rs"
    src.write_text("".join(f"pub mod k{i} {{\n{printed(k['codegen_name'], 'rust')}}}\n" for i, k in enumerate(ks)))
    res = subprocess.run(["rustc", "--edition", "2021", "--crate-type", "lib", "--emit=metadata", "-D", "warnings",
                          "-o", str(tmp_path / "all.rmeta"), str(src)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


@pytest.mark.skipif(shutil.which("octave-cli") is None and shutil.which("octave") is None, reason="octave not on PATH")
def test_printed_octave_units_run_and_equal_the_kernel(tmp_path):
    """Every printed Octave unit, written by --out as its function file, runs in one Octave session
    and gives the NumPy kernel's value at a sample point."""
    calls, want = [], []
    for k in _with("octave"):
        printed(k["codegen_name"], "octave", "--out", str(tmp_path))
        # one in-domain input: the kernel's first hard case, else a sample (Octave's sqrt of a
        # negative is complex, not nan: inputs outside the domain are not compared)
        hard = [c.inputs for c in HARD_CASES if c.kernel == k["name"]]
        inputs = [float(hard[0][a]) for a in k["args"]] if hard else [0.4 + 0.05 * i for i in range(len(k["args"]))]
        if k["args"] == ["s_a", "s_b", "g", "c_a", "c_b"]:  # two surfaces: Delta = s_a s_b - g^2 > 0
            inputs = [2.0, 3.0, -1.0, -1.0, 0.5]
        with np.errstate(all="ignore"):
            w = np.atleast_1d(np.asarray(getattr(K, k["name"])(*inputs), dtype=float))
        if not np.all(np.isfinite(w)):
            continue
        outs = ", ".join(f"o{i}" for i in range(len(w)))
        calls.append(f"[{outs}] = {k['name']}({', '.join(repr(x) for x in inputs)}); "
                     f"printf('%.17e ', {outs}); printf('\\n');")
        want.append((k["name"], w))
    exe = shutil.which("octave-cli") or shutil.which("octave")
    res = subprocess.run([exe, "--no-gui", "--quiet", "--eval", f"addpath('{tmp_path}'); " + " ".join(calls)],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    lines = res.stdout.strip().splitlines()[-len(want):]
    assert len(lines) == len(want) >= 10
    for (name, w), line in zip(want, lines):
        got = np.array([float(x) for x in line.split()])
        assert np.array_equal(np.isnan(got), np.isnan(w)), name
        assert np.allclose(got[~np.isnan(w)], w[~np.isnan(w)], rtol=1e-12, atol=0), (name, got, w)


@pytest.mark.parametrize("lang", LANGS)
def test_out_writes_the_printed_unit_and_a_build_line(lang, tmp_path, capsys):
    k = next(k for k in KERNELS if k["codegen_name"] == "impulse-ratio-root")
    assert main(["codegen", "impulse-ratio-root", "--lang", lang, "--out", str(tmp_path / "gen"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    files = {p.split("/")[-1] for p in data["files"]}
    assert "BUILD" in files and data["build"] in (tmp_path / "gen" / "BUILD").read_text()
    main_file = next(f for f in files if f.startswith(k["name"]) and not f.endswith(".h"))
    assert (tmp_path / "gen" / main_file).read_text() == data["code"]
    if lang == "c":
        assert f"{k['name']}.h" in files


def test_out_refused_with_list_and_unwritable_path(tmp_path, capsys):
    assert main(["codegen", "--list", "--out", str(tmp_path), "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["error"]["argument"] == "out"
    f = tmp_path / "a_file"
    f.write_text("x")
    assert main(["codegen", "reflect-2", "--lang", "c", "--out", str(f), "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["error"]["argument"] == "out"
