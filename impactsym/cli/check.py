"""``impactsym check``: compare a post-impact velocity observed elsewhere (a physics engine, an
experiment) with every law.

The system is given as for ``impactsym resolve``: explicit matrices (``--mass-matrix``,
``--gradients``, ``--velocity``) or a built-in ``--scene`` with its parameters, and
``--restitution``. ``--observed "v1,v2,…"`` is the observed post-impact velocity in the system's
coordinates. For every law that applies (:func:`impactsym.lawbook.resolve_all`) the report gives
the relative kinetic-metric distance to the law's nearest outcome, and for the observation its
momentum residual, energy ratio ``T⁺/T⁻``, contact violations (``H v < 0``) and the impulse-ratio
fit; the definitions are those of :mod:`impactsym.oracle`.

Exit status
-----------
0  the observation matches at least one law within ``--tolerance``;
3  it matches none (a finding, not an error: the report, or the JSON object, is still printed);
2  bad input (``--observed`` of the wrong length, NaN, a negative tolerance, an unknown law, an
   option that does not apply), with the message on stderr and, with ``--json``, one
   ``{"error": …}`` object on stdout;
1  a bug.
"""

from __future__ import annotations

from ..errors import ImpactInputError
from .common import add_json_flag

EXIT_HELP = """the observation: --observed "v1,v2,..." (in the system's coordinates), or --engine NAME to run
  the scene (--scene, --scene-file) in a physics engine and check its answer.
exit status:
  0  the observation matches at least one law within the tolerance
  3  it matches none (a finding: the report / JSON object is still printed)
  2  bad input (observed of the wrong length, NaN, negative tolerance, an option that does not apply)
  1  a bug
distance: ||v_obs - v_law||_M / ||v-||_M (kinetic metric, relative), to the law's nearest outcome;
  exact (an exact sqrt string and a float) for exact input."""



def register(sub) -> None:
    import argparse

    p = sub.add_parser(
        "check",
        help="check an observed post-impact velocity (an engine's, an experiment's) against every law",
        description="Distance from an observed post-impact velocity to every law's outcome set, its momentum "
                    "and energy residuals, contact violations, and the impulse-ratio fit.",
        epilog=EXIT_HELP, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--observed", metavar="v", help='the observed post-impact velocity "v1,v2,..." (or --engine)')
    p.add_argument("--engine", metavar="ENGINE", help="mujoco, pybullet or pymunk: run the scene in that engine "
                   "(pip install 'impactsym[engines]') and check its post-impact velocity instead of --observed")
    p.add_argument("--engine-setting", metavar="KEY=VALUE", action="append",
                   help="an engine setting, e.g. timestep=0.0005 (repeatable; with --engine)")
    p.add_argument("--sweep", metavar="SETTING=v1,v2,...",
                   help="with --engine: run the engine once per value of one setting and show which law it "
                        "follows at each (a table; --plot FILE draws the distance to each law)")
    from .plot import add_plot_option

    add_plot_option(p, "with --sweep: the distance to each law against the setting's value")
    p.add_argument("--tolerance", metavar="T", help="relative kinetic-metric tolerance of a match (default 1e-3, >= 0)")
    p.add_argument("--laws", metavar="L", help="comma-separated laws to check (default: every law)")
    from .scene_args import add_system_arguments

    add_system_arguments(p)
    p.add_argument("--restitution", metavar="e", help='restitution: one coefficient, or one per contact "a,b"')
    p.add_argument("--ratios", metavar="A", help="impulse-ratio, energetic: ratios alpha_12,... against contact 1")
    p.add_argument("--coupling", action="store_true", help="impulse-ratio: set the ratios of uncoupled contacts")
    add_json_flag(p)
    p.set_defaults(func=run)


def _laws(text):
    from ..lawbook import LAWS, get_law

    if text is None:
        return list(LAWS)
    names = [x.strip() for x in text.split(",") if x.strip()]
    if not names:
        raise ImpactInputError("laws", "is empty; give law names separated by commas")
    for n in names:
        get_law(n)  # refuses an unknown name, naming the known ones
    return [n for n in LAWS if n in names]


def _options(args, laws) -> dict:
    from .resolve_impulse_ratio import ratios_arg

    ratios = ratios_arg(args.ratios)
    takers = [n for n in ("impulse-ratio", "energetic") if n in laws]
    if ratios is not None and not takers:
        raise ImpactInputError("ratios", "--ratios applies to the laws impulse-ratio and energetic, "
                               "and neither is checked (--laws)")
    if args.coupling and "impulse-ratio" not in laws:
        raise ImpactInputError("coupling", "--coupling applies to the law impulse-ratio, which is not checked (--laws)")
    opts: dict = {}
    if ratios is not None:
        for n in takers:
            opts.setdefault(n, {})["ratios"] = ratios
    if args.coupling:
        opts.setdefault("impulse-ratio", {})["coupling"] = True
    return opts


def _read_system(args):
    """``(System, Scene or None)``: the Scene is what an engine builds (None for explicit matrices)."""
    from .scene_args import read_system

    system = read_system(args)
    if args.engine is not None and system.source is None:
        raise ImpactInputError("engine", "needs a scene (--scene or --scene-file): an engine builds bodies, "
                                         "not matrices")
    return system, system.source


def _setting_value(text: str):
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text.lower(), text)


