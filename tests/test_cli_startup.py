"""Start-up stays light: ``import impactsym``, ``impactsym --help`` and ``impactsym codegen --list``
import no SymPy, NumPy, SciPy, mpmath or flint, and ``impactsym reflect`` on rational input only
flint (each runs in a fresh interpreter, checked through ``sys.modules``, not by timing); the lazy names of ``impactsym`` resolve to the objects of their
modules; the domain parser's scene names are the domains' own."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("sympy", "numpy", "scipy", "mpmath", "flint", "matplotlib")


def _loaded_after(code: str) -> set:
    probe = (f"import sys\n{code}\n"
             f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))")
    res = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert res.returncode == 0, res.stderr
    return set(res.stdout.split())


@pytest.mark.parametrize("code", [
    "import impactsym",
    "import contextlib, io\nfrom impactsym.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): main(['--help'])",
    "import contextlib, io\nfrom impactsym.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): main(['codegen', '--list', '--json'])",
])
def test_start_up_imports_no_heavy_library(code):
    assert _loaded_after(code) == set()


_REFLECT = ("import contextlib, io\nfrom impactsym.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()): assert main({argv!r}) == 0")


@pytest.mark.parametrize("argv", [
    ["reflect", "--mass-matrix", "2,0;0,1", "--gradient=-1,1", "--velocity", "1,0", "--json"],
    ["reflect", "--mass-matrix", "1.5,1/4;0.25,2", "--gradient", "1e-3,2", "--restitution", "0.9", "--timeout", "30"],
    ["reflect", "--mass-matrix", "3,1,0;1,3,1;0,1,3", "--gradient", "1,0,0"],
])
def test_reflect_on_rational_input_imports_only_flint(argv):
    """``reflect`` on plain rational entries runs in python-flint alone (issue 15): no SymPy, NumPy
    or mpmath at start-up."""
    assert _loaded_after(_REFLECT.format(argv=argv)) == {"flint"}


def test_reflect_on_irrational_input_still_takes_sympy():
    """The probe above can fail: irrational entries load SymPy (the general path)."""
    argv = ["reflect", "--mass-matrix", "sqrt(2),0;0,1", "--gradient=-1,1", "--json"]
    assert "sympy" in _loaded_after(_REFLECT.format(argv=argv))


def test_lazy_names_are_the_modules_objects():
    import impactsym
    from impactsym.errors import ImpactInputError
    from impactsym.laws.reflection import reflection_map

    assert impactsym.reflection_map is reflection_map
    assert impactsym.ImpactInputError is ImpactInputError
    assert set(impactsym.__all__) <= set(dir(impactsym))
    for name in impactsym.__all__:
        assert getattr(impactsym, name) is not None, name
    with pytest.raises(AttributeError, match="no attribute 'no_such_law'"):
        impactsym.no_such_law  # noqa: B018


def test_domain_scene_names_are_the_domains_scenes():
    from impactsym.cli.domain import SCENE_NAMES
    from impactsym.domains import SCENES

    assert tuple(SCENE_NAMES) == tuple(SCENES)


def test_the_clis_copy_of_the_scene_parameters_is_the_registrys():
    from impactsym.cli.scene_args import ALL_PARAMS
    from impactsym.scenes.registry import ALL_PARAMS as REGISTRY

    assert ALL_PARAMS == REGISTRY
