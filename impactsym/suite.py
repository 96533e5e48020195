"""An exported benchmark suite for engine test suites: scenes and every law's exact answer as plain
JSON (``impactsym suite export``).

Layout of an exported directory (schema :data:`SCHEMA`)::

    DIR/index.json            {"schema", "generator", "seed", "random", "laws", "budget",
                               "resolution_schema", "cases": [{"id", "file", "family", "n", "k",
                               "laws": {law: "answer" | "refused" | "skipped"}}, …]}
    DIR/cases/ID.json         {"schema", "id", "family", "spec", "bodies", "contacts",
                               "coordinates", "system": {mass_matrix, gradients, velocity, … with
                               _float twins}, "laws": {law: RESOLUTION | {"refused": reason} |
                               {"skipped": reason}}}

``RESOLUTION`` is :meth:`impactsym.resolution.Resolution.as_json` (schema
``impactsym.resolution/1``: exact strings with ``_float`` twins, ``uniqueness`` ``unique`` /
``set-valued`` / ``gap-dependent``, every outcome) without its ``system`` and ``scene`` keys,
which are given once per case. Everything is plain JSON: a test suite needs only a JSON reader.

Cases
-----
* ``builtin``: every built-in scene of ``impactsym resolve --scene`` with its default parameters
  (``pool`` at ``theta = pi/4``); ``scene-file``: a shipped scene file named in ``--scenes``
  (``impactsym scene list``), its bodies as in the file;
* random families from ``random.Random(seed)``, cycling through

  - ``mass-ratio``: a ball of mass 1 at speed 1 hits a ball of mass ``μ`` resting against a wall,
    or the chain ``[1, μ, 1]`` / ``[1, 1, μ]``; ``μ = 10^u``, ``u`` uniform in ``[-6, 6]``, as an
    exact rational of 3 significant digits;
  - ``chain``: ``2`` to ``20`` touching equal balls, the first ``s`` (1 to 3) striking at speed 1
    (Newton's cradle);
  - ``billiard``: a planar break: a cue ball at ``(1, y)`` (``y`` a small rational) hits a cluster
    of 1 to 4 touching balls built outward along rational directions (Pythagorean triples, so
    that every normal is rational), every ball of mass 1 (as on a pool table).

The same seed gives byte-identical files, whatever the number of workers (tested). Exact laws give
the same strings everywhere; the float laws (the compliant ones: ``hertz``, ``linear``, ``power``,
``hunt-crossley``, ``lzb``, integrated in float64) give the same bits on one installation, and may
differ in the last bits across platforms or SciPy/NumPy versions. They are also the slow ones on
extreme mass ratios (3 to 5 s per law at a mass ratio of 1e-6, against milliseconds for the
impact laws): ``--laws`` chooses.

Budget
------
Some laws cost exponentially in the contacts. The suite applies fixed rules (:data:`BUDGET`),
never a time limit (which would make the files depend on the machine): ``sequential`` is skipped
above 2 contacts unless every mass is the same, ``han-gilmore`` above 4 contacts (over 20,000
hypotheses at 7), and ``impulse-ratio`` is given ``coupling`` (which
sets the ratios of uncoupled contacts) up to 3 contacts; above, it is reported as not applicable
without ratios. A skipped law says so with the rule.

Examples
--------
>>> specs = random_specs(7, 3)
>>> [s["family"] for s in specs]
['mass-ratio', 'chain', 'billiard']
>>> case = solve_case(specs[1], laws=["newton"])
>>> case["laws"]["newton"]["uniqueness"], case["system"]["velocity"][:2]
('unique', ['1', ...])
"""

from __future__ import annotations

import json
import os
import random
import sys
import time
from pathlib import Path
from typing import Iterable

import sympy as sp

from .errors import ImpactInputError

__all__ = ["SCHEMA", "BUDGET", "DASK_CONFIG", "builtin_specs", "random_specs", "build_system", "solve_case",
           "case_text", "export_suite", "FAMILIES"]

