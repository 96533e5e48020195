"""What is specific to ``impactsym resolve --law hertz|linear|power|hunt-crossley|lzb`` (the
compliant and LZB laws of :mod:`impactsym.lawbook_compliant`): their options and the lines of
their details.

Options: ``--stiffness K`` (one number or one per contact ``"a,b"``, default 1), ``--exponent P``
(``power``: required; ``hunt-crossley``, ``lzb``: default 3/2; one or one per contact),
``--damping D`` (``hunt-crossley``: the coefficients ``D`` instead of ``--restitution``),
``--tolerance RTOL`` (the integrator's relative tolerance, default 1e-11). Numbers are read
exactly and handed to the float integrators.

``details`` in JSON: ``model``, ``exponent``, ``stiffness``, ``tolerance`` (``rtol``, ``atol``,
the end thresholds), the integration's counts (``events``, ``steps``, ``nfev``; LZB
``segments``), ``duration``, ``end`` (``separated``), ``energy_ratio`` (``T⁺/T⁻``) and ``ratios``
(``P_j/P_1``); Hunt–Crossley also ``damping`` and ``damping_from``; LZB ``restitution``.
"""

from __future__ import annotations

from ..errors import ImpactInputError

__all__ = ["hertz_options", "linear_options", "power_options", "hunt_crossley_options", "lzb_options", "render",
           "per_contact_arg"]


def parse_number(text, argument):
    """One exact number: plain text (``"3/2"``, ``"1e-11"``) as a ``Fraction``, without SymPy;
    anything else by :func:`impactsym.numbers.parse_number` (which also words every error). The
    laws read both alike (their floats are ``float(N(x, 17))``).

    >>> parse_number("1.5", "exponent"), parse_number("sqrt(2)", "stiffness")
    (Fraction(3, 2), sqrt(2))
    """
    from ..arithmetic.literals import plain_rational

    try:
        value = plain_rational(text)
    except ZeroDivisionError:
        value = None
    if value is not None:
        return value
    from ..numbers import parse_number as parse

    return parse(text, argument)


def per_contact_arg(text, argument):
    """One exact number, or one per contact ``"a,b"`` (a list); None when absent.

    >>> per_contact_arg("3/2", "exponent"), per_contact_arg("1, 2", "stiffness")
    (Fraction(3, 2), [Fraction(1, 1), Fraction(2, 1)])
    """
    if text is None:
        return None
    parts = [x.strip() for x in str(text).split(",")]
    if any(not x for x in parts):
        raise ImpactInputError(argument, f"has an empty entry: {text!r}")
    values = [parse_number(x, argument) for x in parts]
    return values if len(values) > 1 else values[0]


def _common(args) -> dict:
    return {"stiffness": per_contact_arg(args.stiffness, "stiffness"),
            "tolerance": None if args.tolerance is None else parse_number(args.tolerance, "tolerance")}


def hertz_options(args) -> dict:
    return _common(args)


def linear_options(args) -> dict:
    return _common(args)


def power_options(args) -> dict:
    return {**_common(args), "exponent": per_contact_arg(args.exponent, "exponent")}


def hunt_crossley_options(args) -> dict:
    return {**power_options(args), "damping": per_contact_arg(args.damping, "damping")}


def lzb_options(args) -> dict:
    return power_options(args)


def _fmt(xs) -> str:
    return "[" + ", ".join(f"{x:.10g}" for x in xs) + "]"


def render(result: dict) -> list[str]:
    d = result["details"]
    if d.get("end") == "no impact":
        return ["no contact approaches: nothing to integrate"]
    lines = [f"model: {d['model']}, exponent {_fmt(d['exponent'])}, stiffness {_fmt(d['stiffness'])}"]
    if "damping" in d:
        lines.append(f"Hunt-Crossley damping D = {_fmt(d['damping'])}" +
                     ("" if d["damping_from"] == "given" else
                      f" (from e = {_fmt(d['damping_from']['restitution'])} at speeds "
                      f"{_fmt(d['damping_from']['calibration_speed'])})"))
    if "restitution" in d:
        lines.append(f"energetic restitution per contact e = {_fmt(d['restitution'])}")
    tol = d["tolerance"]
    if d["model"] == "lzb":
        lines.append(f"integration: DOP853 in the primary impulse, rtol {tol['rtol']:g}; {d['segments']} segments, "
                     f"{d['steps']} steps, {d['nfev']} RHS evaluations")
    else:
        lines.append(f"integration: DOP853, rtol {tol['rtol']:g}; {d['events']} contact events, {d['steps']} steps, "
                     f"{d['nfev']} RHS evaluations; {d['end']} at t = {d['duration']:.10g}")
    lines.append(f"ratios P_j/P_1 = {_fmt(d['ratios'])}; T+/T- = {d['energy_ratio']:.15g}")
    return lines
