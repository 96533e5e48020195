"""``--plot FILE`` on ``resolve``, ``domain`` and ``bench``: the figure is written (a non-empty PNG),
and the path is checked before the work (a directory that does not exist is exit 2 naming ``plot``,
with nothing computed)."""

from __future__ import annotations

import json

import pytest

from impactsym.cli import main

PNG = b"\x89PNG\r\n\x1a\n"


def _png(path):
    data = path.read_bytes()
    assert data[:8] == PNG and len(data) > 2000
    return data


@pytest.mark.parametrize("argv", [
    ["resolve", "--law", "two-surface", "--mass-matrix", "11/10,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,-2"],
    ["resolve", "--law", "sequential", "--scene", "two-balls-wall", "--masses", "11/10,1"],
    ["resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "5", "--strikers", "2"],
    ["resolve", "--law", "han-gilmore", "--scene", "chain3"],
    ["resolve", "--law", "impulse-ratio", "--scene", "chain3", "--ratios", "0.95"],
    ["resolve", "--law", "all", "--scene", "chain3"],
    ["domain", "--scene", "pool", "--theta", "pi/4"],
    ["domain", "--scene", "chain3"],
    ["domain", "--scene", "pool", "--theta", "pi/4", "--tau", "pi/6"],
], ids=lambda a: " ".join(a[:3]))
def test_plot_is_written_and_the_output_is_unchanged(argv, tmp_path, capsys):
    assert main(argv + ["--json"]) == 0
    plain = json.loads(capsys.readouterr().out)
    path = tmp_path / "fig.png"
    assert main(argv + ["--json", "--plot", str(path)]) == 0
    assert json.loads(capsys.readouterr().out) == plain  # the answer is the same, the picture is extra
    _png(path)


def test_bench_plot_is_written(tmp_path, capsys, monkeypatch):
    from impactsym import bench

    monkeypatch.setattr(bench, "MIN_TIME_QUICK", 0.0)  # 3 calls per batched timing: no rate is read here
    path = tmp_path / "bench.png"
    assert main(["bench", "--quick", "--formula", "reflect_2", "--plot", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["results"]
    _png(path)


@pytest.mark.parametrize("argv", [
    # each of these would fail (or run long) on its own: the plot path is refused first
    ["resolve", "--law", "newton", "--mass-matrix", "1,2;2,1", "--gradients", "1,0", "--velocity", "-1,0"],
    ["domain", "--scene", "pool", "--theta", "3"],
    ["bench", "--quick"],
], ids=lambda a: a[0])
def test_plot_path_checked_before_the_work(argv, tmp_path, capsys):
    bad = tmp_path / "missing" / "fig.png"
    assert main(argv + ["--plot", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "plot: cannot write" in err and "does not exist" in err
    assert "evals/s" not in err  # bench: nothing measured
    assert not bad.parent.exists()


@pytest.mark.parametrize("plot, message", [("fig.txt", "must end with"), ("", "empty"), (".", "directory")])
def test_bad_plot_names_are_refused(plot, message, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["domain", "--scene", "chain3", "--plot", plot, "--json"]) == 2
    out = capsys.readouterr()
    assert message in out.err
    assert json.loads(out.out)["error"]["argument"] == "plot"


def test_plot_goes_through_the_one_option_check(tmp_path, capsys):
    """--plot applies to every law of resolve; an option a law does not take is still refused
    (the plot path then never matters)."""
    path = tmp_path / "fig.png"
    argv = ["resolve", "--law", "newton", "--scene", "chain3", "--reading", "cone", "--plot", str(path), "--json"]
    assert main(argv) == 2
    assert json.loads(capsys.readouterr().out)["error"]["argument"] == "reading"
    assert not path.exists()
