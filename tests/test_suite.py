"""``impactsym suite export``: a reproducible plain-JSON suite (byte-identical for one seed, however
computed), the Dask path on a small local cluster, and a reader that needs only ``json``."""

from __future__ import annotations

import json
import math
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

from impactsym.cli import main
from impactsym.suite import FAMILIES, SCHEMA, export_suite, random_specs


def tree(d: Path) -> dict:
    return {str(p.relative_to(d)): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def test_random_families_from_the_seed():
    specs = random_specs(11, 90)
    assert specs == random_specs(11, 90) and specs != random_specs(12, 90)
    assert [s["family"] for s in specs[:6]] == list(FAMILIES) * 2
    ratios = [Fraction(s["mass_ratio"]) for s in specs if s["family"] == "mass-ratio"]
    assert all(Fraction(1, 10**6) <= r <= 10**6 for r in ratios)
    assert min(ratios) < 1 < max(ratios)
    lengths = [s["n_balls"] for s in specs if s["family"] == "chain"]
    assert all(2 <= n <= 20 for n in lengths) and len(set(lengths)) > 5


@pytest.fixture(scope="module")
def seed5(tmp_path_factory):
    """The in-process export of ``random_specs(5, 6)``: the other seed of the byte-identity test, and
    the reference the Dask export is compared with (computed once for the module)."""
    d = tmp_path_factory.mktemp("seed5")
    export_suite(d, random_specs(5, 6), workers=0, seed=5, random_count=6)
    return d


def test_export_is_byte_identical_for_one_seed(tmp_path, seed5):
    specs = random_specs(4, 6)
    a = export_suite(tmp_path / "a", specs, workers=0, seed=4, random_count=6)
    export_suite(tmp_path / "b", random_specs(4, 6), workers=0, seed=4, random_count=6)
    assert tree(tmp_path / "a") == tree(tmp_path / "b")
    assert a["schema"] == SCHEMA and len(a["cases"]) == 6
    assert tree(tmp_path / "a") != tree(seed5)


def test_dask_local_cluster_matches_in_process(tmp_path, seed5):
    """A real ``LocalCluster`` (worker processes: the cases are pickled to another interpreter and
    the texts back) writes the same files as the in-process export. One worker process: each
    worker pays its own interpreter, Dask and SymPy/SciPy start-up (about 1.4 s of CPU), and the
    number of workers does not enter the files (the index is written in the specs' order). The
    cluster has the suite's own Dask settings (``DASK_CONFIG``: no profiler, a slower health check)."""
    import dask
    from dask.distributed import LocalCluster  # in the 'dev' extra (and 'sweeps'): never skipped

    from impactsym.suite import DASK_CONFIG

    with dask.config.set(DASK_CONFIG), \
            LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        export_suite(tmp_path / "dask", random_specs(5, 6), scheduler=cluster.scheduler_address, progress=True,
                     seed=5, random_count=6)
    assert tree(seed5) == tree(tmp_path / "dask")


def _rational_matrix(rows):
    return [[Fraction(x) for x in r] for r in rows]


def test_read_back_with_json_alone(tmp_path, capsys):
    code = main(["suite", "export", str(tmp_path / "s"), "--scenes", "chain3,two-balls-wall,newton-cradle-5-strikers-2",
                 "--random", "6",
                 "--seed", "3", "--workers", "0", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 0 and summary["cases"] == 9
    # a consumer with nothing but json (and fractions for the exact strings)
    index = json.loads((tmp_path / "s" / "index.json").read_text())
    assert index["schema"] == "impactsym.suite/1" and index["resolution_schema"] == "impactsym.resolution/1"
    checked = 0
    for entry in index["cases"]:
        case = json.loads((tmp_path / "s" / entry["file"]).read_text())
        M = _rational_matrix(case["system"]["mass_matrix"])
        H = _rational_matrix(case["system"]["gradients"])
        v = [Fraction(x) for x in case["system"]["velocity"]]
        newton = case["laws"]["newton"]
        vp = [Fraction(x) for x in newton["velocity"]]
        p = [Fraction(x) for x in newton["impulses"]]
        n, k = len(v), len(H)
        # momentum balance M (v+ - v-) = H^T p, and no penetration H v+ >= 0, from the JSON alone
        for i in range(n):
            assert sum(M[i][j] * (vp[j] - v[j]) for j in range(n)) == sum(H[c][i] * p[c] for c in range(k))
        assert all(sum(H[c][j] * vp[j] for j in range(n)) >= 0 for c in range(k))
        assert newton["uniqueness"] in ("unique", "set-valued", "gap-dependent")
        # the float twins are the exact values rounded (to within one ulp: SymPy's 17-digit evalf, then float)
        assert all(math.isclose(f, float(x), rel_tol=2.0**-52, abs_tol=0.0) for f, x in zip(newton["velocity_float"], vp))
        # and against the library: the same system resolved again gives the same exact answer
        from impactsym.lawbook import resolve
        from impactsym.resolution import System

        sysm = System.from_matrices(sp.Matrix(M), sp.Matrix(H), sp.Matrix(v))
        again = resolve("newton", sysm)
        assert [str(x) for x in again.velocity] == newton["velocity"]
        seq = case["laws"]["sequential"]
        if "skipped" not in seq and "refused" not in seq:
            r = resolve("sequential", sysm)
            assert [[str(x) for x in o.velocity] for o in r.outcomes] == [o["velocity"] for o in seq["outcomes"]]
        checked += 1
    assert checked == 9
    shipped = json.loads((tmp_path / "s" / "cases" / "file-newton-cradle-5-strikers-2.json").read_text())
    assert shipped["family"] == "scene-file" and len(shipped["bodies"]) == 5
    assert shipped["system"]["velocity"] == ["1", "1", "0", "0", "0"]


def test_cli_refusals(tmp_path, capsys):
    for argv, argument in ((["--seed", "3"], "seed"), (["--scenes", "nope"], "scenes"),
                           (["--scenes", "none"], "scenes"), (["--laws", "nope"], "law"),
                           (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "workers"),
                           (["--random", "-1"], "random")):
        code = main(["suite", "export", str(tmp_path / "x"), *argv, "--json"])
        out, err = capsys.readouterr()
        assert code == 2 and json.loads(out)["error"]["argument"] == argument, argv
        assert "Traceback" not in err
