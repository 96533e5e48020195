"""Smoke tests of the generated Rust, Fortran, Octave and Julia kernels (compiled/run where the
toolchain is present; skipped with the reason otherwise), and of ``impactsym codegen``."""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

from derivations.codegen import KERNEL_DIR
from impactsym.cli import main
from impactsym.reference_values import error_ratio, kernel_reference

CASE = {"A": 0.75, "B": -1.0, "C": 1e-13}  # partner root cancels in the naive form


def _check(values):
    ratios = error_ratio(kernel_reference("impulse_ratio_root").evaluate(CASE), values)
    assert max(ratios) <= 16, ratios


def _closed_form_samples(lang: str):
    """The kernel catalog, and one in-domain input per closed-form kernel that has a ``lang`` form,
    with the NumPy kernel's (finite) outputs there: ``(catalog, [(kernel, inputs, outputs)])``."""
    import math

    from impactsym import kernels as K
    from impactsym.hard_cases import HARD_CASES

    cat = json.loads((KERNEL_DIR / "catalog.json").read_text())["kernels"]
    samples = []
    for k in cat:
        if k["kind"] != "closed form" or k["code"][lang] is None:
            continue
        cases = [c for c in HARD_CASES if c.kernel == k["name"]]
        inputs = cases[0].inputs if cases else {a: 0.4 + 0.05 * i for i, a in enumerate(k["args"])}
        # a candidate outside the law's domain gives NaN (documented), and is skipped below
        with np.errstate(invalid="ignore", divide="ignore"):
            want = getattr(K, k["name"])(**inputs)
        want = [float(x) for x in (want if isinstance(want, tuple) else (want,))]
        if all(math.isfinite(x) for x in want):
            samples.append((k, inputs, want))
    return cat, samples


