"""The probe server (tests/probe_server.py) answers as fresh processes do: a fork of its cold root
holds exactly the modules a fresh interpreter running the same snippets holds, where the paths
part as where they share a process; a child of its warm server has the exit status, standard
output and standard error of a fresh ``python -m impactsym``, and a crash shows as one."""

from __future__ import annotations

import ast
import subprocess
import sys

import pytest

from probe_server import REQUEST_PREAMBLE, ROOT, probe_paths, request_snippet, root_modules, run_python

COLD_ENV = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
#: a prefix two paths share, then where they part: the first continues in a fork of its own, the
#: last in the process of the prefix
PREFIX = [REQUEST_PREAMBLE, request_snippet(["scene", "list"], 0)]
ENDS = [request_snippet(["resolve", "--law", "sequential", "--float", "--mass-matrix", "1,0;0,1", "--gradients",
                         "1,0;-1,1", "--velocity", "-1,-2", "--json"], 0),
        "import colorsys"]


def _fresh_modules(snippets) -> list:
    """``sorted(sys.modules)`` after each snippet, run in order by one fresh interpreter."""
    code = "".join(f"{s}\nprint(sorted(sys.modules))\n" for s in ["import sys", *snippets])
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=COLD_ENV)
    assert res.returncode == 0, res.stderr
    return [set(ast.literal_eval(line)) for line in res.stdout.splitlines()]


def test_the_root_is_a_fresh_interpreter():
    assert set(root_modules()) == _fresh_modules([])[0]


def test_each_path_sees_what_a_fresh_interpreter_sees():
    paths = [PREFIX + [end] for end in ENDS]
    fresh = [_fresh_modules(path)[1:] for path in paths]
    assert [[set(step.modules) for step in steps] for steps in probe_paths(paths)] == fresh
    # the comparison sees modules come in: NumPy with the request, colorsys with its import
    assert [("numpy" in f[1], "numpy" in f[2]) for f in fresh] == [(False, True), (False, False)]
    assert [("colorsys" in f[1], "colorsys" in f[2]) for f in fresh] == [(False, False), (False, True)]


def test_a_probe_reports_the_snippets_output_and_raises_its_error():
    steps = probe_paths([["x = 6 * 7", "print(x)"]])[0]
    assert [s.out for s in steps] == ["", "42\n"]
    with pytest.raises(AssertionError, match="ValueError: no such thing"):
        probe_paths([["raise ValueError('no such thing')"]])


def test_a_warm_child_answers_as_a_fresh_process():
    argv = ["-m", "impactsym", "resolve", "--law", "--json"]
    fresh = subprocess.run([sys.executable, *argv], capture_output=True, text=True, cwd=ROOT, env=COLD_ENV)
    warm = run_python(argv)
    assert (warm.returncode, warm.stdout, warm.stderr) == (fresh.returncode, fresh.stdout, fresh.stderr)
    assert warm.returncode == 2 and warm.stdout.startswith('{"error": {"argument": "law"') and "usage:" in warm.stderr


def test_a_warm_child_shows_a_crash_its_status_and_its_input():
    crash = run_python(["-c", "import sys\nprint('before')\nraise ValueError('bug')"])
    assert crash.returncode == 1 and crash.stdout == "before\n"
    assert "Traceback" in crash.stderr and "ValueError: bug" in crash.stderr
    status = run_python(["-c", "import sys\nsys.stdout.write(sys.stdin.read().upper())\nsys.exit(3)", "x"],
                        input="line\r\nnext")
    assert (status.returncode, status.stdout, status.stderr) == (3, "LINE\nNEXT", "")
