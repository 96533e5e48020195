"""``impactsym domain --scene chain3|pool [--theta T] [--json]``: the impulse-ratio law's validity
domain in ``(α, e)``, as exact inequalities and boundary curves (Acary & Taha eqs. 19, 28–32)."""

from __future__ import annotations

from .common import add_json_flag
from .plot import add_plot_option, plot_path, write_figure


#: the scenes of :data:`impactsym.domains.SCENES`, named here so that the parser is built without
#: importing the domains (SymPy, SciPy); tests/test_cli_startup.py checks that the two agree
SCENE_NAMES = ("chain3", "pool")


def register(sub) -> None:
    p = sub.add_parser(
        "domain",
        help="validity domain of the impulse-ratio law in (alpha, e): inequalities and boundary curves",
        description=("Print where the impulse-ratio law has a solution (Delta >= 0) that is admissible "
                     "(p >= 0, H v+ >= 0 on closed contacts), exactly (Acary & Taha eqs. 19, 28-32)."),
    )
    p.add_argument("--scene", required=True, metavar="SCENE", help="one of: " + ", ".join(SCENE_NAMES))
    p.add_argument("--theta", metavar="T",
                   help="pool angle theta in [0, 2*pi/3] (exact text: 'pi/4', '1/2'); omitted: the domain as a function of theta")
    p.add_argument("--tau", metavar="TAU",
                   help="pool incidence angle tau (needs --theta; default 0): the domain at (theta, tau)")
    add_plot_option(p, "the domain drawn (without --theta: small multiples over theta)")
    add_json_flag(p)
    p.set_defaults(func=run)


def run(args) -> dict:
    from ..domains import validity_domain

    path = plot_path(args)  # checked before the work
    result = validity_domain(args.scene, args.theta, args.tau).as_json()
    if path is not None:
        from ..figures import domain_figure

        write_figure(domain_figure(args.scene, args.theta, args.tau)[0], path)
    return result


def render(result: dict) -> str:
    head = f"validity domain of the impulse-ratio law, scene {result['scene']}"
    if result.get("theta") is not None:
        head += f", theta = {result['theta']}"
    if result.get("tau") is not None:
        head += f", tau = {result['tau']}"
    out = [head, "", "inequalities:"]
    out += [f"  {x}" for x in result["inequalities"]]
    out += ["", "boundary curves:"]
    for b in result["boundaries"]:
        out.append(f"  {b['name']}: {b['expression']}")
        out.append(f"      {b['condition']}")
    reg = result["region"]
    out += ["", "region:"]
    if "alpha" in reg:  # an empty domain (no impact at all) has no alpha/e ranges
        out.append(f"  alpha in [{reg['alpha'][0]}, {reg['alpha'][1]}]")
    if "e" in reg:
        out.append(f"  e     in [{reg['e'][0]}, {reg['e'][1]}]")
    out += [f"  empty: {reg['empty']}", f"  {reg['description']}"]
    if result.get("theta_sweep"):
        out += ["", "by theta:"]
        for row in result["theta_sweep"]:
            out.append(f"  theta = {row['theta']:>8}: alpha in [{row['alpha'][0]}, {row['alpha'][1]}], "
                       f"e in [{row['e'][0]}, {row['e'][1]}]")
    return "\n".join(out)
