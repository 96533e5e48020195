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