def _engine_settings(items) -> dict:
    out = {}
    for item in items or []:
        key, sep, val = item.partition("=")
        if not sep or not key.strip():
            raise ImpactInputError("engine_setting", f"expected KEY=VALUE, got {item!r}")
        out[key.strip()] = _setting_value(val.strip())
    return out


def _run_engine(args, system, scene, extra=None):
    """The engine's post-impact velocity (floats) and what the run used (``extra``: settings that
    override ``--engine-setting``, for ``--sweep``)."""
    import sympy as sp

    try:
        from .. import engines
    except ImportError:
        raise ImpactInputError("engine", "the engine adapters (impactsym.engines) are not in this installation") from None
    e = system.restitution
    if isinstance(e, (list, tuple)):
        raise ImpactInputError("restitution", "--engine takes one restitution for every contact")
    e = 1 if e is None else float(sp.sympify(e))
    settings = {**_engine_settings(args.engine_setting), **(extra or {})}
    try:
        r = engines.run(args.engine, scene, restitution=e, settings=settings or None)
    except engines.EngineNotInstalled as exc:
        raise ImpactInputError("engine", str(exc)) from None
    info = {"name": r.engine, "restitution": r.restitution, "settings": dict(r.settings),
            "defaults": dict(r.defaults or {}), "steps": r.steps, "time": r.time, "separated": r.separated,
            "note": r.note, "velocity": [float(x) for x in r.velocity]}
    return [float(x) for x in r.velocity], info


def run(args):
    from ..numbers import parse_number, parse_vector
    from ..oracle import DEFAULT_TOLERANCE, check
    from .scene_args import float_range_guard

    if (args.observed is None) == (args.engine is None):
        raise ImpactInputError("observed", "give exactly one of --observed (a velocity) and --engine (run an engine)")
    if args.engine_setting and args.engine is None:
        raise ImpactInputError("engine_setting", "--engine-setting applies only with --engine")
    if args.sweep is not None and args.engine is None:
        raise ImpactInputError("sweep", "--sweep applies only with --engine (it reruns the engine per value)")
    from .plot import plot_path

    if args.sweep is None and getattr(args, "plot", None) is not None:
        raise ImpactInputError("plot", "--plot applies only with --sweep")
    laws = _laws(args.laws)
    tol = parse_number(args.tolerance if args.tolerance is not None else DEFAULT_TOLERANCE, "tolerance")
    options = _options(args, laws)
    system, scene = _read_system(args)
    if args.sweep is not None:
        return _sweep(args, system, scene, tol, laws, options, plot_path(args))
    engine = None
    if args.engine is not None:
        observed, engine = _run_engine(args, system, scene)
    else:
        observed = parse_vector(args.observed, "observed")
    with float_range_guard(args):
        report = check(system, observed, tolerance=tol, laws=laws, options=options)
    out = report.as_json()
    if engine is not None:
        out["engine"] = engine
    return out, report.exit_status


