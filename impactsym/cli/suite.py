"""``impactsym suite export DIR``: write a benchmark suite for engine test suites as plain JSON
(:mod:`impactsym.suite`): the built-in scenes and ``--random N`` scenes of random families from
``--seed``, each with its system and every law's exact answer.

The cases are computed on Dask: a ``LocalCluster`` of ``--workers`` processes by default (the
number of CPUs when not given), or an existing cluster with ``--scheduler ADDRESS``;
``--workers 0`` computes in this process without Dask. The files are byte-identical for the same
``--seed``, ``--random``, ``--scenes`` and ``--laws``, however they were computed. ``--progress``
draws a progress bar on stderr. Prints a summary (one JSON object with ``--json``).
"""

from __future__ import annotations

import time

from ..errors import ImpactInputError
from .common import add_json_flag


def register(sub) -> None:
    p = sub.add_parser("suite", help="export a benchmark suite (scenes and every law's exact answer) as plain JSON",
                       description="Benchmark suites for physics-engine test suites.")
    actions = p.add_subparsers(dest="action", metavar="ACTION")
    actions.required = True
    e = actions.add_parser("export", help="write DIR/index.json and DIR/cases/*.json",
                           description="Write DIR/index.json and one DIR/cases/ID.json per scene: the system "
                                       "(bodies, M, H, v) and every law's exact answer (the resolution JSON). "
                                       "The same --seed gives byte-identical files.")
    e.add_argument("directory", metavar="DIR", help="output directory (created if missing)")
    e.add_argument("--scenes", metavar="S", help="comma-separated built-in scenes (default: all; 'none' for none)")
    e.add_argument("--laws", metavar="L", help="comma-separated laws (default: every law)")
    e.add_argument("--seed", metavar="S", help="seed of the random families (default 0)")
    e.add_argument("--random", metavar="N", help="number of random scenes (default 0)")
    e.add_argument("--workers", metavar="W", help="Dask LocalCluster processes (default: CPUs; 0: in this process)")
    e.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://127.0.0.1:8786")
    e.add_argument("--progress", action="store_true", help="a progress bar on stderr")
    add_json_flag(e)
    e.set_defaults(func=run)


def run(args) -> dict:
    from ..lawbook import LAWS, get_law
    from ..suite import BUILTINS, builtin_specs, export_suite, random_specs
    from .common import writable_dir
    from .scene_args import int_option

    scenes = list(BUILTINS) if args.scenes is None else \
        [] if args.scenes.strip() == "none" else [x.strip() for x in args.scenes.split(",") if x.strip()]
    specs = builtin_specs(scenes)
    laws = list(LAWS)
    if args.laws is not None:
        names = [x.strip() for x in args.laws.split(",") if x.strip()]
        if not names:
            raise ImpactInputError("laws", "is empty; give law names separated by commas")
        for n in names:
            get_law(n)
        laws = [n for n in LAWS if n in names]
    seed = int_option(args.seed, "seed", 0) if args.seed is not None else 0
    count = int_option(args.random, "random", 0, 10**6) if args.random is not None else 0
    if args.seed is not None and count == 0:
        raise ImpactInputError("seed", "--seed applies only with --random N (N > 0)")
    specs += random_specs(seed, count)
    if not specs:
        raise ImpactInputError("scenes", "no case to export (--scenes none and no --random)")
    if args.scheduler is not None and args.workers is not None:
        raise ImpactInputError("workers", "--workers does not apply with --scheduler (the cluster has its workers)")
    workers = int_option(args.workers, "workers", 0, 256) if args.workers is not None else None
    writable_dir(args.directory, "directory")
    t0 = time.perf_counter()
    index = export_suite(args.directory, specs, laws=laws, workers=workers, scheduler=args.scheduler,
                         progress=args.progress, seed=seed if count else None, random_count=count)
    seconds = time.perf_counter() - t0
    counts: dict = {}
    for c in index["cases"]:
        for law, status in c["laws"].items():
            counts.setdefault(law, {}).setdefault(status, 0)
            counts[law][status] += 1
    return {"schema": index["schema"], "directory": str(args.directory), "index": f"{args.directory}/index.json",
            "cases": len(index["cases"]), "laws": counts, "seconds": round(seconds, 3),
            "workers": "in-process" if workers == 0 and args.scheduler is None else
            (args.scheduler or f"LocalCluster({workers if workers is not None else 'CPUs'})")}


def render(result: dict) -> str:
    lines = [f"wrote {result['cases']} case(s) to {result['directory']} (index {result['index']}) "
             f"in {result['seconds']} s on {result['workers']}"]
    for law, c in result["laws"].items():
        lines.append(f"  {law:<14} " + ", ".join(f"{k} {v}" for k, v in sorted(c.items())))
    return "\n".join(lines)