#: schema of the exported index and case files
SCHEMA = "impactsym.suite/1"
#: the random families, in the order they cycle
FAMILIES = ("mass-ratio", "chain", "billiard")
#: the fixed rules that keep a case's cost bounded (module docstring)
BUDGET = {
    "sequential": "skipped above 2 contacts unless every body has the same mass (M a multiple of I): the exact "
                  "search over orderings of unequal masses can take minutes from 3 contacts on (a 3-contact "
                  "planar break with masses 1, 1/4, 5/2, 2 ran over 30 s); equal-mass chains of 20 balls take 0.2 s",
    "han-gilmore": "skipped above 4 contacts (the hypotheses grow exponentially: over 20,000 at 7 contacts)",
    "impulse-ratio": "coupling up to 3 contacts (the ratios of uncoupled contacts set to 0); above, no ratios "
                     "are given, and the law is reported as not applicable",
}

#: Dask settings of the clusters the suite starts, as Dask recommends for test clusters
#: (``distributed.utils_test.config_for_cluster_tests``): no statistical profiler (a stack sample of
#: the running task every 10 ms, for the dashboard's profile page) and the event loop's health check
#: every 500 ms rather than every 20 ms. Both are diagnostics: the tasks, their results and the files
#: are the same; the worker spends about 0.4 s less CPU on six cases (0.1 s a second in each process)
DASK_CONFIG = {"distributed.worker.profile.enabled": False, "distributed.admin.tick.interval": "500 ms"}

#: built-in scenes and the parameters the suite uses
BUILTINS = {
    "chain3": {}, "pool": {"theta": "pi/4"}, "bernoulli": {}, "two-balls-wall": {}, "three-ball-cradle": {},
    "cradle": {}, "balls-against-wall": {},
}

#: rational unit directions (Pythagorean triples) for the billiard family, all with x > 0
_DIRECTIONS = [(sp.Rational(a, c), sp.Rational(b, c)) for a, b, c in
               ((1, 0, 1), (3, 4, 5), (3, -4, 5), (4, 3, 5), (4, -3, 5), (5, 12, 13), (5, -12, 13),
                (12, 5, 13), (12, -5, 13), (8, 15, 17), (8, -15, 17), (15, 8, 17), (15, -8, 17))]


# ------------------------------------------------------------------------------------ specs
def builtin_specs(names: Iterable[str] | None = None) -> list[dict]:
    """One spec per built-in scene (default: all of them)."""
    names = list(BUILTINS) if names is None else list(names)
    shipped = _shipped_names()
    out = []
    for name in names:
        if name in BUILTINS:
            out.append({"id": f"builtin-{name}", "family": "builtin", "scene": name, "params": dict(BUILTINS[name])})
        elif name in shipped:
            out.append({"id": f"file-{name}", "family": "scene-file", "scene": name})
        else:
            raise ImpactInputError("scenes", f"unknown scene {name!r}; known: {', '.join(list(BUILTINS) + shipped)}")
    return out


def _shipped_names() -> list[str]:
    """The shipped scene files (``impactsym scene list``), when the scenes package has them."""
    try:
        from .scenes import SHIPPED_SCENES
    except ImportError:  # pragma: no cover - an installation without scene files
        return []
    return list(SHIPPED_SCENES)


def _mass_ratio(rng: random.Random) -> str:
    u = rng.uniform(-6, 6)
    exp = int(sp.floor(u))
    mant = round(10 ** (u - exp) * 100)  # 100..1000: 3 significant digits
    return str(sp.Rational(mant, 100) * sp.Rational(10) ** exp)