def _sweep_values(text: str):
    key, sep, vals = text.partition("=")
    items = [v.strip() for v in vals.split(",") if v.strip()]
    if not sep or not key.strip() or not items:
        raise ImpactInputError("sweep", f"expected SETTING=v1,v2,..., got {text!r}")
    return key.strip(), items


def _sweep(args, system, scene, tol, laws, options, path):
    """Which law the engine follows as one setting changes: one engine run and one check per value.
    Exit status 0 when every value's answer matches some law, 3 otherwise."""
    from ..oracle import check

    setting, texts = _sweep_values(args.sweep)
    rows, checks = [], []
    for text in texts:
        value = _setting_value(text)
        observed, engine = _run_engine(args, system, scene, {setting: value})
        report = check(system, observed, tolerance=tol, laws=laws, options=options).as_json()
        distances = {name: e["distance_float"] for name, e in report["laws"].items()
                     if "refused" not in e and e["distance_float"] is not None}
        nearest = min(distances, key=distances.get) if distances else None
        rows.append({"value": value, "nearest": nearest, "distance_float": distances.get(nearest),
                     "matches": report["matches"], "energy_ratio_float": report["energy_ratio_float"],
                     "distances": distances, "separated": engine["separated"]})
        checks.append({"engine": engine, "check": report})
    out = {"schema": "impactsym.check-sweep/1", "engine": args.engine, "setting": setting,
           "tolerance": str(tol), "rows": rows, "checks": checks}
    if path is not None:
        from .plot import write_figure

        write_figure(_sweep_figure(out), path)
    return out, (0 if all(r["matches"] for r in rows) else 3)


def _sweep_figure(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    labels = [str(r["value"]) for r in out["rows"]]
    laws = sorted({law for r in out["rows"] for law in r["distances"]})
    for i, law in enumerate(laws):
        ys = [max(r["distances"].get(law, float("nan")), 1e-17) for r in out["rows"]]
        ax.plot(range(len(labels)), ys, marker="o", color=f"C{i % 10}", label=law)
    from fractions import Fraction

    ax.axhline(float(Fraction(out["tolerance"])), color="k", ls="--", lw=0.8, label="tolerance")
    ax.set_yscale("log")
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, rotation=30, fontsize=8)
    ax.set_xlabel(out["setting"])
    ax.set_ylabel("||v_engine - v_law||_M / ||v-||_M")
    ax.set_title(f"{out['engine']}: distance to each law as {out['setting']} changes", fontsize=9)
    ax.legend(fontsize=6, ncol=2)
    from ..figures._common import tight_layout_once

    return tight_layout_once(fig)


def render_sweep(result: dict) -> str:
    lines = [f"engine {result['engine']}: which law it follows as {result['setting']} changes "
             f"(tolerance {result['tolerance']})"]
    rows = [(result["setting"], "nearest law", "distance", "T+/T-", "matches")]
    for r in result["rows"]:
        rows.append((str(r["value"]), r["nearest"] or "-", "-" if r["distance_float"] is None else
                     f"{r['distance_float']:.3e}", f"{r['energy_ratio_float']:.6g}",
                     ", ".join(r["matches"]) or "none"))
    widths = [max(len(row[c]) for row in rows) for c in range(5)]
    for row in rows:
        lines.append("  ".join(f"{x:<{w}}" for x, w in zip(row, widths)).rstrip())
    return "\n".join(lines)


# ------------------------------------------------------------------------------------ text
def _vec(xs) -> str:
    return "[" + ", ".join(map(str, xs)) + "]" if xs is not None else "-"


def _num(text, value) -> str:
    """An exact number as text, or its float when the exact form is long (a float's binary value)."""
    if text is None:
        return "-"
    if len(str(text)) <= 24 or value is None:
        return str(text)
    return f"{value:.9g} (exact: {len(str(text))} characters in JSON)"


def _nums(texts, values) -> str:
    if texts is None:
        return "-"
    if all(len(str(t)) <= 24 for t in texts):
        return _vec(texts)
    return _vec([f"{v:.9g}" for v in values])