@pytest.mark.skipif(shutil.which("rustc") is None, reason="rustc not on PATH (Rust toolchain not installed)")
def test_rust_compiles_and_matches_reference(tmp_path):
    for rs in sorted((KERNEL_DIR / "rust").glob("*.rs")):
        res = subprocess.run(["rustc", "--edition", "2021", "--crate-type", "lib", "-O", str(rs), "-o",
                              str(tmp_path / (rs.stem + ".rlib"))], capture_output=True, text=True)
        assert res.returncode == 0, (rs.name, res.stderr)
    main_rs = tmp_path / "main.rs"
    main_rs.write_text(f'#[path = "{KERNEL_DIR / "rust" / "impulse_ratio_root.rs"}"]\nmod k;\n'
                       'fn main() { let (a, b) = k::impulse_ratio_root(0.75, -1.0, 1e-13); println!("{:e} {:e}", a, b); }\n')
    exe = tmp_path / "main"
    res = subprocess.run(["rustc", "--edition", "2021", "-O", "-A", "dead_code", str(main_rs), "-o", str(exe)],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    _check([float(x) for x in subprocess.run([str(exe)], capture_output=True, text=True).stdout.split()])


@pytest.fixture(scope="module")
def fortran_objects(tmp_path_factory):
    """Every committed Fortran module compiled once for this file, with ``-std=f2008 -Wall -Werror``
    (each must compile so); the folder holds the objects and the ``.mod`` files."""
    out = tmp_path_factory.mktemp("fortran")
    failed = []
    for f in sorted((KERNEL_DIR / "fortran").glob("*.f90")):
        res = subprocess.run(["gfortran", "-std=f2008", "-Wall", "-Werror", "-c", str(f), "-J", str(out),
                              "-o", str(out / (f.stem + ".o"))], capture_output=True, text=True)
        if res.returncode != 0:
            failed.append((f.name, res.stderr))
    return out, failed


@pytest.mark.skipif(shutil.which("gfortran") is None,
                    reason="gfortran not on PATH (Debian package gfortran; .ci/run installs it as root)")
def test_fortran_compiles_and_matches_reference(tmp_path, fortran_objects):
    objs, failed = fortran_objects
    assert not failed, failed
    prog = tmp_path / "p.f90"
    prog.write_text("program p\n use impactsym_impulse_ratio_root\n use, intrinsic :: iso_c_binding\n"
                    " real(c_double) :: a, b\n call impulse_ratio_root(0.75d0, -1.0d0, 1d-13, a, b)\n"
                    " print '(2ES26.17)', a, b\nend program p\n")
    exe = tmp_path / "p"
    res = subprocess.run(["gfortran", "-I", str(objs), str(prog), str(objs / "impulse_ratio_root.o"),
                          "-o", str(exe)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    _check([float(x) for x in subprocess.run([str(exe)], capture_output=True, text=True).stdout.split()])


@pytest.mark.skipif(shutil.which("octave-cli") is None and shutil.which("octave") is None,
                    reason="octave not on PATH (Debian package octave; .ci/run installs it as root)")
def test_octave_runs_and_matches_reference():
    exe = shutil.which("octave-cli") or shutil.which("octave")
    code = (f"addpath('{KERNEL_DIR / 'octave'}'); [a, b] = impulse_ratio_root(0.75, -1.0, 1e-13); "
            "printf('%.17e %.17e\\n', a, b);")
    res = subprocess.run([exe, "--no-gui", "--quiet", "--eval", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    _check([float(x) for x in res.stdout.split()[-2:]])


@pytest.mark.skipif(shutil.which("julia") is None,
                    reason="julia not on PATH (no Debian bookworm package; not on PyPI as a toolchain)")
def test_julia_runs_and_matches_reference():  # pragma: no cover - no julia here
    code = f'include("{KERNEL_DIR / "julia" / "impulse_ratio_root.jl"}"); a, b = impulse_ratio_root(0.75, -1.0, 1e-13); println(a, " ", b)'
    res = subprocess.run(["julia", "-e", code], capture_output=True, text=True, timeout=300)
    _check([float(x) for x in res.stdout.split()])


def test_naive_form_loses_the_partner_root_and_the_stable_form_does_not():
    from impactsym import kernels as K

    ref = kernel_reference("impulse_ratio_root").evaluate(CASE)
    assert max(error_ratio(ref, K.impulse_ratio_root(**CASE))) <= 16
    assert max(error_ratio(ref, K.impulse_ratio_root_naive(**CASE))) > 1e3


def test_stable_form_proofs():
    from derivations.impulse_ratio_root import stable_form_proofs

    assert all(p["proven"] for p in stable_form_proofs())


def test_cli_codegen_list_json(capsys):
    assert main(["codegen", "--list", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    names = {k["name"] for k in out["kernels"]}
    assert {"chain3-impulse-ratio", "reflect-2", "impulse-ratio-root", "reflection-map"} <= names
    assert all(k["kernel"].replace("_", "-") == k["name"] for k in out["kernels"])


@pytest.mark.parametrize("lang", ["c", "python", "numpy", "julia", "octave", "fortran", "rust"])
def test_cli_codegen_prints_each_language(capsys, lang):
    assert main(["codegen", "chain3-impulse-ratio", "--lang", lang]) == 0
    assert "chain3_impulse_ratio" in capsys.readouterr().out


@pytest.mark.parametrize("argv", [["codegen", "no-such-kernel"], ["codegen", "reflect-2", "--lang", "cobol"],
                                  ["codegen", "reflection-map", "--lang", "rust"]])
def test_cli_codegen_bad_input_exits_2(capsys, argv):
    assert main(argv) == 2
    assert "error" in capsys.readouterr().err


def test_cli_bench_json_contract(capsys, monkeypatch):
    """One formula, quick: the JSON carries the documented fields for every backend and case set.
    (Each batched timing runs its 3 calls only, not for MIN_TIME_QUICK: nothing here reads a rate.)"""
    from impactsym import bench

    monkeypatch.setattr(bench, "MIN_TIME_QUICK", 0.0)
    assert main(["bench", "--quick", "--json", "--formula", "impulse-ratio-root"]) == 0
    out = json.loads(capsys.readouterr().out)
    rows = out["results"]
    keys = {"formula", "backend", "case_set", "evals_per_second", "median_rel_error", "max_rel_error"}
    assert rows and all(keys <= set(r) for r in rows)
    assert {r["case_set"] for r in rows} == {"uniform", "hard"}
    got = {(r["backend"], r["case_set"]): r for r in rows}
    # the generated kernels keep the target on the hard set; the naive lambdify loses the partner root
    assert got[("numpy-batched", "hard")]["max_error_ratio"] <= 16
    assert got[("lambdify-naive", "hard")]["max_error_ratio"] > 1e3


def test_cli_bench_unknown_formula_exits_2(capsys):
    assert main(["bench", "--quick", "--formula", "no-such"]) == 2


@pytest.mark.skipif(shutil.which("rustc") is None, reason="rustc not on PATH (Rust toolchain not installed)")
def test_rust_every_closed_form_matches_numpy(tmp_path):
    """Every closed-form kernel's Rust form, on one in-domain input each, equals the NumPy kernel."""
    import numpy as np

    cat, samples = _closed_form_samples("rust")
    calls, expected = [], []
    for k, inputs, want in samples:
        args = ", ".join(f"{float(inputs[a])!r}_f64" for a in k["args"])
        outs = ", ".join(f"o{i}" for i in range(len(k["outputs"])))
        pat = " ".join("{:e}" for _ in k["outputs"])
        bind = f"let ({outs},) = " if len(k["outputs"]) == 1 else f"let ({outs}) = "
        if len(k["outputs"]) == 1:
            bind = "let o0 = "
        calls.append(f'    {{ {bind}{k["family"]}::{k["name"]}({args}); println!("{pat}", {outs}); }}')
        expected.append((k["name"], want))
    mods = sorted({k["family"] for k in cat if k["code"]["rust"] is not None})
    src = "".join(f'#[path = "{KERNEL_DIR / "rust" / (m + ".rs")}"]\n#[allow(dead_code)]\nmod {m};\n' for m in mods)
    src += "fn main() {\n" + "\n".join(calls) + "\n}\n"
    (tmp_path / "all.rs").write_text(src)
    res = subprocess.run(["rustc", "--edition", "2021", "-O", str(tmp_path / "all.rs"), "-o", str(tmp_path / "all")],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    lines = subprocess.run([str(tmp_path / "all")], capture_output=True, text=True).stdout.splitlines()
    assert len(expected) >= 10 and len(lines) == len(expected)
    for (name, want), line in zip(expected, lines):
        np.testing.assert_allclose([float(x) for x in line.split()], want, rtol=1e-9, atol=1e-300, err_msg=name)


def _fortran_literal(x: float) -> str:
    r = repr(float(x)).replace("e", "d")
    return r if "d" in r else r + "d0"


@pytest.mark.skipif(shutil.which("gfortran") is None,
                    reason="gfortran not on PATH (Debian package gfortran; .ci/run installs it as root)")
def test_fortran_every_closed_form_matches_numpy(tmp_path, fortran_objects):
    """Every closed-form kernel's Fortran form, on one in-domain input each, equals the NumPy kernel."""
    import numpy as np

    objs, failed = fortran_objects
    assert not failed, failed
    _, samples = _closed_form_samples("fortran")
    calls, expected = [], []
    for k, inputs, want in samples:
        n = len(k["outputs"])
        args = ", &\n        ".join(_fortran_literal(inputs[a]) for a in k["args"])
        outs = ", ".join(f"o({i + 1})" for i in range(n))
        calls.append(f"    call {k['name']}({args}, &\n        {outs})\n    print '(*(ES26.17E3,1x))', o(1:{n})")
        expected.append((k["name"], want))
    mods = sorted(f.stem for f in (KERNEL_DIR / "fortran").glob("*.f90"))
    prog = ("program allk\n    use, intrinsic :: iso_c_binding, only: c_double\n"
            + "".join(f"    use impactsym_{m}\n" for m in mods)
            + "    implicit none\n    real(c_double) :: o(16)\n" + "\n".join(calls) + "\nend program allk\n")
    (tmp_path / "allk.f90").write_text(prog)
    res = subprocess.run(["gfortran", "-I", str(objs), str(tmp_path / "allk.f90"),
                          *[str(objs / (m + ".o")) for m in mods], "-o", str(tmp_path / "allk")],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    lines = subprocess.run([str(tmp_path / "allk")], capture_output=True, text=True).stdout.splitlines()
    assert len(expected) >= 10 and len(lines) == len(expected)
    for (name, want), line in zip(expected, lines):
        np.testing.assert_allclose([float(x) for x in line.split()], want, rtol=1e-9, atol=1e-300, err_msg=name)
