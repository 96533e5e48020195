"""One test per claim: the claim must evaluate without raising and reach its pinned verdict."""

import pytest

from paper_checks.framework import REGISTRY, VERDICTS, evaluate, load_all

load_all()
IDS = sorted(REGISTRY, key=lambda k: REGISTRY[k].order)


@pytest.mark.parametrize("claim_id", IDS)
def test_claim(claim_id):
    c = evaluate(claim_id)
    assert c.status != "raised", c.error
    assert c.verdict in VERDICTS
    assert c.verdict == c.expected, f"{claim_id}: verdict {c.verdict!r}, pinned {c.expected!r}. Note: {c.note}"
    if c.verdict == "erratum":
        assert c.corrected is not None
    if c.verdict in ("not-checkable", "convention-difference", "refuted", "match-at-published-precision"):
        assert c.note, "these verdicts must say why"


def test_ids_unique_and_papers_known():
    assert len(IDS) == len(set(IDS))
    assert {REGISTRY[i].paper for i in IDS} <= {"seghete-murphey", "acary-taha"}


def test_crosscheck_within_bounds():
    from paper_checks.crosscheck import run_crosschecks

    r = run_crosschecks()
    bad = [e for e in r["examples"] if not e["ok"]]
    assert not bad, bad


NUMBERED = {
    "seghete-murphey": {"1a", "1b", "2a", "2b", "3", "4", "5", "6a", "6b"},
    "acary-taha": {str(k) for k in range(1, 46)},
}


def test_every_numbered_equation_has_a_record():
    import re

    for paper, eqs in NUMBERED.items():
        found = {m for r in REGISTRY.values() if r.paper == paper for m in re.findall(r"eq\. (\w+)", r.ref)}
        assert eqs <= found, sorted(eqs - found)


def test_decimal_comparison_distinguishes_rounding_from_truncation():
    import sympy as sp

    from paper_checks.framework import compare_decimal

    # Acary & Taha sec. 3.3: q3+ = 380/381 printed 0.99 (truncated), q1+ = -19/381 printed -0.05 (rounded)
    assert compare_decimal(sp.Rational(380, 381), "0.99")["agreement"] == "truncation"
    assert compare_decimal(sp.Rational(-19, 381), "-0.05")["agreement"] == "rounding"
    assert compare_decimal(sp.Rational(1, 21), "0.0476")["agreement"] == "rounding and truncation"
    assert compare_decimal(sp.Rational(20, 21), "0.9524")["agreement"] == "rounding"
    assert compare_decimal(sp.Rational(20, 21), "0.9600")["agreement"] == "neither"
