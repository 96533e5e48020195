"""Compliant (regularized) impacts: where the impulse ratios come from (Acary & Taha sec. 3.4).

The model
---------
Generalized coordinates ``q`` (``q = 0`` at the impact instant, every listed contact touching or
at a given gap ``g⁰``), mass matrix ``M``, contact rows ``H`` (the conventions' ``φ_i ≥ 0``
admissible). The gaps are taken to first order, ``g = g⁰ + H q``, the same linearization the
rigid laws use (exact for balls on a line and walls; for planar scenes a small-displacement
approximation, good while the indentations are small against the radii). Indentation
``δ = −g``, its rate ``δ̇ = −H q̇``, and

    ``M q̈ = Hᵀ f(δ, δ̇)``,   ``Ṗ = f``   (``P_i = ∫ f_i dt``, the impulses of eq. 21).

Contact force of contact ``i``, acting only while ``δ_i > 0`` and never pulling (``f_i`` is
``max(·, 0)``: a damped contact would otherwise become adhesive near the end of restitution;
this is the usual unilateral reading of eq. 20, stated rather than done silently):

* power law (exponent ``p_i ≥ 1``; ``p = 3/2`` is Hertz, eq. 20; ``p = 1`` linear, eq. 23)
  ``f = K δ^p + C δ^{p−1} δ̇`` with the damping ``C ≥ 0`` of eq. 20 (default 0);
* Hunt–Crossley ``f = K δ^p (1 + D δ̇)``, ``D ≥ 0``. For one contact between two bodies the
  restitution it gives depends only on ``x = D u`` (``u`` the impact speed), not on ``K``,
  ``p`` or the masses: ``x − ln(1 + x) = −e x − ln(1 − e x)`` (integrate
  ``μ u du/dδ = −Kδ^p(1 + D u)`` over compression and restitution).
  :func:`hunt_crossley_damping` inverts it: the ``D`` that gives a restitution ``e`` at a speed ``u``.

Event handling and termination
------------------------------
The right-hand side is continuous in the state for the elastic and Hunt–Crossley laws
(``max(δ, 0)^p`` with ``p ≥ 1``; eq. 20 damping with ``p = 1`` jumps at first contact), so the
impact is integrated as one ODE (DOP853, adaptive) but for one kind of contact. In an elastic run
(no damping of either kind) a contact with an integer exponent, the linear one included, has a
force ``K (δ⁺)^p`` whose kink at ``δ = 0`` DOP853's error estimate does not see; such a contact is
*held* within a piece of the run, ``K δ^p`` for every ``δ`` (a polynomial) while closed and 0 while
open, and its gap crossing ``±atol·L``, just beyond its law's 0, ends the piece (a terminal event,
rising through ``+atol·L`` while closed, falling through ``−atol·L`` while open; a crossing there
and back inside one step is found on the step's dense output). The next piece starts from the root
with that gap set to the band's edge and its law flipped; a gap within the band keeps its law (two
bodies that touch and move together at ``t = 0`` stay open until the gap falls through
``−atol·L``), any other gap gives its law by its sign. Measured: a scaled sweep scene of linear
contacts went from 1.8e-8 to 1e-11 off at ``rtol = 1e-11``; watched at 0, the gaps ahead of a wave
(1e-35 to 1e-323, their signs decided by rounding) ended a piece at each flicker (a 10-ball chain
of exponent 2 counted 58 events for 18 crossings). A contact with a non-integer exponent
cannot be held (``δ^p`` has no real value for ``δ < 0``), and its force starts as ``(t − t_c)^p``
and stops as ``(t_e − t)^p``: the steps end at its crossings instead. Once its gap has been beyond
its absolute tolerance (compressed or apart; not the 1e-300 gaps ahead of a wave, whose signs
rounding decides), an accepted step that takes it across 0 is taken again from its start to the
crossing's root at ``rtol/100``, and the run goes on from the root without a restart (``_dop853``'s
``crossings``). Measured against the independent piecewise reference of
``tests/piecewise_reference.py`` on 160 random 3–5-ball chains (``p = 1.5`` and ``2.5``): the worst
went from 5.6e-9 to 3.3e-10 off at ``rtol = 1e-11``, for 7–9 % more steps; ending the steps at the
openings alone left a chain that re-closes 3.1e-9 off. A Hunt–Crossley contact's force starts and
stops at the gap's 0 as well, and its steps end there too (of 120 random chains, ``p`` = 1, 1.5
and 2.5, the worst went from 5.9e-9 to 2.4e-10); where the others' forces pull a closed contact
open faster than ``1/D`` (never in a chain; in 31 of 159 random 3-body systems with ``D`` in
``[0.5, 8]``), its force, kept ``≥ 0``, stops where ``1 + D δ̇`` falls through 0, and the steps end
there too (the worst of those 31 went from 2.9e-10 to 1.3e-11). Eq. 20's damped force
``δ^(p−1) (K δ + C δ̇)``, kept ``≥ 0``, stops where ``K δ + C δ̇`` falls through 0, before the gap
opens: its steps end there too, a crossing of a linear function of the state while the contact is
closed (of 150 random chains, ``p`` = 1, 1.5 and 2.5, the worst went from 1.1e-8 to 4.9e-10 off
``tests/piecewise_reference.py``'s damped reference). What is integrated is ``(g, q̇, P)``
with ``ġ = H q̇``: the gaps, not ``q``, since only they enter the forces and the error control is
relative to each component's size (with ``q`` integrated, gaps of 0.1 between coordinates that
had flown to 16 were kept to ``rtol·16``: 7e-6 off at ``rtol = 1e-11`` on a light ball ringing
between two heavy ones). Time is counted in
a power of two near ``T`` when ``T`` is far from 1 (SciPy places an event's root to an absolute
``4·EPS`` in ``t``). The integration runs in windows and stops at the root of the *stopping
function*

    ``s(y) = min_i min(g_i / L, (H q̇)_i / V + ε_w)``,

i.e. when every contact is open (``g_i ≥ 0``) and none approaches (``(H q̇)_i ≥ −ε_w V``,
``ε_w = 1e-12``: a relative speed below the integrator's own error counts as zero); the same test
is also made on the state at the start of every window. This is a *proof that the result is
final* for the model: with no force, ``q(t) = q + q̇ t`` and every gap ``g_i + (H q̇)_i t`` stays
non-negative for all later ``t``. Free flight (every gap open, so no force) is not integrated:
the gaps are linear in time there, and the state jumps exactly to the next closing (late, slow
re-contacts at the tail of a long chain would otherwise cost ~10⁶ contact times of integration).

*Theorem* (``docs/compliant_termination.md``, with the proof). If some ``u`` has ``H u > 0`` (a
separating direction, decided with an exact certificate by
:func:`impactsym.termination.separating_direction`), every impulse stays below a proved bound
(``Σ_i (Hu)_i P_i ≤ 2 ‖u‖_M √(2T⁻)``), the velocity converges to a ``v∞`` with ``H v∞ ≥ 0``, and an
*elastic* run meets the stopping condition in finite time; a damped one converges to it (finite
time not proved). Otherwise (Gordan's alternative) some ``λ ≥ 0``, ``λ ≠ 0`` has ``Hᵀλ = 0``: those
contacts can never all leave, and a body confined by them need not stop (a ball between two
walls: ``H v ≥ 0`` forces ``v = 0``, and elastic it rings for ever); with damping its energy decays
and ``rest_tol`` stops the run once ``T + V_elastic ≤ rest_tol · T⁻`` (``outcome = "rest"``). The
proof gives finiteness, not a bound on the time or on the number of events.

What the code enforces: the certificate is computed for every run (``CompliantResult.certificate``);
at the end of every window the energy must not exceed ``T⁻ (1 + tol)`` and every impulse must stay
below its proved bound (:func:`impactsym.termination.impulse_bounds`); after the run
:func:`impactsym.termination.check_run` checks the momentum balance, the energy (elastic:
``|T⁺/T⁻ − 1| ≤ tol``, ``tol = min(1e5 rtol, 10 √rtol)``, measured) and the bound again
(``CompliantResult.checks``). A violation raises :class:`~impactsym.errors.VerificationError`
instead of returning. The caps stay as a numerical safeguard: ``max_events`` contact
openings/closings, 10⁵ integration windows of ``200 T`` (``T`` the shortest contact time scale;
a window that ends without a contact event is followed by one twice as long, so that a slow tail
of late, slow re-contacts does not use them up) and the optional ``t_max``; past any of them,
:class:`~impactsym.errors.NonTermination` is raised naming the cap (and, without a separating
direction, the certificate ``λ``).

Events counted: a contact event is a change of ``δ_i > 0`` between consecutive accepted steps
(an opening or a closing; one that opens and closes again inside a single step is not seen, but
for a held contact, whose every crossing ends a piece).
``steps`` and ``nfev`` report the integrator's work. No bound on the number of events is proved
(for elastic chains the number of re-contacts depends on the mass ratios). Measured counts:
``benchmarks/results/compliant.md`` (a monodisperse Hertz chain of ``n ≤ 50`` balls struck at one
end: exactly ``2(n − 1)`` events, each contact closes and opens once; 100 balls: 392 events, the
tail re-contacting slowly).

Scaling (dimensional analysis; tested in ``tests/test_compliant.py``). With ``x = V T x̃``,
``t = T t̃`` and a speed scale ``V``, the Hertz chain is dimensionless for
``T = (m/(K V^{1/2}))^{2/5}`` and ``C/K`` measured in units of ``T``. Hence, *without damping*,
the ratios depend only on the mass ratios, stiffness ratios and the ratios of pre-impact
velocities (claim 2(b) of sec. 3.4), and not on ``|v⁻|``. *With damping*, they are invariant
under ``K → λK``, ``m → μm`` only if ``C → λ (μ/λ)^{2/5} C`` (and under ``v → s v`` only if
``C → s^{−1/5} C``): with ``C`` held fixed, claim 2(b) does not hold as stated. For the linear
model (claim 3) ``T = (m/K)^{1/2}`` does not involve ``V`` and the equations are linear between
contact events, so the ratios depend on neither the absolute stiffness and mass nor ``|v⁻|``.
(For Hunt–Crossley, ``D V`` is dimensionless: the ratios are invariant under ``K → λK``,
``m → μm`` with ``D`` fixed, and under ``v → s v`` only if ``D → D/s``.)

Examples
--------
Three equal balls, ball 1 striking at unit speed, elastic Hertz contacts: balls 1 and 2 keep a
small motion (sec. 3.3's point) and the ratio is ``α ≈ 0.9287``:

>>> r = chain_impact([1, 1, 1], [1, 0, 0], [1, 1])
>>> r.ratios.round(5).tolist(), r.velocity.round(5).tolist(), round(r.energy_ratio, 9)
([1.0, 0.92866], [-0.07095, 0.0764, 0.99455], 1.0)
>>> chain_impact([1, 1, 1], [1, 0, 0], [1, 1], model="linear").ratios.round(5).tolist()
[1.0, 0.86708]

A planar scene goes in through its ``M``, ``H`` and ``v`` (SymPy matrices are accepted): the pool
of sec. 4 at ``θ = π/3``, ``τ = π/12`` with equal Hertz contacts:

>>> import sympy as sp
>>> from impactsym.models.acary_taha import pool
>>> sc = pool(sp.pi / 3, sp.pi / 12)
>>> compliant_impact(sc.M, sc.H, sc.v, 1.0).ratios.round(5).tolist()
[1.0, 0.47903]

References
----------
Acary & Taha, sec. 3.4, eqs. 20–23; claims 2(b) and 3.
K. H. Hunt, F. R. E. Crossley, "Coefficient of restitution interpreted as damping in
vibroimpact", J. Appl. Mech. 42 (1975) 440–445.
"""

