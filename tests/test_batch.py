"""``impactsym batch`` and :func:`impactsym.oracle.run_many`: JSON Lines in and out, each answer the
subcommand's own ``--json`` object, a bad line answered with an error and never stopping the batch."""

from __future__ import annotations

import json

from impactsym.cli import main
from impactsym.oracle import iter_answers, request_argv, run_many
from probe_server import run_python


def cli_json(capsys, *argv):
    code = main(list(argv) + ["--json"])
    out, _ = capsys.readouterr()
    return code, json.loads(out)


def test_both_forms_answer_like_the_cli(capsys):
    answers = run_many([
        {"id": 1, "argv": ["resolve", "--law", "newton", "--scene", "chain3"]},
        {"id": 2, "command": "resolve", "args": {"law": "sequential", "scene": "cradle", "n_balls": 4}},
        {"id": 3, "command": "check", "args": {"scene": "chain3", "observed": "1/2,1/2,0"}},
    ])
    assert [a["id"] for a in answers] == [1, 2, 3]
    for a, argv in zip(answers, (["resolve", "--law", "newton", "--scene", "chain3"],
                                 ["resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "4"],
                                 ["check", "--scene", "chain3", "--observed", "1/2,1/2,0"])):
        code, expected = cli_json(capsys, *argv)
        assert a["exit_status"] == code and a["result"] == expected, argv
    assert answers[2]["exit_status"] == 3  # check that matched no law: a finding, still a result


def test_bad_requests_never_stop_the_batch():
    lines = [
        '{"argv": ["resolve", "--law", "newton", "--scene", "chain3"]}',
        "not json",
        "",
        '{"argv": ["resolve", "--law", "nope", "--scene", "chain3"], "id": "x"}',
        '{"argv": ["resolve", "--law", "newton"]}',
        '{"argv": ["batch"]}',
        '{"command": "resolve", "argv": ["resolve"]}',
        '{"colour": "red"}',
        '[1, 2]',
        '{"argv": ["resolve", "--law", "newton", "--scene", "chain3", "--no-such-option"]}',
        '{"argv": ["resolve", "--law", "newton", "--scene", "chain3"], "id": 9}',
    ]
    answers = list(iter_answers(lines))
    assert [a["line"] for a in answers] == [1, 2, 4, 5, 6, 7, 8, 9, 10, 11]
    assert [a["exit_status"] for a in answers] == [0, 2, 2, 2, 2, 2, 2, 2, 2, 0]
    args = [a["error"]["argument"] for a in answers if "error" in a]
    assert args == ["input", "law", "mass_matrix", "command", "request", "request", "request", "no_such_option"]
    assert answers[2]["id"] == "x" and answers[-1]["id"] == 9
    assert answers[-1]["result"]["velocity"] == ["-1/3", "2/3", "2/3"]


def test_request_argv_forms():
    assert request_argv({"command": "check", "args": {"scene": "chain3", "observed": "-1,0,0", "laws": ["newton"]}}) \
        == ["check", "--scene=chain3", "--observed=-1,0,0", "--laws=newton", "--json"]
    assert request_argv({"argv": ["resolve", "--json"]}) == ["resolve", "--json"]


def test_cli_files(tmp_path, capsys):
    src = tmp_path / "in.jsonl"
    src.write_text(json.dumps({"argv": ["resolve", "--law", "poisson", "--scene", "two-balls-wall"]}) + "\nnope\n")
    dst = tmp_path / "out.jsonl"
    code = main(["batch", "--input", str(src), "--output", str(dst)])
    out, err = capsys.readouterr()
    assert code == 0 and "answered 2 request(s)" in out
    got = [json.loads(x) for x in dst.read_text().splitlines()]
    assert [a["exit_status"] for a in got] == [0, 2] and got[0]["result"]["law"] == "poisson"
    code = main(["batch", "--input", str(tmp_path / "missing.jsonl")])
    assert code == 2 and "input" in capsys.readouterr().err


def test_stdout_is_pure_json_lines():
    reqs = "".join(json.dumps({"id": i, "argv": ["resolve", "--law", "newton", "--scene", "chain3"]}) + "\n"
                   for i in range(3)) + "garbage\n"
    p = run_python(["-m", "impactsym", "batch"], input=reqs)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 4 and [json.loads(x)["exit_status"] for x in lines] == [0, 0, 0, 2]
    assert "answered 4 request(s)" in p.stderr
