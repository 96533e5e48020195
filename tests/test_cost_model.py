"""``impactsym bench --law NAME``: the cost model's shape (no timed assertion): one row per size with
the problem's contacts and coordinates, the reflection count for two surfaces, a fitted exponent;
bad input exits 2."""

from __future__ import annotations

import json

import pytest

from impactsym.cli import main
from impactsym.cost_model import LAWS, fit_exponent


def _run(capsys, *argv):
    code = main(["bench", *argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_cradle_law_rows_count_contacts_and_coordinates(capsys):
    code, data = _run(capsys, "--law", "poisson", "--sizes", "3,5")
    assert code == 0
    r = data["cost_model"]
    assert r["law"] == "poisson" and r["exact"] and r["size_name"] == "balls"
    assert [(x["size"], x["contacts"], x["coordinates"]) for x in r["rows"]] == [(3, 2, 3), (5, 4, 5)]
    assert all(x["seconds"] > 0 and x["peak_kib"] > 0 for x in r["rows"])
    assert isinstance(r["time_exponent"], float) and isinstance(r["memory_exponent"], float)


def test_two_surface_size_is_the_reflection_count(capsys):
    code, data = _run(capsys, "--law", "two-surface", "--sizes", "1,2")
    assert code == 0
    rows = data["cost_model"]["rows"]
    # two balls and a wall, masses 1 : 100^d: the count is the first digits of pi times 10^d
    assert [x["reflections"] for x in rows] == [32, 314]


def test_every_law_has_a_problem_family():
    assert set(LAWS) == {"sequential", "two-surface", "newton", "poisson", "energetic", "han-gilmore", "impulse-ratio"}


def test_fit_exponent():
    assert fit_exponent([2, 4, 8], [4.0, 16.0, 64.0]) == 2.0
    assert fit_exponent([3], [1.0]) is None
    assert fit_exponent([3, 4], [1.0, 0.0]) is None


@pytest.mark.parametrize("argv, argument", [
    (["--law", "nope"], "law"),
    (["--law", "newton", "--sizes", "0,3"], "sizes"),
    (["--law", "newton", "--sizes", "a"], "sizes"),
    (["--law", "newton", "--sizes", "1"], "sizes"),
    (["--law", "sequential", "--sizes", "80"], "sizes"),
    (["--law", "newton", "--formula", "reflect_2"], "formula"),
    (["--sizes", "3"], "sizes"),
])
def test_bad_input_exits_2(capsys, argv, argument):
    code, data = _run(capsys, *argv)
    assert code == 2 and data["error"]["argument"] == argument
