"""``assert`` vanishes under ``python -O``: no module of the library, of the derivations or of the
paper checks decides anything with it (tests may). Checks raise explicitly
(``DerivationError``, ``VerificationError``, or an error naming the argument)."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_no_assert_statement_outside_tests():
    found = []
    for pkg in ("impactsym", "derivations", "paper_checks"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            if path.name.startswith("test_"):
                continue
            text = path.read_text()
            if "assert" not in text:  # an assert statement is spelled "assert": no parse needed
                continue
            tree = ast.parse(text)
            found += [f"{path.relative_to(ROOT)}:{n.lineno}" for n in ast.walk(tree) if isinstance(n, ast.Assert)]
    assert not found, f"assert statements (stripped by python -O): {found}"