def render(result: dict) -> str:
    if result.get("schema") == "impactsym.check-sweep/1":
        return render_sweep(result)
    lines = []
    if result.get("scene"):
        lines.append("scene: " + ", ".join(f"{k}={v}" for k, v in result["scene"].items()))
    sysj = result["system"]
    if result.get("engine"):
        e = result["engine"]
        lines.append(f"engine {e['name']} (restitution {e['restitution']}; {e['steps']} steps; {e['note']})")
        changed = {k: v for k, v in e["settings"].items() if e["defaults"].get(k) != v}
        if changed:
            lines.append("  settings changed from the defaults: " + ", ".join(f"{k}={v}" for k, v in changed.items()))
        lines.append(f"  v+ = {_vec([f'{x:.6g}' for x in e['velocity']])}")
    lines.append(f"v- = {_vec(sysj['velocity'])}   observed v+ = {_nums(result['observed'], result['observed_float'])}"
                 + ("" if result["observed_exactness"] == "exact" else f" ({result['observed_exactness']})"))
    lines.append(f"tolerance {result['tolerance']} on ||v - v_law||_M / ||v-||_M")
    rows = [("law", "outcome", "distance", "", "nearest v+", "match")]
    for name, e in result["laws"].items():
        if "refused" in e:
            rows.append((name, e["refused"], "", "", "", ""))
            continue
        near = e["nearest"]
        which = "" if near is None or (e["outcomes"] + e["selected"]) == 1 else f"{near['kind']} {near['index'] + 1}"
        df = "" if e["distance_float"] is None else f"{e['distance_float']:.3e}"
        shown = "" if e["distance"] is None else (e["distance"] if e["distance_exact"] else f"({e['exactness']})")
        velocity = "-" if near is None else (_vec(near["velocity"]) if all(len(x) <= 12 for x in near["velocity"])
                                             else _vec([f"{x:.6g}" for x in near["velocity_float"]]))
        rows.append((name, f"{e['uniqueness']} {which}".strip(), df, shown, velocity, "yes" if e["match"] else "no"))
    widths = [max(len(r[c]) for r in rows if r[2] != "" or r[0] == "law" or c != 1) for c in range(6)]
    for r in rows:
        if r[2] == "" and r[0] != "law":
            lines.append(f"{r[0]:<{widths[0]}}  {r[1]}")
        else:
            exact = r[3] if r[3] and len(r[3]) <= 24 else ("" if not r[3] else "(exact)")
            lines.append(f"{r[0]:<{widths[0]}}  {r[1]:<{widths[1]}}  {r[2]:<10} {exact:<24} "
                         f"{r[4]:<{widths[4]}}  {r[5]}".rstrip())
    m = result["momentum"]
    lines.append(f"momentum residual ||r||_(M^-1)/||v-||_M = {_num(m['residual_norm'], m['residual_norm_float'])}"
                 + ("  (zero: M(v - v-) = H^T p with p = " + _vec(m["impulses"]) + ")" if m["residual_zero"] and m["impulses"] else ""))
    lines.append(f"energy ratio T+/T- = {_num(result['energy_ratio'], result['energy_ratio_float'])}")
    lines.append(f"contact velocities H v+ = {_nums(result['contact_velocity'], result['contact_velocity_float'])}")
    for v in result["contact_violations"]:
        lines.append("  violated: " + v["message"])
    f = result["impulse_ratio_fit"]
    fit = f"impulse-ratio fit: {f['status']}"
    if f["ratios"] is not None:
        fit += f" (ratios {_nums(f['ratios'], f['ratios_float'])}, e = {_num(f['restitution'], f['restitution_float'])})"
    lines.append(fit)
    if f["reason"]:
        lines.append("  " + f["reason"])
    if f["valid"] is False:
        lines.append("  the law with these ratios and e is outside its domain: "
                     + "; ".join(v["condition"] for v in f["violations"]))
    for n in result["notes"]:
        lines.append("note: " + n)
    lines.append("matches: " + (", ".join(result["matches"]) if result["matches"] else
                                "none (exit status 3)"))
    return "\n".join(lines)