def random_specs(seed: int, count: int) -> list[dict]:
    """``count`` random scene specs from ``random.Random(seed)``, cycling through
    :data:`FAMILIES`; every number is an exact string, so a spec is plain JSON.

    >>> random_specs(1, 2) == random_specs(1, 2)
    True
    """
    rng = random.Random(seed)
    out = []
    for i in range(count):
        family = FAMILIES[i % len(FAMILIES)]
        sid = f"random-{seed}-{i:06d}"
        if family == "mass-ratio":
            mu = _mass_ratio(rng)
            shape = rng.choice(["wall", "heavy-middle", "heavy-last"])
            out.append({"id": sid, "family": family, "shape": shape, "mass_ratio": mu})
        elif family == "chain":
            n = rng.randint(2, 20)
            s = rng.randint(1, min(3, n - 1))
            out.append({"id": sid, "family": family, "n_balls": n, "strikers": s})
        else:
            out.append({"id": sid, "family": family, **_billiard(rng)})
    return out


def _billiard(rng: random.Random) -> dict:
    """A cluster of touching unit balls grown along rational directions, and a cue ball."""
    targets = rng.randint(1, 4)
    pos = [(sp.Integer(0), sp.Integer(0)), (sp.Integer(2), sp.Integer(0))]  # cue at 0, first target at (2, 0)
    attempts = 0
    while len(pos) < targets + 1 and attempts < 50:
        attempts += 1
        base = rng.randrange(1, len(pos))
        d = rng.choice(_DIRECTIONS)
        p = (pos[base][0] + 2 * d[0], pos[base][1] + 2 * d[1])
        if all((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 >= 4 for q in pos):  # no overlap (touching allowed)
            pos.append(p)
    vy = sp.Rational(rng.randint(-4, 4), 10)
    return {"masses": ["1"] * len(pos), "positions": [[str(x), str(y)] for x, y in pos],
            "velocities": [["1", str(vy)]] + [["0", "0"] for _ in pos[1:]]}


# ------------------------------------------------------------------------------------ systems
def _builtin_system(spec: dict):
    import argparse

    from .cli.scene_args import read_system

    fields = dict.fromkeys(("mass_matrix", "gradients", "velocity", "restitution", "theta", "tau", "masses",
                            "velocities", "n_balls", "strikers"))
    fields.update(spec["params"])
    return read_system(argparse.Namespace(scene=spec["scene"], **fields)), None


def build_system(spec: dict):
    """``(System, bodies)`` of a spec; ``bodies`` describes the balls (None for built-in scenes,
    whose ``scene`` description is in the system)."""
    from .resolution import System
    from .scenes import balls_in_plane, balls_on_line

    family = spec["family"]
    if family == "builtin":
        return _builtin_system(spec)
    if family == "scene-file":
        from .scenes import SHIPPED_SCENES, load_scene, scene_to_dict

        sc = load_scene(spec["scene"])
        desc = {"scene": spec["scene"], "file": Path(SHIPPED_SCENES[spec["scene"]]).name}
        return System.from_scene(sc, description=desc), scene_to_dict(sc).get("bodies")
    if family == "mass-ratio":
        mu = sp.Rational(spec["mass_ratio"])
        if spec["shape"] == "wall":
            bodies = {"masses": [1, mu], "radii": [1, 1], "positions": [0, 2], "velocities": [1, 0], "walls": [3]}
        else:
            m = [1, mu, 1] if spec["shape"] == "heavy-middle" else [1, 1, mu]
            bodies = {"masses": m, "radii": [1, 1, 1], "positions": [0, 2, 4], "velocities": [1, 0, 0], "walls": []}
        sc = balls_on_line(**bodies)
    elif family == "chain":
        n, s = spec["n_balls"], spec["strikers"]
        bodies = {"masses": [1] * n, "radii": [1] * n, "positions": [2 * i for i in range(n)],
                  "velocities": [1] * s + [0] * (n - s), "walls": []}
        sc = balls_on_line(**bodies)
    elif family == "billiard":
        P = [tuple(sp.Rational(c) for c in p) for p in spec["positions"]]
        V = [tuple(sp.Rational(c) for c in p) for p in spec["velocities"]]
        bodies = {"masses": [sp.Rational(m) for m in spec["masses"]], "radii": [1] * len(P), "positions": P,
                  "velocities": V}
        sc = balls_in_plane(**bodies)
    else:
        raise ImpactInputError("family", f"unknown family {family!r}")
    bodies = {"kind": "balls on a line" if family != "billiard" else "balls in the plane", **_jsonable(bodies)}
    return System.from_scene(sc, description={"scene": spec["id"], "family": family}), bodies


def _jsonable(x):
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (int, sp.Basic)):
        return str(x)
    return x


