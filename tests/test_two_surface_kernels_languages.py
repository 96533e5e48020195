"""The two-surface kernels in Octave and Fortran on every branch: counts equal to the NumPy kernel's
exactly, exits to a few ulps (libm's atan2/sin may differ by an ulp), NaN exactly where NumPy has NaN.

Points: a 60-degree wedge (3 reflections each way), a 45-degree one (4: the angle form), a grazing
after one reflection, the right-angle wedge whose float ceiling was one short, a thin wedge
(~3000 reflections), a valid velocity, a branch that does not exist; for (M, H, v) the paper's
example, the valid velocity v = (1e-12, 1e12) and nearly parallel rows. The Octave form printed
every exit of these kernels as NaN before (0 * NaN in its inline Piecewise).
"""

from __future__ import annotations

import math
import shutil
import subprocess

import numpy as np
import pytest

from derivations.codegen import KERNEL_DIR
from impactsym import kernels as K

SGC = [(1.0, 1.0, -0.5, -1.0, -1.0), (1.0, 1.0, -math.cos(math.pi / 4), -1.0, -1.0), (1.0, 1.0, 0.5, -1.0, -1.0),
       (1e-12, 1.0, -6.123233995736766e-23, -1.0, -1e-12), (1.0, 1.0, -math.cos(1e-3), -1.0, -0.5),
       (1.0, 2.0, -0.5, 1.0, 0.5), (1.0, 1.0, -0.5, 1.0, -1.0)]
MHV = [(1.1, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, -1.0, -2.0),
       (999999999999.9999, 0.0, 1.0000000000000777, 0.955336489125606, 0.29552020666133955, 1.0000000339875186,
        0.3333333223409499, 9.999999921847224e-13, 999999999993.8527),
       (1.0, 0.0, 1.0, 1.0, 0.0, 0.9999999999995, -1.000000000262076e-06, -1.0, 0.5),
       (1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1e-3, -1.0, 0.0)]
CASES = [("two_surface_resolution", x) for x in SGC] + [("two_surface_reflection_count", x) for x in SGC] + \
        [("two_surface_resolution_2", x) for x in MHV]


def _expected(name, x):
    return [float(o) for o in getattr(K, name)(*[np.asarray(a) for a in x])]


def _compare(name, x, got):
    want = _expected(name, x)
    assert len(got) == len(want), (name, x, got)
    for g, w in zip(got, want):
        if math.isnan(w):
            assert math.isnan(g), (name, x, got, want)
        else:
            assert g == pytest.approx(w, rel=8 * 2.0**-52, abs=0.0), (name, x, got, want)


def _counts_equal(name, x, got):
    want = _expected(name, x)
    idx = [0, 1] if name == "two_surface_reflection_count" else [0, 3]
    assert [got[i] for i in idx] == [want[i] for i in idx], (name, x, got, want)


@pytest.mark.skipif(shutil.which("octave-cli") is None and shutil.which("octave") is None,
                    reason="octave not on PATH (Debian package octave)")
def test_octave_two_surface_kernels_match_numpy():
    exe = shutil.which("octave-cli") or shutil.which("octave")
    lines = [f"addpath('{KERNEL_DIR / 'octave'}');"]
    for name, x in CASES:
        n = 2 if name == "two_surface_reflection_count" else 6
        outs = ", ".join(f"o{i}" for i in range(n))
        args = ", ".join(repr(float(a)) for a in x)
        lines.append(f"[{outs}] = {name}({args}); printf('%.17e ', {outs}); printf('\\n');")
    res = subprocess.run([exe, "--no-gui", "--quiet", "--eval", "\n".join(lines)], capture_output=True, text=True,
                         timeout=300)
    rows = [ln for ln in res.stdout.splitlines() if ln.strip()]
    assert len(rows) == len(CASES), res.stdout + res.stderr
    for (name, x), row in zip(CASES, rows):
        got = [float(t) for t in row.split()]
        _counts_equal(name, x, got)
        _compare(name, x, got)


def _f(x: float) -> str:
    r = repr(float(x)).replace("e", "d")
    return r if "d" in r else r + "d0"


@pytest.mark.skipif(shutil.which("gfortran") is None, reason="gfortran not on PATH (Debian package gfortran)")
def test_fortran_two_surface_kernels_match_numpy(tmp_path):
    src = KERNEL_DIR / "fortran" / "two_surface.f90"
    res = subprocess.run(["gfortran", "-c", str(src), "-J", str(tmp_path), "-o", str(tmp_path / "ts.o")],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    calls = []
    for name, x in CASES:
        n = 2 if name == "two_surface_reflection_count" else 6
        outs = ", ".join(f"o({i + 1})" for i in range(n))
        args = ", &\n        ".join(_f(a) for a in x)
        calls.append(f"    call {name}({args}, &\n        {outs})\n    print '(*(ES26.17E3,1x))', o(1:{n})")
    prog = ("program tsk\n    use, intrinsic :: iso_c_binding, only: c_double\n    use impactsym_two_surface\n"
            "    implicit none\n    real(c_double) :: o(6)\n" + "\n".join(calls) + "\nend program tsk\n")
    (tmp_path / "tsk.f90").write_text(prog)
    res = subprocess.run(["gfortran", "-I", str(tmp_path), str(tmp_path / "tsk.f90"), str(tmp_path / "ts.o"),
                          "-o", str(tmp_path / "tsk")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    rows = subprocess.run([str(tmp_path / "tsk")], capture_output=True, text=True).stdout.splitlines()
    assert len(rows) == len(CASES)
    for (name, x), row in zip(CASES, rows):
        got = [float(t) for t in row.split()]
        _counts_equal(name, x, got)
        _compare(name, x, got)
