"""The cost model (``impactsym bench --law NAME``; issue 15): the growth fit recovers a known
exponent and calls a noisy series poor; a small run writes its table, JSON and plot; the problem
families are deterministic; bad input exits 2. No timed assertion: only the shape of the results."""

from __future__ import annotations

import json
import math
import random

import pytest

from impactsym.cli import main
import numpy as np

from impactsym import cost_model
from impactsym.cost_model import (COST_LAWS, POOR_RMS, approaching_cradle, dense_system, digits_chain, fit_exponent,
                                  fit_growth, law_cost)


@pytest.fixture(autouse=True)
def _no_minimum_timing(monkeypatch):
    """The bench repeats a short call for at least MIN_SECONDS (0.1 s) of wall time to take a stable
    median; these tests check the shape of its results (at least ``repeats`` calls), not the
    timings, so they take the ``repeats`` calls only."""
    monkeypatch.setattr(cost_model, "MIN_SECONDS", 0.0)


def _run(capsys, *argv):
    code = main(["bench", *argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


# ------------------------------------------------------------------------------------ the fit
@pytest.mark.parametrize("k, model", [(0.0, "O(1)"), (1.0, "O(n)"), (2.0, "O(n^2)"), (2.5, "~n^2.50")])
def test_fit_recovers_a_known_exponent(k, model):
    sizes = [2, 4, 8, 16, 32, 64]
    fit = fit_growth(sizes, [3.0 * s ** k for s in sizes])
    assert fit["exponent"] == k and fit["quality"] == "good" and fit["model"] == model
    assert fit["rms"] == 0.0 and fit["stderr"] == 0.0 and fit["points"] == 6
    assert fit["tail"]["exponent"] == k and fit["tail"]["from_size"] == 16  # the largest half: 16, 32, 64


def test_fit_with_mild_noise_stays_good_and_close():
    rng = random.Random(1)
    sizes = [2 ** i for i in range(1, 9)]
    fit = fit_growth(sizes, [s ** 1.5 * math.exp(rng.uniform(-0.05, 0.05)) for s in sizes])
    assert fit["quality"] == "good" and abs(fit["exponent"] - 1.5) < 0.05 and fit["stderr"] < 0.05


def test_a_noisy_series_is_reported_as_a_poor_fit():
    rng = random.Random(15)
    sizes = [2 ** i for i in range(1, 9)]
    fit = fit_growth(sizes, [s * math.exp(rng.gauss(0, 1.5)) for s in sizes])
    assert fit["rms"] > POOR_RMS and fit["quality"] == "poor" and fit["model"] is None


def test_the_tail_fit_sees_past_a_constant_overhead():
    sizes = [2 ** i for i in range(1, 11)]
    values = [1000.0 + s ** 2 for s in sizes]  # flat, then quadratic
    fit = fit_growth(sizes, values)
    assert fit["exponent"] < 1.5 and abs(fit["tail"]["exponent"] - 2) < 0.25


def test_too_few_points():
    assert fit_growth([3, 4], [1.0, 2.0])["quality"] == "too few points"
    assert fit_growth([3], [1.0])["exponent"] is None
    assert fit_growth([3, 4], [1.0, 0.0])["exponent"] is None  # a non-positive value is dropped
    assert fit_exponent([2, 4, 8], [4.0, 16.0, 64.0]) == 2.0


# ---------------------------------------------------------------------------- the problems
def test_every_law_of_the_lawbook_has_a_cost_family():
    from impactsym.lawbook import LAWS

    assert list(COST_LAWS) == list(LAWS)


def test_problem_families_are_deterministic_and_as_described():
    a, b = digits_chain(8), digits_chain(8)
    assert (a.M, a.v, a.restitution, a.options) == (b.M, b.v, b.restitution, b.options)
    assert all(len(str(x.p)) == 8 and len(str(x.q)) == 8 for x in a.M.diagonal())
    assert all(w < 0 for w in a.H * a.v)  # both contacts approach
    d = dense_system(7)
    assert d.M == d.M.T and sum(x != 0 for x in d.M) >= 0.8 * 49 and d.M.is_positive_definite  # dense SPD
    assert list(d.H * d.v) == [-1, -2]
    c = approaching_cradle(5)
    assert all(w < 0 for w in c.H * c.v)


# ------------------------------------------------------------------------ runs and outputs
def test_one_cheap_law_writes_its_table_json_and_plot(capsys, tmp_path):
    code, data = _run(capsys, "--law", "poisson", "--axis", "balls", "--sizes", "3,4", "--out", str(tmp_path))
    assert code == 0
    rep = data["cost_model"]
    assert rep["machine"]["cores"] >= 1 and rep["machine"]["cpu"] and rep["machine"]["load_start"] is not None
    (r,) = rep["results"]
    assert r["law"] == "poisson" and r["paths"] == ["exact", "float"]
    (axis,) = r["axes"]
    assert axis["axis"] == "balls"
    assert [(x["size"], x["contacts"], x["coordinates"]) for x in axis["rows"]] == [(3, 2, 3), (4, 3, 4)]
    for row in axis["rows"]:
        for path in ("exact", "float"):
            assert row[path]["seconds"] > 0 and row[path]["peak_kib"] > 0 and row[path]["calls"] >= 3
    assert axis["fits"]["exact"]["time"]["points"] == 2
    md = (tmp_path / "cost_model.md").read_text()
    assert "### poisson" in md and "| balls | 3 | 2 | 3 |" in md and "cost_model/poisson.png" in md
    assert rep["machine"]["cpu"] in md
    assert (tmp_path / "cost_model" / "poisson.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((tmp_path / "cost_model.json").read_text())["results"][0]["law"] == "poisson"


def test_a_run_of_one_law_replaces_its_table_and_keeps_the_others(capsys, tmp_path):
    """``--out`` into a directory with a cost model: the law measured now replaces its own table,
    plot and JSON entry; the other laws are kept with the run that measured them, named in the
    header; the laws stay in the lawbook's order."""
    assert _run(capsys, "--law", "poisson", "--axis", "balls", "--sizes", "3", "--out", str(tmp_path))[0] == 0
    first = json.loads((tmp_path / "cost_model.json").read_text())
    poisson_png = (tmp_path / "cost_model" / "poisson.png").read_bytes()
    assert _run(capsys, "--law", "newton", "--axis", "balls", "--sizes", "3,4", "--out", str(tmp_path))[0] == 0
    both = json.loads((tmp_path / "cost_model.json").read_text())
    assert [r["law"] for r in both["results"]] == [x for x in COST_LAWS if x in ("newton", "poisson")]
    kept = next(r for r in both["results"] if r["law"] == "poisson")
    assert kept == first["results"][0]  # as the first run wrote it, its run included
    assert kept["run"]["command"] == "impactsym bench --law poisson" and both["measured"] == ["newton"]
    assert (tmp_path / "cost_model" / "poisson.png").read_bytes() == poisson_png
    md = (tmp_path / "cost_model.md").read_text()
    assert "### poisson" in md and "### newton" in md and "| balls | 4 | 3 | 4 |" in md
    assert "That run measured newton" in md and "- poisson: `impactsym bench --law poisson` on " in md
    # newton again, with other sizes: its table replaced, not appended
    assert _run(capsys, "--law", "newton", "--axis", "balls", "--sizes", "3", "--out", str(tmp_path))[0] == 0
    again = json.loads((tmp_path / "cost_model.json").read_text())
    assert [r["law"] for r in again["results"]] == [r["law"] for r in both["results"]]
    assert [x["size"] for x in next(r for r in again["results"] if r["law"] == "newton")["axes"][0]["rows"]] == [3]
    assert "| balls | 4 | 3 | 4 |" not in (tmp_path / "cost_model.md").read_text()


@pytest.mark.parametrize("text", ["not json", '{"results": [{"axes": []}]}', '{"other": 1}'])
def test_a_cost_model_json_that_is_not_ours_is_refused_before_the_work(capsys, tmp_path, monkeypatch, text):
    (tmp_path / "cost_model.json").write_text(text)
    monkeypatch.setattr(cost_model, "run", lambda *a, **k: pytest.fail("measured before refusing --out"))
    code, data = _run(capsys, "--law", "newton", "--axis", "balls", "--sizes", "3", "--out", str(tmp_path))
    assert code == 2 and data["error"]["argument"] == "out" and "not a cost model" in data["error"]["message"]
    assert (tmp_path / "cost_model.json").read_text() == text


def test_a_compliant_law_has_the_float_path_only(capsys):
    code, data = _run(capsys, "--law", "linear", "--axis", "balls", "--sizes", "3")
    assert code == 0
    (r,) = data["cost_model"]["results"]
    assert r["paths"] == ["float"] and "exact" not in r["axes"][0]["rows"][0]
    assert r["axes"][0]["rows"][0]["float"]["steps"] > 0


def test_two_surface_is_fitted_against_the_reflection_count(capsys):
    code, data = _run(capsys, "--law", "two-surface", "--axis", "reflections", "--sizes", "1,2")
    assert code == 0
    axis = data["cost_model"]["results"][0]["axes"][0]
    # two balls and a wall, masses 1 : 100^d: the count is the first digits of pi times 10^d
    assert [x["exact"]["reflections"] for x in axis["rows"]] == [32, 314] and axis["x"] == "reflections"


def test_the_sequential_search_reports_its_states():
    r = law_cost("sequential", axes=["approaching"], sizes=(4, 5), repeats=1)
    rows = r["axes"][0]["rows"]
    states = [x["exact"]["states"] for x in rows]
    assert 0 < states[0] < states[1]  # the count itself is the sequential law's business (it may shrink)
    assert "time_vs_states" in r["axes"][0]["fits"]["exact"]


def test_a_series_stops_before_a_call_over_the_cap():
    r = law_cost("poisson", axes=["balls"], sizes=(3, 4, 5), repeats=1, max_call=1e-9)
    rows = r["axes"][0]["rows"]
    assert [x["size"] for x in rows] == [3, 4] and "seconds" in rows[0]["exact"]
    assert rows[1]["exact"]["stopped"].startswith("skipped: the call at size 3 took")


@pytest.mark.parametrize("argv, argument, words", [
    (["--law", "nonexistent"], "law", "unknown 'nonexistent'"),
    (["--law", "newton", "--axis", "nope"], "axis", "no axis 'nope'"),
    (["--law", "newton", "--sizes", "3,4"], "sizes", "name one with --axis"),
    (["--law", "newton", "--axis", "balls", "--sizes", "0,3"], "sizes", "positive integers"),
    (["--law", "newton", "--axis", "balls", "--sizes", "a"], "sizes", "positive integers"),
    (["--law", "newton", "--axis", "balls", "--sizes", "1"], "sizes", "must lie in [2, 200]"),
    (["--law", "sequential", "--axis", "approaching", "--sizes", "13"], "sizes", "must lie in [2, 12]"),
    (["--law", "all", "--axis", "balls"], "axis", "one law"),
    (["--law", "newton", "--formula", "reflect_2"], "formula", "does not apply"),
    (["--sizes", "3"], "sizes", "with --law only"),
    (["--axis", "balls"], "axis", "with --law only"),
])
def test_bad_input_exits_2(capsys, argv, argument, words):
    code, data = _run(capsys, *argv)
    assert code == 2 and data["error"]["argument"] == argument and words in data["error"]["message"]


def test_unknown_law_without_json_is_one_clear_line(capsys):
    assert main(["bench", "--law", "nonexistent"]) == 2
    err = capsys.readouterr().err
    assert "law" in err and "unknown 'nonexistent'" in err and "lzb" in err and "Traceback" not in err


def test_out_must_be_a_directory(capsys, tmp_path):
    f = tmp_path / "file.txt"
    f.write_text("x")
    code, data = _run(capsys, "--law", "newton", "--out", str(f))
    assert code == 2 and data["error"]["argument"] == "out"


def test_a_call_past_the_hard_limit_is_interrupted():
    with pytest.raises(cost_model.CallTimeout):
        with cost_model._hard_limit(0.05):
            while True:
                pass


def test_warnings_and_non_finite_outcomes_are_recorded_and_shown():
    import types
    import warnings

    def call():
        warnings.warn("overflow encountered in matmul", RuntimeWarning)
        return types.SimpleNamespace(law="energetic", details={},
                                     outcomes=[types.SimpleNamespace(velocity=np.array([np.nan, 1.0]))])

    m = cost_model._measure(call, repeats=1)
    assert m["finite"] is False and m["warnings"] == ["RuntimeWarning: overflow encountered in matmul"]
    fit = fit_growth([64], [m["seconds"]])
    r = {"law": "energetic", "title": "t", "paths": ["float"], "float_note": "n",
         "axes": [{"axis": "dimension", "symbol": "n", "description": "d", "x": "size", "also": None,
                   "rows": [{"size": 64, "contacts": 2, "coordinates": 64, "float": m}],
                   "fits": {"float": {"time": fit, "memory": fit}}}]}
    md = cost_model.markdown({"results": [r]})
    assert "(!)" in md and "dimension 64, float: the outcome holds NaN or infinity" in md
    assert "warning RuntimeWarning: overflow encountered in matmul" in md