# ------------------------------------------------------------------------------------ solving
def _equal_masses(system) -> bool:
    M = system.M
    return all(M[i, j] == (M[0, 0] if i == j else 0) for i in range(M.shape[0]) for j in range(M.shape[1]))


def _law_options(law: str, system):
    """The suite's options for ``law`` on ``system``, or the reason it is skipped (:data:`BUDGET`)."""
    k = system.k
    if law == "sequential" and k > 2 and not _equal_masses(system):
        return None, f"skipped: {BUDGET['sequential']}"
    if law == "han-gilmore" and k > 4:
        return None, f"skipped: {BUDGET['han-gilmore']}"
    if law == "impulse-ratio" and 1 < k <= 3:
        return {"coupling": True}, None
    return {}, None


def solve_case(spec: dict, laws: Iterable[str] | None = None) -> dict:
    """The exported case of one spec: system, bodies and every law's answer (module docstring)."""
    from .lawbook import LAWS, resolve_all

    system, bodies = build_system(spec)
    names = list(laws) if laws is not None else list(LAWS)
    skips, options = {}, {}
    for name in names:
        opts, skipped = _law_options(name, system)
        if skipped:
            skips[name] = skipped
        else:
            options[name] = opts
    # one call for every law resolved (in the order of ``names``): the system's content is keyed
    # for its memo once, not once per law
    resolved = resolve_all(system, laws=list(options), options=options) if options else {}
    answers = {}
    for name in names:
        if name in skips:
            answers[name] = {"skipped": skips[name]}
            continue
        r, opts = resolved[name], options[name]
        if isinstance(r, str):
            answers[name] = {"refused": r}
        else:
            j = r._as_json(False)  # as_json() without "system" and "scene" (given once per case)
            j["options"] = _jsonable(opts)
            answers[name] = j
    return {"schema": SCHEMA, "id": spec["id"], "family": spec["family"], "spec": spec, "bodies": bodies,
            "contacts": list(system.contacts), "coordinates": list(system.coordinates),
            "system": system.as_json(), "laws": answers}


def case_text(spec: dict, laws: Iterable[str] | None = None) -> tuple[str, str, dict]:
    """``(id, file text, index entry)`` of one case: what a worker returns (deterministic text)."""
    from .cli.common import dumps_strict

    case = solve_case(spec, laws)
    entry = {"id": case["id"], "file": f"cases/{case['id']}.json", "family": case["family"],
             "n": len(case["system"]["velocity"]), "k": len(case["contacts"]),
             "laws": {name: ("skipped" if "skipped" in a else "refused" if "refused" in a else "answer")
                      for name, a in case["laws"].items()}}
    return case["id"], dumps_strict(case) + "\n", entry


# ------------------------------------------------------------------------------------ export
class _Progress:
    """A one-line progress bar on stderr (nothing on stdout)."""

    def __init__(self, total: int, enabled: bool, stream=None):
        self.total, self.enabled, self.done = total, enabled, 0
        self.stream = stream or sys.stderr
        self.start = time.monotonic()
        self.last = 0.0

    def step(self):
        self.done += 1
        now = time.monotonic()
        if self.enabled and (now - self.last > 0.2 or self.done == self.total):
            self.last = now
            width = 30
            filled = int(width * self.done / max(self.total, 1))
            rate = self.done / max(now - self.start, 1e-9)
            self.stream.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} cases, "
                              f"{rate:.1f}/s")
            if self.done == self.total:
                self.stream.write("\n")
            self.stream.flush()


