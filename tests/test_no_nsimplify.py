"""``sympy.nsimplify`` guesses a nearby simple number (``nsimplify(1/10**40)`` is 0): it must never
touch exact data. The only calls allowed turn a *float* into display text, and they say so."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: file -> number of allowed calls, each on a value already known to be a float
ALLOWED = {
    "impactsym/mechanics.py": 1,  # a float mass matrix's leading minor, for the error message only
    "impactsym/numbers.py": 1,  # exact_str of a sympy Float (display of a float input)
}


def _calls(path: Path) -> int:
    text = path.read_text()
    if "nsimplify" not in text:  # every call or binding counted below spells the name
        return 0
    tree = ast.parse(text)
    n = 0
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", None)
            n += name == "nsimplify"
        if isinstance(node, ast.Attribute) and node.attr == "nsimplify" and not isinstance(node.ctx, ast.Load):
            n += 1
    return n


def test_no_nsimplify_on_exact_paths():
    found = {}
    for pkg in ("impactsym", "derivations", "paper_checks"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            n = _calls(path)
            if n:
                found[str(path.relative_to(ROOT))] = n
    extra = {k: v for k, v in found.items() if v > ALLOWED.get(k, 0)}
    assert not extra, f"nsimplify on a path that may carry exact data: {extra}"
