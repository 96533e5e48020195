"""The README's verdict table is the audit's own count: rebuilt from the claims and compared."""

from pathlib import Path

from impactsym.cli.reproduce import verdict_table
from paper_checks.audit import count_verdicts
from paper_checks.framework import evaluate_all

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_verdict_table_is_the_audits():
    claims = evaluate_all()  # memoized per process: shared with test_claims and the reproduce tests
    assert all(c.status == "ok" for c in claims), [c.id for c in claims if c.status != "ok"]
    table = verdict_table(count_verdicts(claims))
    text = README.read_text()
    assert table in text, "README's verdict table differs from the audit; it should read:\n" + table
