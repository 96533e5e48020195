"""CLI contract for the foundation subcommands: one JSON object with --json, exit 2 and no
traceback for bad input (CONVENTIONS.md)."""

import json

import pytest

from impactsym.cli import main
from probe_server import run_python


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_reflect_json_exact_and_float_twins(capsys):
    code, out, err = run(capsys, "reflect", "--mass-matrix", "1.1,0;0,1", "--gradient", "-1,1",
                         "--velocity", "1,0", "--json")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert data["matrix"] == [["1/21", "20/21"], ["22/21", "-1/21"]]
    assert data["velocity"] == ["1/21", "22/21"]
    assert data["matrix_float"][1][0] == 22 / 21 and data["velocity_float"] == [1 / 21, 22 / 21]


def test_reflect_restitution_and_algebraic_entries(capsys):
    code, out, _ = run(capsys, "reflect", "--mass-matrix", "2,0;0,1", "--gradient", "sqrt(2),0",
                       "--restitution", "1/2", "--json")
    assert code == 0
    assert json.loads(out)["matrix"] == [["-1/2", "0"], ["0", "1"]]


def test_reflect_readable_output(capsys):
    code, out, _ = run(capsys, "reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0")
    assert code == 0 and "G_u(e) with e = 1" in out and "-1" in out


@pytest.mark.parametrize(
    "args, needle",
    [
        (["--mass-matrix", "1,0,0;0,1,0", "--gradient", "1,0"], "square"),
        (["--mass-matrix", "1,2;3,1", "--gradient", "1,0"], "not symmetric"),
        (["--mass-matrix", "1,2;2,1", "--gradient", "1,0"], "not positive definite"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "0,0"], "zero covector"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "1,0,0"], "has length 3, expected 2"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--velocity", "1"], "velocity: has length 1"),
        (["--mass-matrix", "1,nan;nan,1", "--gradient", "1,0"], "finite"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "inf,0"], "finite"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--restitution", "11/10"], "[0, 1]"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--restitution", "-1/2"], "[0, 1]"),
        (["--mass-matrix", "1,0;0", "--gradient", "1,0"], "rows have different lengths"),
        (["--mass-matrix", "1,0;0,1", "--gradient", "a,0"], "cannot read"),
    ],
)
def test_reflect_bad_input_exit_2(capsys, args, needle):
    code, out, err = run(capsys, "reflect", *args, "--json")
    assert code == 2 and json.loads(out)["error"]["message"] in err  # --json: the error object on stdout
    assert needle in err and "Traceback" not in err


def test_prove_json_shape(capsys):
    code, out, _ = run(capsys, "prove", "--dimension", "2", "--dimension", "n", "--json")
    assert code == 0
    data = json.loads(out)
    names = {(p["name"], p["dimension"]) for p in data["properties"]}
    for nm in ("G^2=I", "G^TMG=M", "det(G)=-1"):
        assert (nm, 2) in names and (nm, "n") in names
    assert all(p["proven"] is True and isinstance(p["seconds"], float) and p["method"] for p in data["properties"])


def test_prove_bad_dimension_exit_2(capsys):
    code, out, err = run(capsys, "prove", "--dimension", "seven")
    assert code == 2 and "dimension" in err


def test_unknown_law_exit_2(capsys):
    code, _, err = run(capsys, "resolve", "--law", "no-such-law")
    assert code == 2 and "unknown law" in err


def test_console_script_and_argparse_errors_exit_2():
    """Through a real process: the installed console entry point, and argparse's own exit 2."""
    proc = run_python(["-m", "impactsym", "reflect", "--mass-matrix", "1,2;2,1", "--gradient", "-1,1"])
    assert proc.returncode == 2 and "not positive definite" in proc.stderr and "Traceback" not in proc.stderr
    proc = run_python(["-m", "impactsym", "reflect"])
    assert proc.returncode == 2 and "required" in proc.stderr