from __future__ import annotations

from dataclasses import dataclass

import math
from math import inf, nextafter, sqrt

import numpy as np
from scipy.integrate import DOP853
from scipy.integrate._ivp.ivp import handle_events, prepare_events, solve_event_equation
from scipy.optimize import brentq

from .errors import ImpactInputError, NonTermination, VerificationError

__all__ = ["CompliantResult", "chain_impact", "compliant_impact", "chain_matrices", "hunt_crossley_damping",
           "hunt_crossley_restitution", "MODELS", "WALLS"]

MODELS = ("hertz", "linear")
WALLS = ("left", "right")

#: relative approach speed (in units of the largest initial one) treated as zero by the stopping test
SEPARATION_EPS = 1e-12
#: the pre-impact kinetic energies the compliant laws take: inside float64 with the products of
#: the energy, the masses and the impulses that the run and its checks form
ENERGY_RANGE = (1e-305, 1e300)
#: the effective masses ``μ_i = 1/(H_i M⁻¹ H_iᵀ)`` the float64 integrations (the compliant laws and
#: LZB) take. Measured (issue 15) on a grid of M, H and v scaled by 10^k, k = −150…150 in steps of
#: 50: with μ and T⁻ inside their ranges no run of hertz, linear or LZB raised or hung (outcomes
#: within 3e-8 of the unit problem's); outside, a row of H at 1e-140 or 1e140 (a 1e-320 one hung for
#: minutes) ended in a ZeroDivisionError, a ValueError of the integrator or a failed self-check.
#: Inside, a random sweep of continuous scales (M, H, v times 10^U(−170, 170) each, 3-ball chains,
#: the runs the ranges admit) found failures until the laws integrated the gaps in their own units
#: and LZB's P_p and threshold were scaled: then 2118 of 2118 hertz, linear and Hunt–Crossley runs and
#: 2410 of 2411 LZB runs (e = 0.8) within 1e-6 of the unit problem; the other, 2.4e-5 off at
#: rtol 1e-11 and right at 1e-12, missed a contact's turn to expansion and back inside one step,
#: which LZB's turns now find (then 1169 of 1169 LZB runs of seed 5 in 420 s, worst 4.9e-9;
#: benchmarks/results/scale_sweep.md has the committed run). Sampled, not proved
SCALE_RANGE = (1e-150, 1e150)


@dataclass
class CompliantResult:
    """Outcome of a compliant impact.

    Attributes
    ----------
    impulses : ``P_i = ∫ f_i dt`` per contact (k)
    ratios : ``α_1j = P_j / P_1`` (eq. 21), ``ratios[0] = 1``
    velocity : post-impact generalized velocity (n)
    duration : time at which the last contact opened (the ``t_f`` of eq. 21), or the time the
        ``rest_tol`` test stopped the run
    energy_ratio : ``T⁺ / T⁻`` (the global energetic coefficient ``e`` this run realizes)
    events : number of contact openings/closings met
    steps : accepted integrator steps
    nfev : right-hand-side evaluations
    outcome : ``"separated"`` (every contact open, none approaching) or ``"rest"`` (``rest_tol``)
    certificate : :class:`~impactsym.termination.SeparationCertificate` of the rows: ``u`` with
        ``H u > 0`` (the termination theorem applies) or ``λ ≥ 0`` with ``Hᵀλ = 0`` (it does not)
    checks : the residuals of :func:`~impactsym.termination.check_run` (momentum, energy, impulse
        bound) and their tolerances
    """

    impulses: np.ndarray
    ratios: np.ndarray
    velocity: np.ndarray
    duration: float
    energy_ratio: float
    events: int
    steps: int = 0
    nfev: int = 0
    outcome: str = "separated"
    #: :class:`~impactsym.termination.SeparationCertificate` of the rows (the theorem's hypothesis)
    certificate: object = None
    #: the a-posteriori checks passed (:func:`impactsym.termination.check_run`)
    checks: dict | None = None


class _Run:
    """What :func:`_dop853` returns: the fields of ``solve_ivp``'s result that the callers read."""

    __slots__ = ("t", "y", "t_events", "y_events", "status", "message", "nfev", "steps", "y_last", "t_prev", "y_prev",
                 "h_abs")


