"""``impactsym domain``: the CLI contract (one JSON object, exit codes) and its content."""

import json

import pytest

from impactsym.cli import main
from probe_server import run_python


def _run(*args):
    return run_python(["-m", "impactsym", "domain", *args])  # a real process, on this checkout


def test_json_pool_pi_over_4(capsys):
    assert main(["domain", "--scene", "pool", "--theta", "pi/4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    names = [b["name"] for b in out["boundaries"]]
    assert names == ["alpha_min", "g", "h", "e_max"]
    assert all(set(b) == {"name", "expression", "condition"} for b in out["boundaries"])
    assert out["region"]["alpha"] == ["sqrt(2)/4", "1"] and out["region"]["e"] == ["3/7", "1"]
    assert out["region"]["e_float"] == [3 / 7, 1.0] and out["region"]["empty"] is False
    assert out["boundaries"][1]["expression"].startswith("e = ")


def test_json_chain3_has_eq19(capsys):
    assert main(["domain", "--scene", "chain3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["region"]["alpha"] == ["1/2", "1"] and out["region"]["e"] == ["1/3", "1"]
    assert any("sqrt(6*e - 2)" in s for s in out["inequalities"])


def test_text_output(capsys):
    assert main(["domain", "--scene", "pool", "--theta", "2*pi/3"]) == 0
    text = capsys.readouterr().out
    assert "g3" in text and "e     in [5/9, 1]" in text


@pytest.mark.parametrize("args,needle", [
    (["--scene", "pool", "--theta", "3"], "theta"),
    (["--scene", "pool", "--theta", "-1/2"], "theta"),
    (["--scene", "billiards"], "scene"),
    (["--scene", "chain3", "--theta", "pi/4"], "theta"),
    (["--scene", "pool", "--theta", "inf"], "theta"),
])
def test_bad_input_exits_2_without_traceback(capsys, args, needle):
    """In this process (``main``): an unexpected exception would escape ``main`` and fail the test,
    so exit status 2 with the message is the whole contract here; the process test below checks
    the same through a real interpreter."""
    code = main(["domain", *args, "--json"])
    out, err = capsys.readouterr()
    assert code == 2 and json.loads(out)["error"]["message"] in err  # the --json error object
    assert out.count("\n") == 1 and needle in err and "Traceback" not in err


def test_bad_input_exits_2_without_traceback_in_a_real_process():
    r = _run("--scene", "pool", "--theta", "3", "--json")
    assert r.returncode == 2 and json.loads(r.stdout)["error"]["message"] in r.stderr  # the --json error object
    assert "theta" in r.stderr and "Traceback" not in r.stderr
