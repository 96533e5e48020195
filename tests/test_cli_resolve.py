"""CLI contract of ``impactsym resolve`` for the impulse-ratio and classical laws: JSON keys with
``_float`` twins, the sec. 3.2 numbers, exit 2 (no traceback) for every bad input and for a
result outside the law's domain unless --allow-invalid."""

from __future__ import annotations

import json

import pytest

from impactsym.cli import main
from probe_server import run_python

CHAIN = ["--mass-matrix", "1,0,0;0,1,0;0,0,1", "--gradients", "-1,1,0;0,-1,1", "--velocity", "1,0,0"]


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def js(capsys, *argv):
    code, out, err = run(capsys, "resolve", *argv, "--json")
    assert code == 0, err
    assert err == ""
    return json.loads(out)


def test_impulse_ratio_json(capsys):
    d = js(capsys, "--law", "impulse-ratio", *CHAIN, "--restitution", "1", "--ratios", "1/2")
    assert d["impulses"] == ["4/3", "2/3"] and d["velocity"] == ["-1/3", "2/3", "2/3"]
    assert d["impulses_float"] == [4 / 3, 2 / 3] and d["velocity_float"][0] == -1 / 3
    dd = d["details"]
    assert dd["delta"] == "1" and dd["delta_float"] == 1.0 and dd["delta_normalized"] == "1"
    assert d["valid"] is True and d["violations"] == []


def test_impulse_ratio_paper_sec33_alpha_095(capsys):
    d = js(capsys, "--law", "impulse-ratio", "--scene", "chain3", "--ratios", "0.95")
    assert d["velocity"] == ["-19/381", "20/381", "380/381"]  # the paper prints [-0.05, 0.05, 0.99]
    assert [round(x, 2) for x in d["velocity_float"]] == [-0.05, 0.05, 1.0]


def test_classical_laws_sec32(capsys):
    for law in ("newton", "poisson", "energetic"):
        d = js(capsys, "--law", law, "--scene", "chain3")
        assert d["velocity"] == ["-1/3", "2/3", "2/3"] and d["impulses"] == ["4/3", "2/3"], law
        assert d["kinetic_energy_before"] == d["kinetic_energy_after"] == "1/2"
    d = js(capsys, "--law", "han-gilmore", "--scene", "chain3")
    assert [o["velocity"] for o in d["outcomes"]] == [["-1/3", "2/3", "2/3"], ["0", "0", "1"]]
    assert d["outcomes"][1]["details"]["sequences"] == [[[0], [1]]]  # 0-based contacts, stage by stage
    assert d["outcomes"][1]["order"] == [[0], [1]] and d["uniqueness"] == "set-valued"


def test_pool_coupling_reports_forced_zero(capsys):
    d = js(capsys, "--law", "impulse-ratio", "--scene", "pool", "--theta", "pi/2", "--ratios", "1/2", "--coupling")
    dd = d["details"]
    assert dd["ratios"] == ["1", "0"] and d["impulses"][1] == "0"
    assert dd["coupling"][0]["ratio"] == "alpha_12" and dd["coupling"][0]["cos_kinetic_angle"] == "0"
    assert dd["coupling_decision"]["coupled"] == {"1-2": False}
    d = js(capsys, "--law", "impulse-ratio", "--scene", "pool", "--theta", "pi/3", "--ratios", "1/2", "--coupling")
    assert d["details"]["coupling_decision"]["cos_kinetic_angles"] == {"1-2": "-1/4"}  # eq. 42: -cos(pi/3)/2
    d = js(capsys, "--law", "impulse-ratio", "--scene", "pool", "--theta", "pi/4", "--ratios", "1/2",
           "--restitution", "9/10", "--coupling")
    assert d["details"]["ratios"] == ["1", "1/2"] and "coupling" not in d["details"]


def test_domain_violation_exit_2_and_allow_invalid(capsys):
    code, out, err = run(capsys, "resolve", "--law", "impulse-ratio", *CHAIN, "--ratios", "1/4", "--json")
    assert code == 2 and json.loads(out)["error"]["message"] in err  # --json: the error object on stdout
    assert "penetration: contact 2" in err and "Traceback" not in err
    d = js(capsys, "--law", "impulse-ratio", *CHAIN, "--ratios", "1/4", "--allow-invalid")
    assert d["valid"] is False and d["violations"][0]["condition"] == "penetration"
    d = js(capsys, "--law", "impulse-ratio", *CHAIN, "--ratios", "1", "--restitution", "1/10", "--allow-invalid")
    assert d["impulses"] is None and d["impulses_float"] is None and d["details"]["real_solution"] is False


