"""``impactsym reproduce``: the CLI contract (one JSON object, exit codes, report) of the paper audit."""

import json

import pytest

from impactsym.cli import main
from paper_checks.framework import REGISTRY, VERDICTS, load_all


@pytest.fixture(scope="module")
def audit_json():
    import io
    import contextlib

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["reproduce", "--json"])
    return code, buf.getvalue()


def test_json_is_one_object_with_claims_and_summary(audit_json):
    code, out = audit_json
    assert code == 0
    data = json.loads(out)  # exactly one JSON document on stdout
    assert set(data) == {"claims", "summary"}
    load_all()
    assert len(data["claims"]) == len(REGISTRY)
    s = data["summary"]
    assert s["ok"] and s["all_evaluated"] and not s["raised"] and not s["verdict_differs"]
    assert sum(s["per_verdict"].values()) == len(data["claims"])
    for paper, counts in s["per_paper"].items():
        assert counts["claims"] == sum(counts[v] for v in VERDICTS)
    assert s["crosscheck"]["ok"] and s["G_u_derivation"]["all_proven"]


def test_every_claim_record_is_complete(audit_json):
    data = json.loads(audit_json[1])
    for c in data["claims"]:
        assert c["id"] and c["paper"] in ("seghete-murphey", "acary-taha") and c["ref"] and c["quantity"]
        assert c["verdict"] in VERDICTS and c["verdict"] == c["expected"]
        assert c["published"], c["id"]
        if c["verdict"] == "erratum":
            assert c["corrected"] is not None, c["id"]
        assert c["ref"].startswith(("eq.", "sec.")), c["ref"]


def test_a_changed_verdict_fails_the_run(monkeypatch, capsys):
    load_all()
    reg = REGISTRY["at-eq18-q3"]
    monkeypatch.setattr(reg, "expected", "exact-match")  # pretend the misprint had been pinned as a match
    code = main(["reproduce", "--paper", "acary-taha", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 1
    assert data["summary"]["verdict_differs"] == ["at-eq18-q3"]


def test_a_raising_check_fails_the_run(monkeypatch, capsys):
    load_all()
    reg = REGISTRY["sm-III-B1-G"]

    def boom():
        raise RuntimeError("injected failure")

    monkeypatch.setattr(reg, "func", boom)
    code = main(["reproduce", "--paper", "seghete-murphey"])
    out = capsys.readouterr().out
    assert code == 1 and "RAISED" in out and "sm-III-B1-G" in out


def test_report_has_errata_corrections_and_figure(tmp_path, capsys):
    code = main(["reproduce", "--paper", "acary-taha", "--report", str(tmp_path)])
    assert code == 0
    text = (tmp_path / "report.md").read_text()
    assert "## Errata and their corrections" in text and "at-eq31" in text and "$$" in text
    assert "| **total** | **115** |" in text  # the README's table (verdict_table), for this paper
    assert "**erratum** (judgment)" in text  # typography readings are flagged, as in the printed table
    assert (tmp_path / "fig3.png").stat().st_size > 1000
    assert "report written to" in capsys.readouterr().out
