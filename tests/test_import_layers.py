"""The one-way layers of the README's Layout section, enforced over the source with ``ast``.

* ``impactsym`` (the library, generated kernels included) imports neither ``derivations`` nor
  ``paper_checks`` (nor ``benchmarks`` or ``tests``), at module level or inside a function, except
  the two public entry points listed in :data:`ALLOWED`: ``impactsym prove`` calls
  ``derivations.reflection.prove_all`` and ``impactsym reproduce`` calls ``paper_checks.run_audit``.
  What the library needs from a derivation is generated, committed data (``impactsym/kernels``).
* ``derivations`` never imports ``paper_checks`` (a derivation does not depend on the audit).
* ``paper_checks`` may import ``impactsym`` and ``derivations``; none of the three imports
  ``benchmarks`` or ``tests``.

Every form counts: ``import x``, ``import x.y as z``, ``from x.y import z``, and
``importlib.import_module("x...")`` / ``__import__("x...")`` with a literal name.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from probe_server import probe_paths, run_python

ROOT = Path(__file__).resolve().parents[1]

#: what each layer must not import (top-level package names)
FORBIDDEN = {
    "impactsym": ("derivations", "paper_checks", "benchmarks", "tests"),
    "derivations": ("paper_checks", "benchmarks", "tests"),
    "paper_checks": ("benchmarks", "tests"),
}

#: the only exceptions: (file, enclosing function) -> {(module, imported names)}
ALLOWED = {
    ("impactsym/cli/prove.py", "run"): {("derivations.reflection", ("PROPERTIES", "prove_all"))},
    ("impactsym/cli/reproduce.py", "run"): {("paper_checks", ("run_audit",))},
}


def _imports(tree: ast.AST):
    """Yield ``(module, names, function, lineno)`` for every import in ``tree``; ``function`` is the
    innermost enclosing function (None at module level), ``names`` None for ``import module``."""

    def walk(node, func):
        for child in ast.iter_child_nodes(node):
            inner = child.name if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)) else func
            if isinstance(child, ast.Import):
                for alias in child.names:
                    yield alias.name, None, func, child.lineno
            elif isinstance(child, ast.ImportFrom):
                if child.level == 0 and child.module:  # relative imports stay inside their package
                    yield child.module, tuple(a.name for a in child.names), func, child.lineno
            elif isinstance(child, ast.Call):
                f = child.func
                name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else None
                if name in ("import_module", "__import__") and child.args and \
                        isinstance(child.args[0], ast.Constant) and isinstance(child.args[0].value, str):
                    yield child.args[0].value, None, func, child.lineno
            yield from walk(child, inner)

    yield from walk(tree, None)


def layer_violations(source: str, path: str) -> list[str]:
    """The forbidden imports of one source file (``path`` relative to the repository root)."""
    layer = path.split("/")[0]
    forbidden = FORBIDDEN.get(layer, ())
    out = []
    for module, names, func, line in _imports(ast.parse(source, path)):
        if module.split(".")[0] not in forbidden:
            continue
        allowed = ALLOWED.get((path, func), set())
        if names is not None and (module, tuple(sorted(names))) in allowed:
            continue
        what = f"from {module} import {', '.join(names)}" if names is not None else f"import {module}"
        out.append(f"{path}:{line} ({func or 'module level'}): {what}")
    return out


def _sources(package: str):
    for p in sorted((ROOT / package).rglob("*.py")):
        if "__pycache__" not in p.parts:
            yield p.relative_to(ROOT).as_posix(), p.read_text()


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_layers_are_one_way(package):
    files = list(_sources(package))
    assert len(files) > 5, f"no sources found under {package}/"
    problems = [v for path, src in files for v in layer_violations(src, path)]
    assert not problems, "imports against the layer rules (README, Layout):\n" + "\n".join(problems)


def test_each_allowed_import_is_still_there():
    """An exception that is no longer used is removed from :data:`ALLOWED`, not left open."""
    for (path, func), allowed in ALLOWED.items():
        found = {(m, tuple(sorted(n))) for m, n, f, _ in _imports(ast.parse((ROOT / path).read_text()))
                 if f == func and n is not None}
        assert allowed <= found, (path, func, allowed - found)


@pytest.mark.parametrize("source, path", [
    ("import derivations\n", "impactsym/x.py"),
    ("import derivations.domains as d\n", "impactsym/x.py"),
    ("def f():\n    from derivations.domains import pool_g\n", "impactsym/domains.py"),
    ("class A:\n    def m(self):\n        from paper_checks.framework import VERDICTS\n", "impactsym/cli/reproduce.py"),
    ("def run(args):\n    from paper_checks.seghete_murphey import _proof\n", "impactsym/cli/reproduce.py"),
    ("def run(args):\n    from paper_checks import run_audit, evaluate_all\n", "impactsym/cli/reproduce.py"),
    ("def render(r):\n    from paper_checks import run_audit\n", "impactsym/cli/reproduce.py"),
    ("from paper_checks import run_audit\n", "impactsym/cli/reproduce.py"),
    ("def run(args):\n    from derivations.reflection import prove_all\n", "impactsym/cli/reproduce.py"),
    ("import importlib\nm = importlib.import_module('derivations.chain3')\n", "impactsym/bench.py"),
    ("m = __import__('paper_checks')\n", "impactsym/x.py"),
    ("from paper_checks.framework import identical\n", "derivations/domains.py"),
])
def test_the_checker_flags_a_forbidden_import(source, path):
    assert layer_violations(source, path), source


@pytest.mark.parametrize("source, path", [
    ("def run(args):\n    from paper_checks import run_audit\n", "impactsym/cli/reproduce.py"),
    ("def run(args):\n    from derivations.reflection import PROPERTIES, prove_all\n", "impactsym/cli/prove.py"),
    ("from .kernels import pool_g\nfrom ..numbers import exact_str\n", "impactsym/domains.py"),
    ("from impactsym.models.acary_taha import pool\n", "derivations/domains.py"),
    ("from derivations.reflection import derive_single_impact\n", "paper_checks/audit.py"),
])
def test_the_checker_lets_the_allowed_imports_through(source, path):
    assert layer_violations(source, path) == []


RUN_WITHOUT_UPPER_LAYERS = '''
import sys


class Refuse:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("derivations", "paper_checks"):
            raise ImportError(f"layer rule: the library imported {name}")
        return None


sys.meta_path.insert(0, Refuse())
from impactsym.bench import naive_outputs
from impactsym.domains import validity_domain

print(validity_domain("chain3").region["e"], validity_domain("pool").region["alpha"][0],
      validity_domain("pool", "2*pi/3").region["e"], validity_domain("pool", "pi/3", "pi/6").region["e"],
      len(naive_outputs("chain3_impulse_ratio")[1]))
'''


def test_domains_and_benchmark_run_with_derivations_unimportable():
    """At run time, the code that used to run derivations (every domain kind, the chain's naive
    form) works in a process where importing ``derivations`` or ``paper_checks`` raises (a real
    process that imports this checkout's ``impactsym`` itself, after the finder is in place)."""
    r = run_python(["-c", RUN_WITHOUT_UPPER_LAYERS])
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["(1/3,", "1)", "Max(0,", "cos(theta)/2)", "(5/9,", "1)", "(3/5,", "1)", "5"], r.stdout


def test_import_impactsym_does_not_load_matplotlib_or_scipy_integrate():
    """Figures and integrators load their heavy libraries when called, not on import (probed in a
    process that began as a fresh interpreter)."""
    code = ("import sys, impactsym, impactsym.figures, impactsym.cli; "
            "print(sorted(m for m in ('matplotlib', 'scipy.integrate') if m in sys.modules))")
    out = probe_paths([[code]])[0][0].out
    assert out.strip() == "[]", out
