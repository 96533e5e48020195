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
        code = main(["reproduce", "--json", "-j", "1"])  # in-process: paper_checks tests reuse its memo
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
    code = main(["reproduce", "--paper", "acary-taha", "--json", "-j", "2"])  # a worker process decides it
    data = json.loads(capsys.readouterr().out)
    assert code == 1
    assert data["summary"]["verdict_differs"] == ["at-eq18-q3"]


def test_a_raising_check_fails_the_run(monkeypatch, capsys):
    load_all()
    reg = REGISTRY["sm-III-B1-G"]

    def boom():
        raise RuntimeError("injected failure")

    monkeypatch.setattr(reg, "func", boom)
    code = main(["reproduce", "--paper", "seghete-murphey", "-j", "2"])
    out = capsys.readouterr().out
    assert code == 1 and "RAISED" in out and "sm-III-B1-G" in out


def test_report_has_errata_corrections_and_figure(tmp_path, capsys):
    code = main(["reproduce", "--paper", "acary-taha", "--report", str(tmp_path), "-j", "1"])
    assert code == 0
    text = (tmp_path / "report.md").read_text()
    assert "## Errata and their corrections" in text and "at-eq31" in text and "$$" in text
    assert "| **total** | **115** |" in text  # the README's table (verdict_table), for this paper
    assert "**erratum** (judgment)" in text  # typography readings are flagged, as in the printed table
    assert (tmp_path / "fig3.png").stat().st_size > 1000
    assert "report written to" in capsys.readouterr().out


def _comparable(data):
    """A run's JSON without what legitimately differs between two runs: timings and the temporary
    folder a figure was drawn in."""
    import re

    def norm(x):
        if isinstance(x, dict):
            return {k: norm(v) for k, v in x.items() if k != "seconds"}
        if isinstance(x, list):
            return [norm(v) for v in x]
        if isinstance(x, str):
            return re.sub(r"/impactsym-fig3-[^/]+/", "/TMP/", x)
        return x

    return norm(data)


def test_parallel_records_equal_serial_records(audit_json, capsys):
    """``-j 2`` (claims, the G_u derivation and the cross-check on two worker processes, each record
    rendered to JSON where it was evaluated) prints the same records, in the same order, as the
    serial run. The workers are forked from this process and start from its memo: what is tested
    is the distribution, the rendering and the reassembly (a from-scratch ``-j 2`` run was compared
    with ``-j 1`` the same way when it was written; the claim functions are the same code)."""
    serial = json.loads(audit_json[1])
    code = main(["reproduce", "--paper", "seghete-murphey", "--json", "-j", "2"])
    parallel = json.loads(capsys.readouterr().out)
    assert code == 0
    sm = [c for c in serial["claims"] if c["paper"] == "seghete-murphey"]
    assert _comparable(parallel["claims"]) == _comparable(sm)
    for key in ("G_u_derivation", "crosscheck"):
        assert _comparable(parallel["summary"][key]) == _comparable(serial["summary"][key])
    assert parallel["summary"]["per_paper"] == {"seghete-murphey": serial["summary"]["per_paper"]["seghete-murphey"]}
    assert parallel["summary"]["ok"]


@pytest.mark.parametrize("jobs", ["0", "-1", "two", "1.5"])
def test_bad_jobs_exit_2(jobs, capsys):
    code = main(["reproduce", "--jobs", jobs, "--json"])
    err = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and err["argument"] == "jobs" and "positive integer" in err["message"]


def test_the_audit_collects_at_its_thresholds_and_puts_them_back(monkeypatch, capsys):
    """``reproduce`` runs the audit at AUDIT_GC_THRESHOLDS and leaves the caller's thresholds as it
    found them, also when the audit raises."""
    import gc

    import paper_checks
    from impactsym.cli.reproduce import AUDIT_GC_THRESHOLDS

    seen = []

    def audit(paper, jobs):
        seen.append(gc.get_threshold())
        raise RuntimeError("stop here")

    monkeypatch.setattr(paper_checks, "run_audit", audit)
    saved = gc.get_threshold()
    try:
        gc.set_threshold(700, 10, 10)
        with pytest.raises(RuntimeError, match="stop here"):
            main(["reproduce", "-j", "1"])
        assert seen == [AUDIT_GC_THRESHOLDS] and gc.get_threshold() == (700, 10, 10)
    finally:
        gc.set_threshold(*saved)
