"""Start-up stays light: ``import impactsym``, ``impactsym --help``, ``impactsym codegen --list`` and
``impactsym scene list`` import no SymPy, NumPy, SciPy, mpmath or flint, ``impactsym reflect`` on
rational input only flint, and the law interface (:mod:`impactsym.lawbook`,
:mod:`impactsym.resolution`) no SymPy or mpmath, so that refusing an option costs none (probed in
forks of one fresh interpreter, snippets whose expected sets grow sharing one process, checked
through ``sys.modules``, not by timing); the lazy names of
``impactsym`` and ``impactsym.scenes`` resolve to the objects of their modules; the domain parser's
scene names are the domains' own."""

from __future__ import annotations

import importlib

import pytest

from probe_server import probe_paths

HEAVY = ("sympy", "numpy", "scipy", "mpmath", "flint", "matplotlib")


_START_UP = [
    "import impactsym",
    "import contextlib, io\nfrom impactsym.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): main(['--help'])",
    "import contextlib, io\nfrom impactsym.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): main(['codegen', '--list', '--json'])",
    "import contextlib, io\nfrom impactsym.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): assert main(['scene', 'list']) == 0",
    "import contextlib, io\nfrom impactsym.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): assert main(['scene', 'list', '--json']) == 0",
    "import impactsym.scenes.registry, impactsym.scenes.reading",
]


_REFLECT = ("import contextlib, io\nfrom impactsym.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()): assert main({argv!r}) == 0")


_RATIONAL_REFLECT = [
    ["reflect", "--mass-matrix", "2,0;0,1", "--gradient=-1,1", "--velocity", "1,0", "--json"],
    ["reflect", "--mass-matrix", "1.5,1/4;0.25,2", "--gradient", "1e-3,2", "--restitution", "0.9", "--timeout", "30"],
    ["reflect", "--mass-matrix", "3,1,0;1,3,1;0,1,3", "--gradient", "1,0,0"],
]
_LAWBOOK = "import impactsym.lawbook, impactsym.lawbook_compliant, impactsym.resolution"
_IRRATIONAL_REFLECT = ["reflect", "--mass-matrix", "sqrt(2),0;0,1", "--gradient=-1,1", "--json"]
_SETS: dict = {}


def _sets(path: str) -> list:
    """The heavy libraries loaded after each snippet of one of three paths (probe_server.probe_paths:
    forks of one fresh interpreter) that begin with the start-up snippets, whose sets must be
    empty: then the rational ``reflect`` requests (flint) and an irrational one (SymPy); the law
    interface; every law's ``--float`` refusal and an exact law that runs (SymPy). Along a path a
    library stays loaded and the sets only grow: each path orders its snippets so."""
    if not _SETS:
        reflect = [_REFLECT.format(argv=argv) for argv in _RATIONAL_REFLECT + [_IRRATIONAL_REFLECT]]
        paths = {"reflect": _START_UP + reflect,
                 "lawbook": _START_UP + [_LAWBOOK],
                 "refusals": _START_UP + [_refusal(law) for law in _FLOAT_REFUSERS] + [_NEWTON]}
        for name, steps in zip(paths, probe_paths(list(paths.values()))):
            _SETS[name] = [{m for m in HEAVY if m in step.modules} for step in steps]
    return _SETS[path]


@pytest.mark.parametrize("code", _START_UP)
def test_start_up_imports_no_heavy_library(code):
    assert _sets("reflect")[_START_UP.index(code)] == set()


@pytest.mark.parametrize("argv", _RATIONAL_REFLECT)
def test_reflect_on_rational_input_imports_only_flint(argv):
    """``reflect`` on plain rational entries runs in python-flint alone (issue 15): no SymPy, NumPy
    or mpmath at start-up."""
    assert _sets("reflect")[len(_START_UP) + _RATIONAL_REFLECT.index(argv)] == {"flint"}


def test_reflect_on_irrational_input_still_takes_sympy():
    """The probe above can fail: irrational entries load SymPy (the general path)."""
    assert "sympy" not in _sets("reflect")[-2] and "sympy" in _sets("reflect")[-1]


def test_the_law_interface_imports_no_sympy_or_mpmath():
    """The laws' table, options and outcome types (issue 15): NumPy only."""
    assert _sets("lawbook")[-1] == {"numpy"}


_RESOLVE = ("import contextlib, io\nfrom impactsym.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            "    assert main({argv!r}) == {status}")
_CHAIN = ["--mass-matrix", "1,0,0;0,1,0;0,0,1", "--gradients", "-1,1,0;0,-1,1", "--velocity", "1,0,0"]


_FLOAT_REFUSERS = ["newton", "poisson", "energetic", "impulse-ratio", "two-surface", "han-gilmore", "hertz", "lzb"]
_NEWTON = _RESOLVE.format(argv=["resolve", "--law", "newton", *_CHAIN, "--json"], status=0)


def _refusal(law: str) -> str:
    return _RESOLVE.format(argv=["resolve", "--law", law, "--float", *_CHAIN, "--json"], status=2)


@pytest.mark.parametrize("law", _FLOAT_REFUSERS)
def test_refusing_float_for_a_law_without_it_imports_no_sympy(law):
    """``--float`` belongs to ``--law sequential``: every other law refuses it (exit 2) before any
    number is read, without SymPy (all refusals probed in one process, in order)."""
    assert "sympy" not in _sets("refusals")[len(_START_UP) + _FLOAT_REFUSERS.index(law)]


def test_the_refusal_probe_can_fail():
    """The probe above can fail: an exact law that runs loads SymPy."""
    assert "sympy" not in _sets("refusals")[-2] and "sympy" in _sets("refusals")[-1]


def test_lazy_scene_names_are_the_modules_objects():
    import impactsym.scenes as scenes
    from impactsym.scenes import fileformat, reading, registry

    for name in scenes.__all__:
        assert getattr(scenes, name) is getattr(importlib.import_module(f"impactsym.scenes.{scenes._LAZY[name]}"),
                                                name), name
    assert scenes.read_scene_file is reading.read_scene_file is fileformat.read_scene_file
    assert scenes.SHIPPED_SCENES is registry.SHIPPED_SCENES
    assert set(scenes.__all__) <= set(dir(scenes))
    with pytest.raises(AttributeError, match="no attribute 'no_such_scene'"):
        scenes.no_such_scene  # noqa: B018


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