def test_text_output(capsys):
    code, out, _ = run(capsys, "resolve", "--law", "impulse-ratio", "--scene", "chain3", "--ratios", "1/2")
    assert code == 0 and "v+ = [-1/3, 2/3, 2/3]" in out and "valid: True" in out
    code, out, _ = run(capsys, "resolve", "--law", "han-gilmore", "--scene", "chain3")
    assert code == 0 and "(order {1-2} > {2-3})" in out


@pytest.mark.parametrize(
    "args, needle",
    [
        (["--law", "nope", *CHAIN], "unknown law"),
        (["--law", "impulse-ratio"], "mass_matrix: is required unless --scene"),
        (["--law", "impulse-ratio", "--mass-matrix", "1,0;0,1", "--gradients", "1,0"], "velocity: is required"),
        (["--law", "impulse-ratio", *CHAIN], "expected 1 ratio"),
        (["--law", "impulse-ratio", *CHAIN, "--ratios", "1,2"], "expected 1 ratio"),
        (["--law", "impulse-ratio", *CHAIN, "--ratios", "nan"], "finite"),
        (["--law", "impulse-ratio", *CHAIN, "--ratios", "x"], "cannot read"),
        (["--law", "impulse-ratio", *CHAIN, "--ratios", "1/2", "--restitution", "3/2"], "[0, 1]"),
        (["--law", "impulse-ratio", *CHAIN, "--ratios", "1/2", "--restitution", "-1/2"], "[0, 1]"),
        (["--law", "impulse-ratio", *CHAIN, "--ratios", "1/2", "--restitution", "inf"], "finite"),
        (["--law", "newton", "--mass-matrix", "1,2;2,1", "--gradients", "1,0", "--velocity", "-1,0"], "not positive definite"),
        (["--law", "newton", "--mass-matrix", "1,2;3,1", "--gradients", "1,0", "--velocity", "-1,0"], "not symmetric"),
        (["--law", "newton", "--mass-matrix", "1,0;0,1", "--gradients", "0,0", "--velocity", "-1,0"], "zero covector"),
        (["--law", "newton", "--mass-matrix", "1,0;0,1", "--gradients", "1,0,0", "--velocity", "-1,0"], "columns"),
        (["--law", "newton", "--mass-matrix", "1,0;0,1", "--gradients", "1,0", "--velocity", "-1"], "velocity: has length 1"),
        (["--law", "newton", "--mass-matrix", "1,0;0", "--gradients", "1,0", "--velocity", "-1,0"], "different lengths"),
        (["--law", "newton", *CHAIN, "--ratios", "1/2"], "--ratios does not apply"),
        (["--law", "newton", *CHAIN, "--coupling"], "--coupling applies to --law impulse-ratio"),
        (["--law", "newton", *CHAIN, "--variant", "glocker-pfeiffer"], "--variant applies to --law poisson"),
        (["--law", "poisson", *CHAIN, "--variant", "x"], "variant"),
        (["--law", "poisson", *CHAIN, "--restitution", "1,1,1"], "expected one per contact (2)"),
        (["--law", "han-gilmore", *CHAIN, "--allow-invalid"], "does not apply"),
        (["--law", "energetic", "--mass-matrix", "1,0;0,1", "--gradients", "1,0;1,0", "--velocity", "-1,0"], "not unique"),
        (["--law", "impulse-ratio", "--scene", "nope"], "unknown scene"),
        (["--law", "impulse-ratio", "--scene", "pool"], "theta: is required"),
        (["--law", "impulse-ratio", "--scene", "pool", "--theta", "pi"], "must lie in [0, 2*pi/3]"),
        (["--law", "impulse-ratio", "--scene", "chain3", "--theta", "pi/4"], "--theta does not apply"),
        (["--law", "impulse-ratio", "--scene", "chain3", "--masses", "1,1"], "three masses"),
        (["--law", "impulse-ratio", "--scene", "chain3", "--masses", "1,0,1"], "masses: must be positive"),
        (["--law", "impulse-ratio", "--scene", "chain3", *CHAIN], "cannot be combined with --scene"),
        (["--law", "impulse-ratio", *CHAIN, "--tau", "0"], "--tau applies only with --scene"),
    ],
)
def test_bad_input_exit_2(capsys, args, needle):
    code, out, err = run(capsys, "resolve", *args, "--json")
    assert code == 2, err
    assert json.loads(out)["error"]["message"] in err and needle in err and "Traceback" not in err


def test_subprocess_contract():
    proc = run_python(["-m", "impactsym", "resolve", "--law", "newton", "--scene", "chain3", "--json"])
    assert proc.returncode == 0 and json.loads(proc.stdout)["impulses"] == ["4/3", "2/3"]
    proc = run_python(["-m", "impactsym", "resolve", "--law", "impulse-ratio", "--scene", "chain3", "--ratios", "1/4",
                       "--json"])
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert json.loads(proc.stdout)["error"]["message"] in proc.stderr  # one JSON object on stdout