def _dop853(fun, t0, t_bound, y0, rtol, atol, events, keep_states=True, into=False, values=None, stage=None,
            turns=(), crossings=(), first_step=None):
    """``solve_ivp(fun, (t0, t_bound), y0, method="DOP853", rtol=rtol, atol=atol, events=events)``, faster.

    The same floating-point operations in the same order as SciPy's ``DOP853`` (the initial step,
    every stage, the error norm and step-size control, the dense output and the event roots found
    by ``brentq`` on it, all on arrays of the same shapes), so the steps, the states and the event
    roots are bit for bit those of ``solve_ivp``; ``tests/test_dop853_driver.py`` checks that on runs of
    both laws. What it saves is the Python around the arithmetic: two wrapper calls and an
    ``asarray`` per right-hand side, the slicing of the stage table at every stage, temporaries,
    conversions of Python scalars, NumPy scalar arithmetic in the step control and the event
    bookkeeping. ``fun`` and the events may read ``t``, given as a Python float (SciPy may pass a
    NumPy one of the same value); the events carry SciPy's ``terminal`` and ``direction``
    attributes. With ``into``, ``fun(t, y, out)`` writes the stages into the stage table's rows
    (``out`` is None where a fresh array is wanted) instead of returning arrays to copy there.
    ``values(t, y)``, if given, returns the events' values at an accepted state in one call (a
    list, one per event), equal to the events' own but for the sign of a zero: only their signs
    are read there (which events change sign within a step), while the roots are found with the
    events themselves. ``stage(y, out)``, if given, is called once per stage row ``out`` with the
    one buffer ``y`` that will hold every stage's input, and returns ``None`` or a function of no
    argument that does ``fun(t, y, out)`` for ``y``'s contents at the time (``fun`` must not read
    ``t`` then): its views and work arrays are made once per integration, not once per stage.

    ``turns`` (our addition; none by default, and then every step is SciPy's) lists pairs
    ``(i, slope)``: event ``i`` (with a direction ``±1``) whose two crossings inside one step are to
    be found too, where ``slope(f)`` is the event's derivative for the state derivative ``f`` (or
    an int ``j``: the derivative is ``f[j]``; when every slope is one, the ends of the step are read
    for all turns at once, :func:`_excursions`' ``columns``).
    SciPy sees only sign changes between accepted steps, so a value that rises through 0 and falls
    back within one step is never seen. When event ``i`` has the same sign, against its direction,
    at both ends of a step and its slopes at the ends say that it turns towards 0 and back inside
    (an extremum, the only one the end slopes reveal), the extremum of the event on the step's
    dense output is found (:func:`_excursion_root`); if it lies past 0, the first crossing is a
    root of the event like any other, located by ``brentq`` as SciPy locates them.

    ``crossings`` (our addition; none by default) lists pairs ``(i, floor)``: a gap ``y[i]`` whose
    crossings of 0 are to end steps (or triples ``(row, floor, gate)``: the linear function
    ``row · y``, its crossings counted only where the gap ``y[gate]`` is below 0 at both ends of
    the step, and no value set at its root; eq. 20's ``K δ + C δ̇``; or ``(row, floor, gate,
    offset)``, the affine ``offset + row · y`` the same way: Hunt–Crossley's ``1 + D δ̇``). Where a
    force ``K (δ⁺)^p`` with a non-integer ``p`` starts or stops (a contact closing or opening, the
    force growing as ``(t − t_c)^p`` or falling as ``(t_e − t)^p``), the right-hand side is not smooth, and DOP853
    underestimates the error of a step with that point inside. A gap is armed once it reads beyond
    ``floor`` at an accepted state: below ``−floor`` (compressed) it is armed to open, above
    ``floor`` (apart) to close; gaps that never leave ``[−floor, floor]`` (the 1e-300 gaps ahead of
    a wave, whose signs rounding decides) are never armed. When an accepted step takes an armed gap
    across 0, the crossing's root is found on the step's dense output (``brentq``), the step is
    taken again from its start to the first such root at ``rtol/100`` (floored at
    :data:`REFINE_RTOL_FLOOR`) and ``atol/100`` with the events (a terminal one before the root ends
    this run at its own root), and the run goes on from the root, the gap set to 0 and disarmed,
    with the step size it had: no restart. So no step has an armed crossing inside it, as in a run
    stopped at each crossing (:func:`_cut_at_crossing`).

    Returns an object with ``t`` (accepted times, only if ``keep_states``), ``y`` (the states, one
    column per time, only if ``keep_states``), ``steps``, ``y_last`` (the final state), ``t_prev`` and
    ``y_prev`` (the last step's start: where a terminal event's step began), ``t_events``,
    ``y_events``, ``status`` (0 end of the span, 1 a terminal event, -1 the step size underflowed),
    ``message``, ``nfev`` and ``h_abs`` (the step size the controller would try next). ``first_step``
    (our addition) starts the run with that step size instead of SciPy's initial choice.
    """
    t0, t_bound = float(t0), float(t_bound)
    if not t_bound > t0:  # pragma: no cover - the callers always integrate forward over a non-empty span
        raise ValueError("_dop853 integrates forward over a non-empty span")
    # the initial derivative and step: SciPy's own (or first_step, capped at the span)
    solver = DOP853(fun, t0, y0, t_bound, rtol=rtol, atol=atol,
                    first_step=None if first_step is None else min(float(first_step), t_bound - t0))
    events, max_events, event_dir = prepare_events(events)
    event_count = np.zeros(len(events))
    dirs = [float(d) for d in event_dir]
    K = solver.K
    A, B, C, E3, E5 = solver.A, solver.B, solver.C, solver.E3, solver.E5
    ybuf = np.empty(K.shape[1])  # every bound stage's input (stage), written by np.add as dy would be
    stages = [(K[:s].T, A[s][:s], float(C[s]), s, K[s], None if stage is None else stage(ybuf, K[s]))
              for s in range(1, len(C))]
    # the last stage f(t + h, y_new) bound to K[-1] as well: y_new is copied into the stage buffer,
    # and the accepted f is then that row (K[0] takes it once at the start of the next step)
    last = None if stage is None else stage(ybuf, K[-1])
    # every stage bound: the loop below with only what it reads (the products' methods bound once)
    bound_stages = ([(KsT.dot, a, bound) for KsT, a, _c, _s, _Ks, bound in stages]
                    if last is not None and all(st[-1] is not None for st in stages) else None)
    multiply, add, divide, maximum = np.multiply, np.add, np.divide, np.maximum
    # work arrays of the bound stages' increments and of the error norm, written by the products'
    # and ufuncs' out= (the same routines as the temporaries SciPy makes)
    dybuf, scale, err5, err3 = np.empty(K.shape[1]), np.empty(K.shape[1]), np.empty(K.shape[1]), np.empty(K.shape[1])
    KbT, KT = K[:-1].T, K.T
    rtol, atol = solver.rtol, solver.atol
    rtol_arr = np.array(rtol)
    expo = solver.error_exponent
    nscale = float(solver.n)
    t, y, f, h_abs = solver.t, solver.y, solver.f, float(solver.h_abs)
    t_old, y_old = t, y
    if values is None:
        def values(t, y):
            return [event(t, y) for event in events]
    g = values(t, y)
    abs_y = np.abs(y)
    ts, ys = ([t], [y]) if keep_states else (None, None)
    t_events = [[] for _ in events]
    y_events = [[] for _ in events]
    calls = 0
    steps = 0
    status = None
    message = None
    # turns whose slopes are all components of the state derivative (an int j: f[j]), read together
    columns = None
    if turns and all(isinstance(sl, (int, np.integer)) for _i, sl in turns):
        columns = (np.array([i for i, _ in turns], dtype=np.intp), np.array([sl for _, sl in turns], dtype=np.intp),
                   np.array([dirs[i] for i, _ in turns]))
    # the crossings (_crossing) and which are armed (+1 to rise through 0, -1 to fall; _arm)
    cross = [_crossing(c) for c in crossings]
    armed = [0] * len(cross)
    _arm(armed, cross, y)
    while status is None:
        # OdeSolver.step -> RungeKutta._step_impl (direction +1, max_step inf)
        min_step = 10 * abs(nextafter(t, inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        K[0] = f  # no stage writes K[0]; a rejected attempt leaves it as it was
        while True:
            if h_abs < min_step:
                status, message = -1, solver.TOO_SMALL_STEP
                break
            t_new = t + h_abs
            if t_new - t_bound > 0:
                t_new = t_bound
            h = t_new - t
            h_abs = abs(h)
            h_arr = np.array(h)  # a 0-d array multiplies as the float does, without converting it each time
            # rk_step: each stage's input y + (K[:s]ᵀ a_s) h, built in one buffer
            if bound_stages is not None:
                for dot, a, bound in bound_stages:
                    dot(a, out=dybuf)
                    multiply(dybuf, h_arr, dybuf)  # out positional: the same loop, without parsing a keyword
                    add(y, dybuf, ybuf)
                    bound()
            else:
                for KsT, a, c, s, Ks, bound in stages:
                    dy = KsT.dot(a)  # np.dot's own routine, without its dispatcher
                    np.multiply(dy, h_arr, out=dy)
                    if bound is not None:
                        np.add(y, dy, out=ybuf)
                        bound()
                    elif into:
                        fun(t + c * h, np.add(y, dy, out=dy), Ks)
                    else:
                        K[s] = fun(t + c * h, np.add(y, dy, out=dy))
            dy = KbT.dot(B)
            np.multiply(h_arr, dy, out=dy)
            y_new = np.add(y, dy, out=dy)
            if last is not None:
                ybuf[...] = y_new
                last()
                f_new = K[-1]  # read (as K[0], and by the dense output) before the next attempt writes it
            else:
                f_new = fun(t + h, y_new)
                K[-1] = f_new
            calls += len(stages) + 1
            # DOP853._estimate_error_norm (|y| kept from the step that accepted y)
            abs_new = np.abs(y_new)
            maximum(abs_y, abs_new, out=scale)
            multiply(scale, rtol_arr, scale)
            add(atol, scale, scale)
            KT.dot(E5, err5)
            divide(err5, scale, err5)
            KT.dot(E3, err3)
            divide(err3, scale, err3)
            e5 = sqrt(err5.dot(err5)) ** 2  # math.sqrt reads the NumPy float as float() would
            e3 = sqrt(err3.dot(err3)) ** 2
            if e5 == 0 and e3 == 0:
                error_norm = 0.0
            else:
                error_norm = abs(h) * e5 / sqrt((e5 + 0.01 * e3) * nscale)
            if error_norm < 1:
                factor = 10.0 if error_norm == 0 else min(10, 0.9 * error_norm ** expo)
                if rejected:
                    factor = min(1, factor)
                h_abs *= factor
                break
            h_abs *= max(0.2, 0.9 * error_norm ** expo)
            rejected = True
        if status == -1:
            break
        steps += 1
        t_old, y_old = t, y
        t, y, f, abs_y = t_new, y_new, f_new, abs_new
        if crossings:
            cut = _cut_at_crossing(fun, solver, cross, armed, t_old, t, y_old, y, f, h, rtol, atol, events, into,
                                   values, stage, turns)
            if cut is not None:
                # the step ends at the crossing (or at a terminal event before it): the finer run's
                # state, events and status
                t, y, fine = cut
                calls += fine.nfev + 1
                steps += fine.steps
                f = fun(t, y, None) if into else fun(t, y)
                abs_y = np.abs(y)
                for e, (te, ye) in enumerate(zip(fine.t_events, fine.y_events)):
                    t_events[e] += te.tolist()
                    y_events[e] += list(ye)
                if fine.status == 1:
                    status = 1
                if keep_states:
                    ts.append(t)
                    ys.append(y)
                g = values(t, y)
                continue
        if t - t_bound >= 0:
            status = 0
        if keep_states:
            ts.append(t)
            ys.append(y)
        g_new = values(t, y)
        # (K[0] holds the derivative at t_old: no stage writes it)
        excursions = (_excursions(turns, events, dirs, g, g_new, K[0], f,
                                  lambda: _dense_output(solver, t_old, t, y_old, y, f, h), columns) if turns else ())
        # SciPy's find_active_events: up (a <= 0 <= b) for d > 0, down (a >= 0 >= b) for d < 0,
        # either for d == 0; one plain loop (no comprehension to call at every step)
        active = []
        i = 0
        for a, b, d in zip(g, g_new, dirs):
            if (d >= 0 and a <= 0 and b >= 0) or (d <= 0 and a >= 0 and b <= 0):
                active.append(i)
            i += 1
        if excursions or active:
            if excursions:
                # an event's two crossings inside the step (turns): its first crossing is a root beside
                # the active events' own, and SciPy's rule (the first terminal root ends) applies to all
                sol, extra, extra_roots = excursions
                active = [i for i in active if i not in extra]
                event_count[np.array(active + extra, dtype=np.intp)] += 1
                root_indices, roots, terminate = _handle_with(sol, events, np.array(active, dtype=np.intp), extra,
                                                              extra_roots, event_count, max_events, t_old, t)
            else:
                # SciPy's dense output and event handling, on the solver's own state
                sol = _dense_output(solver, t_old, t, y_old, y, f, h)
                active = np.array(active, dtype=np.intp)
                event_count[active] += 1
                root_indices, roots, terminate = handle_events(sol, events, active, event_count, max_events, t_old, t)
            for e, te in zip(root_indices, roots):
                t_events[e].append(te)
                y_events[e].append(sol(te))
            if terminate:
                status = 1
                t = roots[-1]
                y = sol(t)
                if keep_states:
                    ts[-1], ys[-1] = t, y
        g = g_new
    run = _Run()
    run.status = status
    run.message = message if status == -1 else ("A termination event occurred." if status == 1 else
                                                 "The solver successfully reached the end of the integration "
                                                 "interval.")
    run.nfev = solver.nfev + calls
    run.steps = steps
    run.y_last = y
    run.t_prev, run.y_prev = t_old, y_old
    run.h_abs = h_abs
    run.t = np.array(ts) if keep_states else None
    run.y = np.vstack(ys).T if keep_states else None
    run.t_events = [np.asarray(te) for te in t_events]
    run.y_events = [np.asarray(ye) for ye in y_events]
    return run


def _crossing(spec):
    """One of :func:`_dop853`'s ``crossings`` as ``(value, floor, gate, index)``: ``(i, floor)``, a gap
    ``y[i]`` (set to 0 at its roots), or ``(row, floor, gate)`` / ``(row, floor, gate, offset)``, the
    linear function ``row · y`` (plus ``offset``: affine), counted only where ``y[gate] < 0`` at both
    ends of the step.

    >>> value, floor, gate, index = _crossing((np.array([0.0, -2.0]), 1e-14, 0, 1.0))
    >>> value(np.array([-1.0, 0.25])), gate, index
    (0.5, 0, None)
    """
    if len(spec) == 2:
        i, floor = spec
        return (lambda y, i=int(i): y.item(i)), float(floor), None, int(i)
    row, floor, gate, *offset = spec
    dot = np.asarray(row, float).dot
    if offset:
        off = float(offset[0])
        return (lambda y: off + float(dot(y))), float(floor), int(gate), None
    return (lambda y: float(dot(y))), float(floor), int(gate), None


def _cut_at_crossing(fun, solver, cross, armed, t_old, t, y_old, y, f, h, rtol, atol, events, into, values, stage,
                     turns):
    """:func:`_dop853`'s ``crossings`` (``cross``, made by :func:`_crossing`) for the accepted step
    ``[t_old, t]``: ``None`` where no armed value crosses 0 in it (the arming updated from ``y``), else
    ``(t_end, y_end, fine)``, the step taken again from ``t_old`` to the first crossing's root at the
    finer tolerance (``fine``, its events with it; ``t_end`` its last time: the root, or a terminal
    event's root before it), a gap set to 0 there and the crossing disarmed. ``armed[n]`` is +1
    (armed to rise through 0: below ``−floor`` at an accepted state), −1 (to fall: above ``floor``)
    or 0."""
    first, first_root = None, None
    sol = None
    for n, (val, _fl, gate, _i) in enumerate(cross):
        if not armed[n]:
            continue
        a, b = val(y_old), val(y)
        if not ((armed[n] > 0 and a < 0.0 <= b) or (armed[n] < 0 and a > 0.0 >= b)):
            continue
        if gate is not None and not (y_old.item(gate) < 0.0 and y.item(gate) < 0.0):
            continue
        if sol is None:
            sol = _dense_output(solver, t_old, t, y_old, y, f, h)
        root = solve_event_equation(lambda _t, yy, val=val: val(yy), sol, t_old, t)
        if first_root is None or root < first_root:
            first, first_root = n, root
    if first is None or not first_root > t_old:
        _arm(armed, cross, y)
        if first is not None:
            armed[first] = 0  # (its root at the step's start: nothing to take again)
        return None
    fine = _finer(fun, t_old, first_root, y_old, rtol, atol, events, into=into, values=values, stage=stage,
                  turns=turns)
    if fine.status not in (0, 1):
        return None  # pragma: no cover - the finer run failed: the step stays as it was
    y_end = fine.y_last.copy()
    t_end = float(first_root)
    if fine.status == 1:
        t_end = float(max(te[-1] for te in fine.t_events if len(te)))
    else:
        if cross[first][3] is not None:
            y_end[cross[first][3]] = 0.0
        armed[first] = 0
    _arm(armed, cross, y_end)
    return t_end, y_end, fine


def _arm(armed, cross, y):
    """Arm the crossings of :func:`_cut_at_crossing` that ``y`` puts beyond their floor: to rise (+1)
    below ``−floor``, to fall (−1) above ``floor``."""
    for n, (val, fl, _gate, _i) in enumerate(cross):
        x = val(y)
        if x < -fl:
            armed[n] = 1
        elif x > fl:
            armed[n] = -1


#: the points of [0, 1] at which an event is read off a step's dense output (a polynomial of degree 7
#: in the step fraction for DOP853) to fit it exactly and find its extremum: Chebyshev–Lobatto
_EXCURSION_NODES = 0.5 - 0.5 * np.cos(np.pi * np.arange(8) / 7)


def _dense_output(solver, t_old, t, y_old, y, f, h):
    """SciPy's dense output of the step ``[t_old, t]``, made by the solver on that step's state."""
    solver.t_old, solver.t, solver.y_old, solver.y, solver.f, solver.h_previous = t_old, t, y_old, y, f, h
    return solver.dense_output()


def _excursions(turns, events, dirs, g, g_new, f_old, f, dense, columns=None):
    """The turns of :func:`_dop853` that cross 0 twice inside the step whose event values are ``g``
    and ``g_new`` at its ends and whose state derivatives are ``f_old`` and ``f``: ``()`` if none,
    else ``(sol, indices, roots)`` with the step's dense output (``dense()``, made only when a turn
    needs it) and each first crossing. With ``columns`` (``(events, components, directions)`` as
    arrays, which :func:`_dop853` makes when every slope is a component ``j`` of the state
    derivative) the ends are tested for all turns in one pass: the same tests on the same floats (a
    product ``d · a`` of float64 numbers rounds as NumPy's does), the turns that pass them in the
    same order."""
    if columns is None:
        candidates = []
        for i, slope in turns:
            d, a, b = dirs[i], g[i], g_new[i]
            if not (d * a < 0.0 and d * b < 0.0):
                continue  # a crossing SciPy sees, or a value already past 0
            s0, s1 = slope(f_old), slope(f)
            if not (d * s0 > 0.0 and d * s1 < 0.0):
                continue  # no turn towards 0 and back that the end slopes reveal
            candidates.append((i, d))
    else:
        ti, tj, td = columns
        m = (td * np.array(g)[ti] < 0.0) & (td * np.array(g_new)[ti] < 0.0)
        if not m.any():
            return ()
        m &= (td * f_old[tj] > 0.0) & (td * f[tj] < 0.0)
        candidates = [(int(ti[pos]), float(td[pos])) for pos in np.flatnonzero(m).tolist()]
    found, roots, sol = [], [], None
    for i, d in candidates:
        if sol is None:
            sol = dense()
        root = _excursion_root(events[i], d, sol, sol.t_old, sol.t)
        if root is not None:
            found.append(i)
            roots.append(root)
    return (sol, found, roots) if found else ()


def _excursion_root(event, d, sol, t_old, t):
    """The first crossing of 0 in direction ``d`` of ``event`` along the dense output ``sol`` on
    ``[t_old, t]``, where the event has the sign ``−d`` at both ends and turns inside; ``None``
    when its extremum stays short of 0.

    The event along the step is fitted by a polynomial of degree 7 through 8 Chebyshev–Lobatto
    points (the dense output is one, and the event is linear in the state for LZB's turns: the fit
    is exact up to rounding); the extremum is the root of its derivative inside the step where the
    event is furthest in direction ``d``, read off ``sol`` itself; the crossing is found between
    ``t_old`` and it by SciPy's own ``solve_event_equation`` (``brentq``).

    >>> sol = lambda t: np.array([1e-3 - (t - 0.5) ** 2])   # rises through 0 and back inside [0, 1]
    >>> ev = lambda t, y: y[0]
    >>> round(_excursion_root(ev, 1.0, sol, 0.0, 1.0), 6), _excursion_root(lambda t, y: y[0] - 1, 1.0, sol, 0.0, 1.0)
    (0.468377, None)
    """
    h = t - t_old
    ts = t_old + h * _EXCURSION_NODES
    vals = np.array([event(x, sol(x)) for x in ts])
    if not np.all(np.isfinite(vals)):
        return None  # a non-finite dense output: no turn is read off it (the step's own values decide)
    poly = np.polynomial.Polynomial.fit(_EXCURSION_NODES, vals, 7, domain=[0.0, 1.0], window=[0.0, 1.0])
    best, best_t = -inf, None
    for r in poly.deriv().roots():
        if abs(r.imag) > 1e-9 or not 0.0 < r.real < 1.0:
            continue
        tc = t_old + h * float(r.real)
        val = d * event(tc, sol(tc))
        if val > best:
            best, best_t = val, tc
    if best_t is None or best < 0.0:
        return None
    if best == 0.0:
        return best_t
    return solve_event_equation(event, sol, t_old, best_t)


def _handle_with(sol, events, active, extra, extra_roots, event_count, max_events, t_old, t):
    """SciPy's ``handle_events`` for the ``active`` events plus the ``extra`` ones whose roots
    (``extra_roots``) were found already (:func:`_excursions`): the roots in time order, up to the
    first of an event that has reached its ``max_events`` (then ``terminate``)."""
    roots = [solve_event_equation(events[i], sol, t_old, t) for i in active]
    idx = np.concatenate([active, np.array(extra, dtype=np.intp)])
    roots = np.concatenate([np.asarray(roots, dtype=float), np.asarray(extra_roots, dtype=float)])
    order = np.argsort(roots, kind="stable")
    idx, roots = idx[order], roots[order]
    ends = np.nonzero(event_count[idx] >= max_events[idx])[0]
    if len(ends):
        return idx[:ends[0] + 1], roots[:ends[0] + 1], True
    return idx, roots, False


def _in_units(rhs, bind, unit: float):
    """``rhs`` and ``bind`` (a right-hand side in ``x`` and its bound stages, for :func:`_dop853`) for
    the independent variable ``x / unit``: every derivative times ``unit``, a power of two, so the
    products are exact and the steps the same as in ``x``. LZB's segments use it for ``P_p``, the
    time-domain laws for ``t``: SciPy locates an event's root to an absolute ``4·EPS`` in the
    independent variable, which is coarse once that variable's scale is far below one (and far
    above one, the error norm's squares of derivative over scale underflow)."""

    def fun(P, y, out=None):
        out = rhs(P, y, out)
        np.multiply(out, unit, out=out)
        return out

    def stage_of(y, out):
        stage = bind(y, out)
        if stage is None:
            return None
        multiply = np.multiply

        def scaled():
            stage()
            multiply(out, unit, out)

        return scaled

    return fun, stage_of


def _unit_near(x: float) -> float:
    """The unit :func:`_in_units` counts an independent variable of scale ``x`` in: 1 for ``x`` in
    ``[2⁻¹⁰, 2¹⁰]`` (or not positive), so that those scales integrate exactly as without it, else
    the power of two at or below ``x``.

    >>> _unit_near(3.0), _unit_near(1e-30) == 2.0 ** -100, _unit_near(5000.0)
    (1.0, True, 4096.0)
    """
    if not x > 0 or 2.0 ** -10 <= x <= 2.0 ** 10:
        return 1.0
    return 2.0 ** math.floor(math.log2(x))


def _speed_scales(Minv, T0: float):
    """Each coordinate's speed scale ``√(2T⁻)·√((M⁻¹)_jj)``: a bound on ``|v_j|`` while the kinetic
    energy does not grow above ``T⁻`` (Cauchy–Schwarz in the kinetic metric), in the coordinate's own
    units. The integrating laws' absolute tolerances on the speeds (the fastest approach ``(H v)_i``
    is in the rows' units: with rows of H at 1e30 it was 1e30 too coarse). A product of roots:
    ``2T⁻(M⁻¹)_jj`` underflowed to 0 at ``T⁻ ~ 1e-243`` with masses of 1e85, where each root is a
    normal float, and the zero tolerance hung the run.

    >>> _speed_scales(np.diag([1.0, 0.25]), 2.0).tolist()
    [2.0, 1.0]
    """
    return sqrt(2.0 * T0) * np.sqrt(np.diag(Minv))


def float_system(M, H, v):
    """``M`` (symmetric positive definite), ``H`` (k×n, no zero row) and ``v`` (n) as checked
    float arrays, for the integrating laws (compliant and LZB); errors name the argument.

    >>> float_system([[1, 0], [0, 2]], [0, 1], [1, 0])[1].tolist()
    [[0.0, 1.0]]
    """
    try:
        Mf = np.array(M, dtype=float)
        Hf = np.array(H, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ImpactInputError("M/H", f"must be numeric matrices ({exc})") from None
    if Mf.ndim != 2 or Mf.shape[0] != Mf.shape[1]:
        raise ImpactInputError("M", f"must be square, got shape {Mf.shape}")
    n = Mf.shape[0]
    if Hf.ndim == 1:
        Hf = Hf.reshape(1, -1)
    if Hf.ndim != 2 or Hf.shape[1] != n:
        raise ImpactInputError("H", f"must have {n} columns, got shape {Hf.shape}")
    if not (np.all(np.isfinite(Mf)) and np.all(np.isfinite(Hf))):
        raise ImpactInputError("M/H", "contain NaN or inf")
    if not np.allclose(Mf, Mf.T, rtol=1e-12, atol=0):
        raise ImpactInputError("M", "must be symmetric")
    try:
        np.linalg.cholesky(Mf)
    except np.linalg.LinAlgError:
        raise ImpactInputError("M", "must be positive definite") from None
    if np.any(np.all(Hf == 0, axis=1)):
        raise ImpactInputError("H", "has a zero row")
    v0 = _vec(v, n, "v")
    return Mf, Hf, v0


def _kinetic_energy_in_range(Mf, v0, energy_range, integration: str) -> float:
    """``T⁻ = ½ v⁻ᵀ M v⁻``, refused by name (``ImpactInputError`` on ``v``) outside ``energy_range``,
    the energies where ``integration`` stays inside float64 (computed without a warning where it
    overflows or underflows: it is refused then).

    >>> _kinetic_energy_in_range(np.eye(1), np.array([2.0]), (1e-300, 1e300), "this")
    2.0
    """
    with np.errstate(over="ignore", under="ignore"):
        T0 = 0.5 * float(v0 @ Mf @ v0)
    if not energy_range[0] <= T0 <= energy_range[1]:
        raise ImpactInputError("v", f"the kinetic energy T- = {T0:.3g} is outside [{energy_range[0]:g}, "
                                    f"{energy_range[1]:g}], where {integration} works: rescale the units "
                                    "(the outcome relative to the speeds does not depend on them)")
    return T0


def _contact_scales_in_range(Mf, Hf, integration: str) -> None:
    """Refuse by name (``ImpactInputError`` on ``gradients``) a system with an effective mass
    ``μ_i = 1/(H_i M⁻¹ H_iᵀ)`` outside :data:`SCALE_RANGE` (a row far from the scale of M),
    computed without a warning where it overflows or underflows (refused then).

    >>> _contact_scales_in_range(np.eye(1), np.array([[1e-160]]), "this")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: gradients: row 1's effective mass 1/(H_i M^-1 H_i^T) = inf is outside ...
    """
    lo, hi = SCALE_RANGE
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        mu = 1.0 / np.einsum("ij,ji->i", Hf, np.linalg.solve(Mf, Hf.T))
    out = ~((mu >= lo) & (mu <= hi))
    if np.any(out):
        i = int(np.argmax(out))
        raise ImpactInputError("gradients", f"row {i + 1}'s effective mass 1/(H_i M^-1 H_i^T) = {mu[i]:.3g} is "
                                            f"outside [{lo:g}, {hi:g}], where {integration} works: rescale the "
                                            "units of M or of that row")


def _vec(x, n, name):
    try:
        arr = np.asarray(x, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise ImpactInputError(name, f"must be numbers ({exc})") from None
    if arr.shape[0] != n:
        raise ImpactInputError(name, f"expected {n} values, got {arr.shape[0]}")
    if not np.all(np.isfinite(arr)):
        raise ImpactInputError(name, "contains NaN or inf")
    return arr


def _per_contact(x, k, name, default=None):
    if x is None:
        return np.full(k, default, dtype=float)
    if np.ndim(x) == 0:
        return _vec([x] * k, k, name)
    return _vec(x, k, name)


def hunt_crossley_restitution(x: float) -> float:
    """Restitution ``e`` of one Hunt–Crossley contact with ``x = D u`` (damping × impact speed).

    Solves ``x − ln(1 + x) = −e x − ln(1 − e x)`` for ``e ∈ (0, 1]`` (``e = 1`` at ``x = 0``);
    independent of the stiffness, the exponent and the masses (see the module docstring).

    Examples
    --------
    >>> round(hunt_crossley_restitution(0.0), 12), round(hunt_crossley_restitution(0.3), 6)
    (1.0, 0.83287)
    """
    x = float(x)
    if not np.isfinite(x) or x < 0:
        raise ImpactInputError("x", f"must be a finite number >= 0, got {x}")
    if x == 0:
        return 1.0
    lhs = x - np.log1p(x)
    # h(e) = -e x - ln(1 - e x) increases from 0 (e = 0) to +inf (e -> 1/x when x > 1)
    hi = 1.0 if x < 1 else (1.0 - 1e-15) / x
    return float(brentq(lambda e: -e * x - np.log1p(-e * x) - lhs, 0.0, hi, xtol=1e-16))


def hunt_crossley_damping(e: float, impact_speed: float) -> float:
    """The Hunt–Crossley damping ``D`` that gives the restitution ``e`` at the impact speed ``u``.

    Parameters
    ----------
    e : restitution, ``0 < e ≤ 1``
    impact_speed : relative normal speed at first contact, ``u > 0``

    Returns
    -------
    float ``D = x/u`` with ``x`` the root of ``x − ln(1 + x) = −e x − ln(1 − e x)``.

    Examples
    --------
    >>> D = hunt_crossley_damping(0.8, 2.0)
    >>> round(D, 6), round(hunt_crossley_restitution(D * 2.0), 12)
    (0.186573, 0.8)
    """
    e, u = float(e), float(impact_speed)
    if not (0 < e <= 1):
        raise ImpactInputError("e", f"must satisfy 0 < e <= 1, got {e}")
    if not (np.isfinite(u) and u > 0):
        raise ImpactInputError("impact_speed", f"must be a finite number > 0, got {u}")
    if e == 1:
        return 0.0
    lo, hi = 0.0, 1.0
    while hunt_crossley_restitution(hi) > e:
        hi *= 2
        if hi > 1e12:  # pragma: no cover - e tiny
            raise ImpactInputError("e", f"too small to reach with Hunt–Crossley damping, got {e}")
    x = brentq(lambda x: hunt_crossley_restitution(x) - e, lo, hi, xtol=1e-16)
    return float(x / u)


def chain_matrices(masses, walls=()):
    """Mass matrix and contact rows of balls on a line, touching, with optional walls at the ends.

    Contacts, in order: the left wall (``φ = x_1 − w``, row ``+e_1``) if ``"left" in walls``, the
    ball pairs ``1-2, …, (n−1)-n`` (``φ = x_{i+1} − x_i``), the right wall (row ``−e_n``).

    Examples
    --------
    >>> M, H, names = chain_matrices([1, 2], walls=("right",))
    >>> H.tolist(), names
    ([[-1.0, 1.0], [0.0, -1.0]], ['1-2', '2-wall'])
    """
    m = _vec(masses, len(np.atleast_1d(masses)), "masses")
    if np.any(m <= 0):
        raise ImpactInputError("masses", "must be positive")
    for w in walls:
        if w not in WALLS:
            raise ImpactInputError("walls", f"each wall must be one of {WALLS}, got {w!r}")
    n = m.shape[0]
    rows, names = [], []
    if "left" in walls:
        r = np.zeros(n)
        r[0] = 1.0
        rows.append(r)
        names.append("wall-1")
    for i in range(n - 1):
        r = np.zeros(n)
        r[i], r[i + 1] = -1.0, 1.0
        rows.append(r)
        names.append(f"{i + 1}-{i + 2}")
    if "right" in walls:
        r = np.zeros(n)
        r[-1] = -1.0
        rows.append(r)
        names.append(f"{n}-wall")
    H = np.array(rows).reshape(len(rows), n)
    return np.diag(m), H, names


#: a step taken again (to an LZB release, to a compliant crossing) is taken at a hundredth of
#: ``rtol``, but no finer than this (SciPy's DOP853 takes no rtol below 100·eps)
REFINE_RTOL_FLOOR = 1e-13


def _finer(fun, t0, t1, y0, rtol, atol, events, **options):
    """:func:`_dop853` from ``t0`` to ``t1`` at ``rtol/100`` (floored at :data:`REFINE_RTOL_FLOOR`) and
    ``atol/100``, keeping no states: a step taken again where DOP853 underestimates its error."""
    return _dop853(fun, t0, t1, y0, max(rtol * 1e-2, REFINE_RTOL_FLOOR), atol * 1e-2, events, keep_states=False,
                   **options)


def _step_to_root_again(fun, sol, t_root, rtol, atol, stage):
    """The state at ``t_root``, a terminal event's root in ``sol``'s last step, from that step taken again
    from its start (``sol.t_prev``, ``sol.y_prev``) to the root at ``rtol/100`` (floored at
    :data:`REFINE_RTOL_FLOOR`) and ``atol/100``, with no events (none fired before the root).

    Used where a force reaches zero without being smooth (an LZB release, ``f_j ∝ s_j^η``): DOP853
    underestimates the error of the step to such a root (an LZB chain took one step from 4 % of
    ``s_j``'s largest value to the root and was 6e-10 off there at rtol = 1e-11). Returns
    ``(y, steps, nfev)``, ``y`` None where the root is the step's start or the integration failed
    (the caller keeps the dense output's state)."""
    if not t_root > sol.t_prev:
        return None, 0, 0
    fine = _finer(fun, sol.t_prev, t_root, sol.y_prev, rtol, atol, [], into=True, stage=stage)
    return (fine.y_last if fine.status == 0 else None), fine.steps, fine.nfev


def compliant_impact(M, H, v, stiffness, exponent=1.5, damping=None, *, hunt_crossley=None, gaps=None,
                     rtol: float = 1e-11, atol: float = 1e-14, max_events: int = 10_000, t_max: float | None = None,
                     rest_tol: float | None = None) -> CompliantResult:
    """Integrate a compliant multibody impact ``M q̈ = Hᵀ f(δ, δ̇)`` until it is over.

    Parameters
    ----------
    M : (n, n) symmetric positive definite mass matrix (SymPy matrices are converted to floats)
    H : (k, n) contact rows (``g = g⁰ + H q``); a wall is a row acting on one body only
        (each row's effective mass ``1/(H_i M⁻¹ H_iᵀ)`` must lie in :data:`SCALE_RANGE`,
        ``[1e-150, 1e150]``, else ``ImpactInputError`` on ``gradients``)
    v : (n,) pre-impact generalized velocity; its kinetic energy ``T⁻`` must lie in
        :data:`ENERGY_RANGE` (``[1e-305, 1e300]``), else ``ImpactInputError``; the outcome relative to
        the speeds does not depend on the units
    stiffness : ``K_i > 0``, one per contact (or one number for all)
    exponent : ``p_i ≥ 1`` per contact (or one number): 1.5 Hertz, 1 linear, any power
    damping : ``C_i ≥ 0`` of eq. 20 (``C δ^{p−1} δ̇``), per contact or one number (default 0)
    hunt_crossley : ``D_i ≥ 0`` of Hunt–Crossley (``K δ^p (1 + D δ̇)``); exclusive with ``damping``
    gaps : initial gaps ``g⁰_i ≥ 0`` (default 0: all contacts touching)
    rtol, atol : integrator tolerances; ``atol`` is relative to the problem's own scales (the
        gaps: the length ``V T``, with ``T`` the shortest contact time scale and ``V`` the fastest
        approach; speed ``j``: ``√(2T⁻(M⁻¹)_jj)``, which bounds it while the energy does not grow;
        the impulses: ``μ V``)
    max_events : cap on contact openings/closings (``NonTermination`` beyond)
    t_max : cap on the time (default none; the run is still bounded by ``max_events``)
    rest_tol : optional; stop when the mechanical energy falls below ``rest_tol · T⁻``

    Returns
    -------
    CompliantResult

    Raises
    ------
    ImpactInputError
        Shapes, NaN, non-positive stiffness, exponent < 1, negative damping or gap, both damping
        kinds, or no contact approaching.
    NonTermination
        More than ``max_events`` events, or ``t_max`` reached (a numerical safeguard; the message
        says whether the termination theorem applies).
    VerificationError
        The integration broke a proved fact (an impulse above its bound, the energy growing, the
        momentum balance off): raised instead of returning (``docs/compliant_termination.md``).

    Examples
    --------
    A ball hitting a wall (row ``−1``) through a linear spring: the velocity is reversed.

    >>> r = compliant_impact([[2.0]], [[-1.0]], [1.0], 8.0, exponent=1)
    >>> r.velocity.round(9).tolist(), round(float(r.impulses[0]), 9), r.outcome
    ([-1.0], 4.0, 'separated')
    """
    Mf, Hf, v0 = float_system(M, H, v)
    n, k = Mf.shape[0], Hf.shape[0]
    K = _per_contact(stiffness, k, "stiffness")
    p = _per_contact(exponent, k, "exponent")
    if np.any(K <= 0):
        raise ImpactInputError("stiffness", "must be positive")
    if np.any(p < 1):
        raise ImpactInputError("exponent", "must be >= 1 (the force must be continuous at first contact)")
    if damping is not None and hunt_crossley is not None:
        raise ImpactInputError("damping", "give either damping (eq. 20) or hunt_crossley, not both")
    C = _per_contact(damping, k, "damping", 0.0)
    D = _per_contact(hunt_crossley, k, "hunt_crossley", 0.0)
    if np.any(C < 0):
        raise ImpactInputError("damping", "must be non-negative")
    if np.any(D < 0):
        raise ImpactInputError("hunt_crossley", "must be non-negative")
    g0 = _per_contact(gaps, k, "gaps", 0.0)
    if np.any(g0 < 0):
        raise ImpactInputError("gaps", "must be non-negative (an overlapping start is not an impact)")
    w0 = Hf @ v0
    if not np.any(w0 < 0):
        raise ImpactInputError("v", "no contact approaches ((H v)_i < 0 for none): there is no impact")
    # (1e-150 kg at 1e-150 m/s: T- underflowed to 0 and the impulse bound with it; 1e150: inf, and a
    # NaN momentum balance; from 1e-102 to 1e100 the outcome is the unit problem's)
    T0 = _kinetic_energy_in_range(Mf, v0, ENERGY_RANGE, "the float64 integration")
    _contact_scales_in_range(Mf, Hf, "the float64 integration")
    if rest_tol is not None and not (rest_tol > 0):
        raise ImpactInputError("rest_tol", f"must be > 0, got {rest_tol}")

    from .termination import check_run, energy_tolerance, impulse_bounds, separating_direction

    # the theorem's hypothesis, decided exactly on the float rows (read at their binary values):
    # with a separating direction the impulses are bounded (checked below, during and after the run)
    # and an elastic run provably reaches the stopping condition (docs/compliant_termination.md)
    cert = separating_direction(Hf)
    bounds = impulse_bounds(Mf, Hf, v0, cert, verify=False)  # cert was verified by separating_direction
    elastic = (damping is None or not np.any(C > 0)) and (hunt_crossley is None or not np.any(D > 0))
    etol = energy_tolerance(rtol)
    theorem = ("" if cert.separating else
               f"; no separating direction ({cert.statement()}), so the termination theorem does not apply")

    def verify_window(y):
        # step 2 of the proof: the energy never grows and every impulse stays below its bound
        E = energy(y)
        if E > T0 * (1 + etol):
            raise VerificationError("compliant_impact", f"the energy rose to {E / T0:.12g} T- (> 1 + {etol:.3g}) at "
                                                        f"t = {t:g}: the integration failed")
        P = y[k + n:]
        fin = np.isfinite(bounds)
        over = fin & (P > bounds * (1 + etol))
        if np.any(over):
            i = int(np.argmax(over))
            raise VerificationError("compliant_impact", f"the impulse P_{i + 1} = {P[i]:.12g} at t = {t:g} exceeds its "
                                                        f"proved bound {bounds[i]:.12g} (step 2 of "
                                                        "docs/compliant_termination.md): the integration failed")

    Minv = np.linalg.inv(Mf)
    A = Minv @ Hf.T  # accelerations per unit contact force
    mu = 1.0 / np.einsum("ij,ji->i", Hf, A)  # effective mass of each contact
    V = float(np.max(-w0[w0 < 0]))
    Tc = (mu / (K * V ** (p - 1))) ** (1 / (p + 1))
    T = float(np.min(Tc))
    Lsc = V * T
    Psc = float(np.max(mu)) * V
    if t_max is None:
        t_max = np.inf
    max_windows = 100_000
    lin = np.all(p == 1)
    hc = hunt_crossley is not None

    pm1 = p - 1
    # a force that needs the mask δ > 0 (damping acts through δ̇); zero damping of either kind is none:
    # such a run is the elastic one, bit for bit (Hunt–Crossley with e = 1 is Hertz)
    masked = not elastic
    damped = masked and not hc  # eq. 20's damping (not zero)

    # The state is (g, q̇, P): the gaps, not q. Only the gaps enter the forces, and DOP853's error
    # control is relative to each component's size: with q the state, a gap (a difference of
    # coordinates that had flown for 200 contact times, |q| ~ 16 against gaps ~ 0.1) was kept to
    # rtol |q|, and a light ball ringing between two heavy ones ended 7e-6 off at rtol = 1e-11
    # (1e-7 at 1e-10, right at 1e-12). g' = H q̇ is the linearized gap's own derivative.
    # Called some 12 times per DOP853 step: the same float operations as the formula in the
    # docstring, without the rate of indentation where the force does not use it (elastic)
    zero_k = np.zeros(k)
    N = 2 * k + n
    i_v, i_p = k, k + n  # where q̇ and P start in the state

    # the +0.0 of δ⁺'s zeros is made by the power itself when no exponent is an odd integer
    # (IEEE pow(−0, p) = +0 for p > 0 not an odd integer; pow(±0, p) = ±0 for an odd one)
    canon = lin or bool(np.any((p % 2) == 1))

    # Contacts whose force law is held within a piece of the run (elastic runs only; the contacts
    # with an integer exponent): K (δ⁺)^p has a kink at δ = 0 (for p = 1, linear: the acceleration
    # jumps its slope) that DOP853's error estimate does not see, and stepped across it a scaled
    # sweep scene ended 1.8e-8 off at rtol = 1e-11 (1.9e-10 at 1e-10, right at 1e-12). Within a
    # piece a held contact keeps its law, K δ^p for every δ (a polynomial) if it is closed, 0 if
    # open, and its gap crossing 0 (opening or closing: a terminal event) ends the piece; a
    # crossing there and back inside one step is found on the dense output (_dop853's turns). The
    # law is held through the lower and upper clips of δ: δ⁺ = min(max(δ, lo), hi), lo = 0 and
    # hi = ∞ for the other contacts (max(δ, 0), as before), lo = −∞ for a held closed contact, and
    # hi = 0 for a held open one.
    held = np.zeros(k, dtype=bool) if masked else (p == np.floor(p))
    held_idx = np.flatnonzero(held).tolist()
    lo = np.zeros(k) if held_idx else zero_k
    hi = np.full(k, inf)

    def elastic_force(d, f):
        # f = K (δ⁺)^p into ``f``, from the indentations ``d`` (overwritten): rhs's elastic branch
        np.maximum(d, lo, out=d)
        if held_idx:
            np.minimum(d, hi, out=d)
        if canon:
            np.add(d, zero_k, out=d)
        if not lin:
            np.power(d, p, out=d)
        np.multiply(K, d, out=f)

    def rhs(_t, y, out=None):
        # (H q̇, M⁻¹Hᵀf, f) with f_i = where(δ_i > 0, force_i, 0), written into ``out`` (a row of the
        # stage table) or a new array; the operations that round are those of the formula in the
        # docstring on the same arrays (δ⁺ only matters where δ > 0, where it is δ)
        if out is None:
            out = np.zeros(N)
        elif masked:
            out[i_p:] = 0.0
        qd = y[i_v:i_p]
        Hf.dot(qd, out=out[:k])  # g' = H q̇
        d = np.negative(y[:k])  # the indentations δ = −g
        f = out[i_p:]
        if masked:
            pos = np.greater(d, zero_k)
            dp = np.maximum(d, zero_k)
            dpp = dp if lin else dp ** p
            if hc:
                ff = K * dpp * (1.0 + D * -out[:k])
            else:
                ff = K * dpp + C * (dp ** pm1 if not lin else (d > 0)) * -out[:k]
            np.copyto(f, np.maximum(ff, 0.0), where=pos)
        else:
            # elastic: f = K (δ⁺)^p without a mask (two ufuncs fewer, and no masked loop). Where
            # δ > 0 these are the masked product's operations on the same values; where δ <= 0, δ⁺
            # is a zero, made +0.0 (−0.0 + 0.0 is +0.0; np.maximum may keep either zero; without an
            # odd integer exponent the power does it: pow(±0, p) = +0), so (δ⁺)^p = +0.0 (p >= 1)
            # and K·(+0.0) = +0.0, the masked product's zero. (A NaN δ gives
            # NaN where the mask gave 0; it needs a non-finite stage already in the table, whose
            # step is rejected with the same step-size factor either way.)
            elastic_force(d, f)
        A.dot(f, out=out[i_v:i_p])  # the product into its place: the same BLAS call as A.dot(f)
        return out

    few = k <= 24
    Kl, Cl, Dl = K.tolist(), C.tolist(), D.tolist()
    unit_k = all(x == 1.0 for x in Kl)
    ones_l = [1.0] * k

    def masked_force(dl, ppl, pml, wl):
        # rhs's masked force for a few contacts as Python floats, contact by contact: the same IEEE
        # products and sums in the formula's order (δ⁺ is δ where δ > 0; a bool δ > 0 multiplies as
        # 1.0), +0.0 where δ <= 0 (or NaN); None where np.maximum(ff, 0.0) is not read off the sign
        # of ff (a zero, whose sign np.maximum's loops may pick either way, or a NaN): NumPy's path.
        # One loop over zipped lists per kind (no indexing, no comprehension)
        fl = []
        fa = fl.append
        if hc:
            for dj, x, pj, c, wj in zip(dl, Kl, ppl, Dl, wl):
                if dj > 0.0:
                    ff = x * pj * (1.0 + c * -wj)
                    if ff > 0.0:
                        fa(ff)
                    elif ff < 0.0:
                        fa(0.0)
                    else:
                        return None
                else:
                    fa(0.0)
            return fl
        for dj, x, pj, c, mj, wj in zip(dl, Kl, ppl, Cl, ones_l if lin else pml, wl):
            if dj > 0.0:
                ff = x * pj + c * mj * -wj
                if ff > 0.0:
                    fa(ff)
                elif ff < 0.0:
                    fa(0.0)
                else:
                    return None
            else:
                fa(0.0)
        return fl

    def bind(y, out):
        # rhs(t, y, out) for the contents of the driver's stage buffer y: the same operations on the
        # same values (the products written into their places by the same BLAS calls), with the views
        # and work arrays made once per integration; masked (damped, Hunt–Crossley), for a few
        # contacts, with the per-contact arithmetic of masked_force (rhs itself where that declines)
        if masked and not few:
            return None
        g, qd = y[:k], y[i_v:i_p]
        o_g, o_v, f = out[:k], out[i_v:i_p], out[i_p:]
        maximum, minimum, add, power, multiply, negative = (np.maximum, np.minimum, np.add, np.power, np.multiply,
                                                            np.negative)

        if not masked:
            d = np.empty(k)
            # elastic_force inlined, its last product into ``f`` dropped when every K_i is 1.0
            # (1.0 · x is x, bit for bit: the same +0.0 where δ <= 0 and the same powers elsewhere)
            dk = f if unit_k else d

            def stage():
                Hf.dot(qd, o_g)
                negative(g, d)
                maximum(d, lo, out=d)
                if held_idx:
                    minimum(d, hi, out=d)
                if lin:
                    add(d, zero_k, dk)
                else:
                    if canon:
                        add(d, zero_k, d)
                    power(d, p, out=dk)
                if not unit_k:
                    multiply(K, d, f)
                A.dot(f, o_v)

            return stage

        # δ, (δ⁺)^p, δ̇-rate and (δ⁺)^(p−1) side by side in one work array, read by one tolist
        work = np.empty(4 * k)
        d, dpp, w, dpm1 = work[:k], work[k:2 * k], work[2 * k:3 * k], work[3 * k:]
        dp = dpp if lin else np.empty(k)
        pml = hc or lin  # no (δ⁺)^(p−1) read

        def stage():
            negative(g, d)
            maximum(d, zero_k, out=dp)
            if not lin:
                power(dp, p, out=dpp)
            if not pml:
                power(dp, pm1, out=dpm1)
            Hf.dot(qd, w)
            wl = work.tolist()
            fl = masked_force(wl[:k], wl[k:2 * k], None if pml else wl[3 * k:], wl[2 * k:3 * k])
            if fl is None:
                rhs(None, y, out)
                return
            o_g[...] = w
            f[...] = fl
            A.dot(f, o_v)

        return stage

    def stop(_t, y):
        g = y[:k] / Lsc
        w = (Hf @ y[i_v:i_p]) / V + SEPARATION_EPS
        return float(np.minimum(g, w).min())

    stop.terminal = True
    stop.direction = 1
    events = [stop]

    def stop_value(_t, y):
        # stop's value at an accepted state, its float operations contact by contact in Python
        # floats (the same matrix products): min(g_i / L, w_i / V + ε) is one of those values, the
        # one np.minimum's reduction gives (a NaN, which the reduction would give, goes to stop)
        # (Hf.dot is Hf @'s BLAS routine at half the call cost, the same products but for the sign
        # of a zero, which only the signs read here do not see: 120000 random rows and states checked)
        gl = y[:k].tolist()
        wl = Hf.dot(y[i_v:i_p]).tolist()
        # (one loop: the smallest value, the first of equal ones as min() takes it; a NaN goes to stop)
        m = inf
        for b in gl:
            x = b / Lsc
            if x < m:
                m = x
            elif x != x:
                return stop(_t, y)
        for w in wl:
            x = w / V + SEPARATION_EPS
            if x < m:
                m = x
            elif x != x:
                return stop(_t, y)
        return m

    def energy(y):
        qd = y[i_v:i_p]
        dp = np.maximum(-y[:k], 0.0)
        return 0.5 * float(qd @ Mf @ qd) + float(np.sum(K * dp ** (p + 1) / (p + 1)))

    if rest_tol is not None:
        def rest(_t, y):
            return energy(y) / T0 - rest_tol

        rest.terminal = True
        rest.direction = -1
        events.append(rest)

    # one terminal event per held contact: its gap g_j / L crossing the edge of the band ±atol (the
    # gaps' absolute tolerance, in units of L) beyond the 0 of the law held, rising through +atol (an
    # opening) while it is held closed, falling through −atol (a closing) while held open (the
    # direction and ``offset`` are set for each piece). Watched at 0, the gaps ahead of a wave, 1e-35
    # to 1e-323 whose signs rounding decides, ended a piece at each flicker: a 10-ball chain of
    # exponent 2 counted 58 events for 18 crossings, and a 64-ball one took 5,535 pieces. Within the
    # band the law held differs from K (δ⁺)^p by at most K (atol L)^p, which the tolerance already
    # allows. A value of exactly 0 reads as not crossed (−direction; as LZB's activation): SciPy
    # counts a zero at a step's start as a crossing either way (two strikers of a cradle, touching
    # without relative speed, read 0 at each restart when the event was at 0, and ended each piece
    # there, for ever)
    def gap_event(j):
        def gap(_t, y):
            x = y.item(j) / Lsc - gap.offset
            return x if x != 0.0 else -gap.direction

        gap.terminal = True
        gap.direction = -1.0
        gap.offset = -atol
        return gap

    first_gap = len(events)
    gaps_ev = [gap_event(j) for j in held_idx]
    events += gaps_ev
    # each gap's slope is its own derivative, g_j' = (H q̇)_j, a component of the state derivative
    turns = [(first_gap + i, j) for i, j in enumerate(held_idx)]
    # the gap events' offsets and directions side by side (hold sets them with the events'), so that
    # values reads every gap event at once: the same division and subtraction as gap's, and its
    # -direction for an exact 0
    held_arr = np.array(held_idx, dtype=np.intp)
    gap_off, gap_dir = np.full(len(held_idx), -atol), np.full(len(held_idx), -1.0)

    def values(t, y):
        out = [stop_value(t, y)]
        if rest_tol is not None:
            out.append(rest(t, y))
        if gaps_ev:
            x = y[held_arr] / Lsc
            x -= gap_off
            out += np.where(x != 0.0, x, -gap_dir).tolist()
        return out

    def hold(y, laws):
        # each held contact's law for the piece that starts at y, read off its gap: closed where the
        # gap is below the band ±atol·L of the events (above), open where it is above it, and within
        # it as ``laws`` (True: closed) say, the last piece's laws with the crossing that ended it
        # applied: the contact whose crossing ended the last piece sits at the band's edge (set so),
        # and one resting at 0 (touching, without relative speed: the two strikers of a cradle) stays
        # open until its gap falls through −atol·L. A gap beyond the band on the far side of its law
        # is a crossing the last piece did not end at: held as it was, that contact would never be
        # seen crossing. With ``laws`` None (at the start and after a jump of free flight) a contact
        # is closed where its gap is below 0 or it is 0 and approaching
        w = Hf.dot(y[i_v:i_p]) if laws is None else None
        out = []
        band = atol * Lsc
        for i, (ev, j) in enumerate(zip(gaps_ev, held_idx)):
            gj = y[j]
            if laws is None:
                c = bool(gj < 0 or (gj == 0 and w[j] < 0))
            else:
                c = bool(gj < -band or (-band <= gj <= band and laws[i]))
            lo[j], hi[j], ev.direction = (-inf, inf, 1.0) if c else (0.0, 0.0, -1.0)
            ev.offset = ev.direction * atol
            gap_off[i], gap_dir[i] = ev.offset, ev.direction
            out.append(c)
        return out

    # the gaps in units of V T (the state integrates them, not q), each speed in its own scale
    atol_vec = atol * np.concatenate([np.full(k, Lsc), _speed_scales(Minv, T0), np.full(k, Psc)])
    # time in units of a power of two near T when T is far from 1 (exact: the same steps, scaled):
    # SciPy places an event's root to an absolute 4·EPS in t, so with T ~ 1e-30 (rows of H at 1e30
    # against K of order one) the separation was placed anywhere in a step and the outcome was 7e-9
    # off; every T in [2^-10, 2^10] integrates exactly as before
    unit = _unit_near(T)
    fun, stage_of = (rhs, bind) if unit == 1.0 else _in_units(rhs, bind, unit)
    # the steps that end at a crossing (_dop853's crossings), armed once the gap is beyond its absolute
    # tolerance: every contact that is not held (elastic with a non-integer exponent, Hunt–Crossley,
    # whose force starts and stops at the gap's 0 too, and eq. 20's damping)
    crossings = [(j, float(atol_vec[j])) for j in range(k) if not held[j]]
    if damped:
        # and eq. 20's φ_j = K_j δ_j + C_j δ̇_j crossing 0 while δ_j > 0: its force δ^(p−1) φ_j, kept
        # >= 0, stops there before the gap opens (and starts again if φ_j rises). φ_j = −K_j g_j −
        # C_j (H q̇)_j is linear in the state; its floor atol (K_j L + C_j V). Ending the steps at the
        # gaps alone made 30 random chains worse (median 5e-11 -> 9e-11 off the damped piecewise
        # reference); at both, the worst of 150 went from 1.1e-8 to 4.9e-10
        for j in range(k):
            row = np.zeros(N)
            row[j] = -K[j]
            row[i_v:i_p] = -C[j] * Hf[j]
            crossings.append((row, float(atol * (K[j] * Lsc + C[j] * V)), j))
    if hc:
        # and Hunt–Crossley's ψ_j = 1 + D_j δ̇_j = 1 − D_j (H q̇)_j crossing 0 while δ_j > 0: its force
        # K δ^p ψ_j, kept >= 0, stops there before the gap opens (a contact pulled open faster than
        # 1/D_j by the others' forces, where W has an entry > 0 off its diagonal: never in a chain,
        # where ψ_j = 0 is invariant). Affine in the state; its floor atol (1 + D_j V). On 159 random
        # 3-body systems (D in [0.5, 8]; 31 of them clamp), the worst of the clamped ones against the
        # piecewise reference (which ends its pieces there) went from 2.9e-10 to 1.3e-11 (measured)
        for j in range(k):
            if D[j] > 0.0:
                row = np.zeros(N)
                row[i_v:i_p] = -D[j] * Hf[j]
                crossings.append((row, float(atol * (1.0 + D[j] * V)), j, 1.0))
    y = np.concatenate([g0, v0, np.zeros(k)])
    closed = (-(g0)) > 0
    t, count, steps, nfev, windows = 0.0, 0, 0, 0, 0
    # the window: 200 T, doubled after each window that reached its end without a contact event (a
    # slow tail: late re-contacts at speeds of 1e-8 V last 1e4 T at exponent 3, and a 50-ball chain
    # ran out of its 10^5 windows of 200 T), and 200 T again after one with an event inside it (a
    # ball ringing between two walls keeps its windows, and the cap on the events is read after
    # each). A window that continues the one before (which reached its end) starts with the step
    # size that one's controller had reached: from SciPy's initial choice each window grew its steps
    # again, through the tail's free flights (a 100-ball chain of exponent 3: 86,397 steps, 23,563
    # so; a 100-ball Hertz one 4,286 -> 3,664). A window that a held contact's crossing ended (a
    # terminal event: the next window starts at it, and the caps are read at each) is followed by one
    # as long: started again at 200 T, each of the tail's late re-contacts had grown its windows from
    # 200 T again (the 100-ball chain of exponent 3: 23,563 -> 14,827 steps; 6,924 -> 912 windows at
    # 60 balls). Both together: the same events, the velocities within 2.5e-16 (5.5e-15 at exponent 2,
    # 100 balls) of those of fixed 200 T windows started by SciPy (measured)
    window0 = window = 200.0 * T
    outcome = None
    laws = None  # the held contacts' laws (True: closed), read off the gaps at the start
    h_next = None  # the step size a window starts with: SciPy's initial choice at first
    while outcome is None:
        windows += 1
        if windows > max_windows:
            raise NonTermination(f"compliant impact: not over after {max_windows} windows (of 200 contact time "
                                 f"scales {T:g}, doubled after each without an event){theorem}")
        if windows > 1 and stop(t, y) >= 0:
            # the stopping condition already holds (reached exactly at a window's end): the motion is over
            outcome = "separated"
            break
        g = y[:k]
        if np.all(g >= 0):
            # free flight (no force): the gaps are linear in time, so jump to the next closing exactly
            w = Hf @ y[i_v:i_p]
            appr = w < 0
            t_close = float(np.min(g[appr] / -w[appr])) if np.any(appr) else 0.0
            if t_close > 0:
                y = y.copy()
                y[:k] += t_close * w
                t += t_close
                laws = None  # every held law read off the gaps again
                h_next = None  # a contact closes from free flight: SciPy's initial step again
        if t >= t_max:
            raise NonTermination(f"compliant impact: not over at t_max = {t_max:g} (contact time scale {T:g})"
                                 f"{theorem or '; the termination theorem gives finiteness, not a bound on the time'}")
        if held_idx:
            laws = hold(y, laws)
        sol = _dop853(fun, t / unit, min(t + window, t_max) / unit, y, rtol, atol_vec, events, into=True,
                      values=values, stage=stage_of, turns=turns, crossings=crossings, first_step=h_next)
        h_next = sol.h_abs if sol.status == 0 else None
        if sol.status == -1:  # pragma: no cover - integrator failure
            raise NonTermination(f"compliant impact: integrator failed ({sol.message})")
        steps += sol.steps
        nfev += sol.nfev
        # the window's accepted states after its first (the last window's last state, but for a
        # held contact's gap set to 0 at a crossing, or a jump of free flight, which closes nothing)
        d_steps = -sol.y[:k, 1:]
        c_steps = d_steps > 0
        c_all = np.concatenate([closed[:, None], c_steps], axis=1)
        count_before = count
        count += int(np.count_nonzero(c_all[:, 1:] != c_all[:, :-1]))
        closed = c_steps[:, -1]
        window = window if sol.status == 1 else window * 2.0 if count == count_before else window0
        if count > max_events:
            raise NonTermination(f"compliant impact: more than max_events = {max_events} contact events"
                                 + (f"{theorem} (a ball between two walls never separates: give damping and "
                                    "rest_tol)" if theorem else
                                    "; the termination theorem gives finiteness, not a bound on the events"))
        if sol.status == 1:
            for which, name in ((0, "separated"), (1, "rest"))[:first_gap]:
                if len(sol.t_events[which]):
                    t, y = float(sol.t_events[which][-1]) * unit, sol.y_events[which][-1]
                    outcome = name
                    break
            if outcome == "separated":
                # the stop is the root of min g_i: a contact that opens there may still read δ = +1e-17
                count += int(np.count_nonzero(closed))
            elif outcome is None:
                # a held contact's gap crossed its band's edge (±atol·L): the next piece holds it the
                # other way, from its gap set to that edge (brentq left it within a few ulps of t of
                # it, on either side), inside the band the next piece's law keeps
                i = next(i for i in range(len(gaps_ev)) if len(sol.t_events[first_gap + i]))
                t, y = float(sol.t_events[first_gap + i][-1]) * unit, sol.y_events[first_gap + i][-1].copy()
                y[held_idx[i]] = gaps_ev[i].offset * Lsc
                laws[i] = not laws[i]
        else:
            t, y = float(sol.t[-1]) * unit, sol.y[:, -1]
        verify_window(y)
    P = y[i_p:]
    vplus = y[i_v:i_p]
    T1 = 0.5 * float(vplus @ Mf @ vplus)
    ratios = P / P[0] if P[0] != 0 else np.full(k, np.nan)
    checks = check_run(Mf, Hf, v0, vplus, P, elastic=elastic, rtol=rtol, certificate=cert, bounds=bounds)
    return CompliantResult(P, ratios, vplus, t, T1 / T0, count, steps, nfev, outcome, cert, checks)


def chain_impact(masses, velocities, stiffness, damping=None, *, model: str = "hertz", rtol: float = 1e-11,
                 atol: float = 1e-14, max_events: int = 10_000, exponent=None, hunt_crossley=None, walls=(),
                 rest_tol: float | None = None) -> CompliantResult:
    """Integrate a compliant n-ball chain through its impact and return the impulses (eq. 21).

    A convenience wrapper of :func:`compliant_impact` for balls on a line, touching at ``t = 0``
    (contact ``i`` between balls ``i`` and ``i+1``, indentation ``δ_i = x_i − x_{i+1}``), with
    optional walls at either end (contacts ordered as in :func:`chain_matrices`).

    Parameters
    ----------
    masses : n positive masses
    velocities : n pre-impact velocities (balls touching at ``t = 0``)
    stiffness : one positive stiffness ``K_i`` per contact (n−1, plus one per wall), or one number
    damping : ``C_i ≥ 0`` per contact of eq. 20 (default 0)
    model : ``"hertz"`` (eq. 20, exponent 3/2) or ``"linear"`` (eq. 23); ``exponent`` overrides it
    rtol, atol : tolerances of the integrator (DOP853)
    max_events : cap on contact events (``NonTermination`` beyond)
    exponent : per-contact exponent ``p ≥ 1`` (or one number), overriding ``model``
    hunt_crossley : per-contact Hunt–Crossley damping ``D`` (exclusive with ``damping``)
    walls : subset of ``("left", "right")``
    rest_tol : see :func:`compliant_impact`

    Returns
    -------
    CompliantResult

    Raises
    ------
    ImpactInputError
        Wrong lengths, NaN, non-positive mass or stiffness, negative damping, unknown model,
        or a pre-impact state in which no contact approaches (nothing to integrate).

    Examples
    --------
    Two balls, linear spring: the elastic exchange of velocities, ``P = m v``, contact time
    ``π/ω = π/√(K/μ) = π/√10`` (reduced mass ``μ = 1/2``):

    >>> r = chain_impact([1, 1], [2, 0], [5], model="linear")
    >>> abs(float(r.velocity[0])) < 1e-12, round(float(r.velocity[1]), 9), round(float(r.impulses[0]), 9), round(r.duration, 6)
    (True, 2.0, 2.0, 0.993459)

    A cradle: two strikers moving together (a touching pair that does not approach) hit three
    balls at rest; with Hertz contacts the outcome is not the ideal cradle's ``(0, 0, 0, 1, 1)``:

    >>> r = chain_impact([1] * 5, [1, 1, 0, 0, 0], 1.0)
    >>> r.velocity.round(2).tolist(), r.outcome
    ([-0.11, -0.04, 0.21, 0.8, 1.14], 'separated')
    """
    if model not in MODELS:
        raise ImpactInputError("model", f"must be one of {MODELS}, got {model!r}")
    m = _vec(masses, len(np.atleast_1d(masses)), "masses")
    n = m.shape[0]
    if n < 2 and not walls:
        raise ImpactInputError("masses", "a chain needs at least two balls (or a wall)")
    if np.any(m <= 0):
        raise ImpactInputError("masses", "must be positive")
    Mm, H, _names = chain_matrices(m, walls)
    k = H.shape[0]
    v0 = _vec(velocities, n, "velocities")
    K = _per_contact(stiffness, k, "stiffness")
    if np.any(K <= 0):
        raise ImpactInputError("stiffness", "must be positive")
    if damping is not None:
        C = _per_contact(damping, k, "damping")
        if np.any(C < 0):
            raise ImpactInputError("damping", "must be non-negative")
    if not np.any(H @ v0 < 0):
        raise ImpactInputError("velocities", "no contact approaches (v_i > v_{i+1} for none): there is no impact")
    p = exponent if exponent is not None else (1.5 if model == "hertz" else 1.0)
    return compliant_impact(Mm, H, v0, K, p, damping, hunt_crossley=hunt_crossley, rtol=rtol, atol=atol,
                            max_events=max_events, rest_tol=rest_tol)