def _write(directory: Path, cid: str, text: str) -> None:
    (directory / "cases" / f"{cid}.json").write_text(text, encoding="utf-8")


def export_suite(directory, specs: list[dict], *, laws: Iterable[str] | None = None, workers: int | None = None,
                 scheduler: str | None = None, progress: bool = False, seed=None, random_count: int = 0) -> dict:
    """Write the suite of ``specs`` to ``directory`` (module docstring); return the index.

    ``workers=0`` computes in this process; otherwise a Dask ``LocalCluster`` of ``workers``
    processes (one thread each) is started, or the cluster at ``scheduler`` (an address such as
    ``tcp://127.0.0.1:8786``) is used. The files do not depend on how they were computed.
    """
    from .lawbook import LAWS, get_law

    names = list(laws) if laws is not None else list(LAWS)
    for n in names:
        get_law(n)
    directory = Path(directory)
    (directory / "cases").mkdir(parents=True, exist_ok=True)
    ids = [s["id"] for s in specs]
    if len(set(ids)) != len(ids):
        raise ImpactInputError("scenes", "the cases' ids are not unique")
    entries: dict[str, dict] = {}
    bar = _Progress(len(specs), progress)
    if workers == 0 and scheduler is None:
        for spec in specs:
            cid, text, entry = case_text(spec, names)
            _write(directory, cid, text)
            entries[cid] = entry
            bar.step()
    else:
        _export_dask(directory, specs, names, workers, scheduler, bar, entries)
    index = {"schema": SCHEMA, "generator": f"impactsym {_version()}", "resolution_schema": _resolution_schema(),
             "seed": seed, "random": random_count, "laws": names, "budget": BUDGET,
             "layout": "cases/ID.json: system, bodies and every law's answer (Resolution JSON without its "
                       "'system' and 'scene', given once per case)",
             "cases": [entries[i] for i in ids]}
    from .cli.common import dumps_strict

    _remove_stale(directory, set(ids))
    (directory / "index.json").write_text(dumps_strict(index, indent=1) + "\n", encoding="utf-8")
    return index


def _export_dask(directory, specs, names, workers, scheduler, bar, entries) -> None:
    try:
        import dask
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise ImpactInputError("workers", "the Dask path needs dask[distributed] (pip install 'impactsym[sweeps]'); "
                               "--workers 0 computes in this process") from None
    cluster = None
    if scheduler is None:
        n = workers if workers is not None else (os.cpu_count() or 1)
        with dask.config.set(DASK_CONFIG):  # read when the scheduler, nannies and workers are made
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0")
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise ImpactInputError("scheduler", f"cannot connect to {scheduler!r}: {exc}") from None
    try:
        futures = client.map(case_text, specs, laws=names, pure=False)
        for fut in as_completed(futures):
            cid, text, entry = fut.result()
            _write(directory, cid, text)
            entries[cid] = entry
            bar.step()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _remove_stale(directory: Path, ids: set) -> None:
    """Remove the case files of an earlier export (listed in its index) that are not in this one."""
    old = directory / "index.json"
    if not old.exists():
        return
    try:
        previous = json.loads(old.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return
    if not isinstance(previous, dict) or previous.get("schema") != SCHEMA:
        return
    for case in previous.get("cases", []):
        if case.get("id") not in ids:
            stale = directory / "cases" / f"{case.get('id')}.json"
            if stale.is_file():
                stale.unlink()


def _version() -> str:
    from . import __version__

    return __version__


def _resolution_schema() -> str:
    from .resolution import SCHEMA as RS

    return RS


def read_index(directory) -> dict:
    """The index of an exported suite (plain ``json``)."""
    return json.loads((Path(directory) / "index.json").read_text(encoding="utf-8"))
