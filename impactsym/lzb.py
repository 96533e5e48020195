"""The LZB multiple-impact model (Liu, Zhao & Brogliato), for general ``M`` and ``H``.

The impact is instantaneous (the configuration does not change); what evolves is the state of
each contact along an impulse variable. Contact ``i`` carries a potential energy ``E_i ≥ 0``, a
stiffness ``K_i``, an exponent ``η_i`` (Hertz ``3/2``) and an energetic coefficient of
restitution ``e_i ∈ (0, 1]``. With ``w = H v`` the relative normal velocities (``w_i < 0``
approaching) and ``P_i`` the impulses:

1. Force–energy relation (the compliant law ``f = K δ^η`` with ``E = K δ^{η+1}/(η+1)``):
   ``f_i = a_i E_i^{η_i/(η_i+1)}``, ``a_i = K_i^{1/(η_i+1)} (η_i+1)^{η_i/(η_i+1)}``.
2. Primary contact ``p``: the contact with the largest potential energy (at the start, when all
   ``E_i = 0``, the contact that approaches fastest, for the closed-form first increment only:
   after it the largest energy leads, which is another contact when the fastest is much the
   softer). ``P_p`` is the independent variable.
3. Distributing rule: ``dP_j = (f_j / f_p) dP_p``, which for equal exponents is
   ``dP_j = (K_j/K_p)^{1/(1+η)} (E_j/E_p)^{η/(1+η)} dP_p`` (LZB 2008, eq. 3.13; LZB 2009 II).
4. Velocities: ``M dv = Hᵀ dP``, hence ``dw = H M⁻¹ Hᵀ dP``.
5. Energies: ``dE_j = −w_j dP_j`` in compression (``w_j < 0``) and ``dE_j = −(1/e_j²) w_j dP_j``
   in expansion (``w_j > 0``), so that the energy a contact gives back in expansion is
   ``e_j²`` times what it stored (the energetic restitution).
6. The impact is over when every ``E_i = 0`` and every ``w_i ≥ 0``.

How it is integrated (our choices, stated). A contact that has no energy yet but approaches (``E_j =
0``, ``w_j < 0``) must start to compress, while ``dE_j ∝ E_j^{η/(η+1)}`` would keep it at zero
forever (the equation is not Lipschitz there). We therefore integrate ``s_j = E_j^{1/(η_j+1)}``
(proportional to the indentation ``δ_j``) for the non-primary contacts: ``ds_j/dP_p = −c_j w_j b_j /
f_p``, ``b_j = (K_j/(η_j+1))^{1/(η_j+1)}``, ``c_j = 1`` or ``1/e_j²``, which is regular at ``s_j =
0`` (this is the continuous form of the special first step that Siconos' ``OSNSMultipleImpact``
applies to such contacts). A contact with ``s_j = 0`` and ``w_j ≥ 0`` stays inactive (no gaps exist
in LZB: bodies do not move during the impact). The primary's own energy is integrated directly,
``dE_p/dP_p = −c_p w_p``, which stays regular as ``E_p → 0``. The ODE in ``P_p`` is solved by DOP853
in segments: a segment ends when another contact's energy exceeds ``1.5 E_p`` (the primary is
switched), when a separating contact's ``s_j`` falls through 0 (it is released: the next segment
starts with ``s_j = 0`` and the contact at rest; ``f_j ∝ s_j^η_j`` is not smooth at that root and
DOP853 underestimates the error of the step to it, so the step is taken again from its start to the
root at ``rtol/100``; within a segment a contact that was not at rest at its start follows the
compressing or expanding ``ds_j`` throughout, so that the right-hand side, which jumps to ``ds_j =
0`` there, is smooth within each segment; stepping across the jump made DOP853's step size
underflow, by the last bits of the CPU's arithmetic at default tolerances and in 7 of 60 random
chains at ``rtol = 1e-13``), when a contact at rest begins to approach (``w_j`` falls through 0: the
next segment starts with it live; until then it is held at rest, ``ds_j = 0`` at every stage, so
that the stages of the step across that root leave its ``s_j`` at 0), when a contact with ``e_j <
1``, the primary or a live one, turns (``w_j`` crosses 0, where ``c_j`` jumps between 1 and
``1/e_j²``: a kink that DOP853's error estimate does not see; stepped across, an unloading ended
1e-3 off at ``rtol = 1e-11``, and a re-compression 2.6e-8 off; within its segment the contact keeps
the ``c_j`` it started with, so that the right-hand side stays smooth up to the event; a turn there
and back inside one step, which no sign change between accepted steps shows, is found on the step's
dense output when the end slopes of ``w_j`` reveal it: missed, a scene was 2.4e-5 off at ``rtol =
1e-11``; the contact whose turn ended the last segment starts at ``w_j = 0`` to rounding, on either
side, and its way back is watched as a crossing of ``∓SEPARATION_EPS·V``: watched at 0, a grazing
turn left at −2e-16 was never seen coming back, and a scene was 4e-2 off), when ``E_p`` has fallen
by ``DROP_FACTOR = 1e-3`` within the segment (a new segment counts ``P_p`` from 0 again, so that
the small increments near the end of an unloading are not lost in the ulps of a large ``P_p``), or
when ``E_p`` falls below ``ENERGY_EPS · E⁰`` (then every energy is below ``1.5 ENERGY_EPS · E⁰``
and is set to zero; the process restarts from the fastest approaching contact if one approaches,
else it is over), where ``E⁰ = ½ μ_p w_p²`` at the latest (re)start (the
primary's approach energy, ``μ_p`` its effective mass ``1/(H_p M⁻¹ H_pᵀ)``). The first increment
``P_p ∈ [0, P₀]`` of every start is taken in closed form (``E_p = −w_p P``, ``s_j ∝
P^{1/(η_p+1)}``), ``P₀ = 1e-10 μ_p |w_p|``.

Extreme ratios (measured): with mass ratios up to 10⁶ *and* stiffness ratios up to 10⁴ together in
one chain, random 5–7-ball cases used to make DOP853's step size underflow near the end of a
primary's unloading (``NonTermination`` "integrator failed"): ``P_p`` had grown to ~0.1 while the
increments that mattered were ~1e-17, a few ulps. Restarting ``P_p`` at every ``DROP_FACTOR`` fall
of ``E_p`` resolved the pinned case (``tests/test_lzb.py``) and 36 of 36 random cases of that kind (three
seeds of 12 chains: masses ``10^U(−3, 3)``, stiffnesses ``10^U(−2, 2)``, 5–7 balls, 0.2–4.7 s each
on the shared machine).

Termination (what is and is not proved; ``docs/compliant_termination.md``, step 7). The loop ends
when, after a segment, every energy has been set to zero (the primary's energy fell below
``ENERGY_EPS · E⁰``: a truncation) and no contact approaches by more than ``SEPARATION_EPS · V``;
``max_segments`` caps it (``NonTermination``; with ``e < 1`` two light balls pressed between a
heavier one and a wall take thousands of segments, where Hunt–Crossley in the time domain ends at
once: docs/compliant_termination.md, step 7). A segment whose impulse scale is below ``2⁻¹⁰`` or
above ``2¹⁰`` is integrated in ``P_p`` over a power of two near it
(:func:`impactsym.compliant._in_units`), so that event roots are not lost to SciPy's absolute
tolerance, the error norm's squares do not underflow, and the results do not depend on the units. The impulse bound of
the compliant model holds here too (``M dv = Hᵀ dP`` with ``dP ≥ 0``, and ``T + Σ E_i`` never grows
since ``c_j ≥ 1`` in expansion), so with a separating direction ``u`` the total impulse stays below
``2 ‖u‖_M √(2T⁻) / min (Hu)_i``; it is checked after every run
(:func:`impactsym.termination.check_run`, with the momentum balance and the energy). No bound on
the number of segments or restarts is proved: each restart is triggered by an approach left over
from the previous segment, and nothing here shows that these stop; with ``e < 1`` on a ball between
two walls the approach speed falls by the factor ``e`` per bounce, so the run ends after about
``log(1/SEPARATION_EPS) / log(1/e)`` restarts (120 segments and restarts in all, 40 wall impacts,
at ``e = 1/2``, measured).

With every ``e_i = 1`` this is the time-domain compliant model of :mod:`impactsym.compliant`
re-parametrized by ``P_p`` (``dt = dP_p / f_p``), except that contacts that open during the
impact keep zero gap here; the two agree closely on chains (``tests/test_lzb.py`` states the
figures). ``duration`` (with ``track_time=True``) is the elapsed time of that equivalent compliant process,
``∫ dP_p / f_p``.

Examples
--------
Three equal balls, Hertz contacts, elastic: the same outcome as the compliant chain.

>>> r = lzb_chain([1, 1, 1], [1, 0, 0], [1, 1])
>>> r.velocity.round(5).tolist(), r.ratios.round(5).tolist()
([-0.07095, 0.0764, 0.99455], [1.0, 0.92866])

With ``e = 0.8`` at each contact the impact dissipates energy:

>>> r = lzb_chain([1, 1, 1], [1, 0, 0], [1, 1], restitution=0.8)
>>> round(r.energy_ratio, 4) < 1
True

References
----------
C. Liu, Z. Zhao, B. Brogliato, "Frictionless multiple impacts in multibody systems. I. Theoretical
framework", Proc. R. Soc. A 464 (2008) 3193–3211; "II. Numerical algorithm and simulation
results", Proc. R. Soc. A 465 (2009) 1–23; "Energy dissipation and dispersion effects in granular
media", Phys. Rev. E 78 (2008) 031307.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .compliant import (_contact_scales_in_range, _dop853, _in_units, _kinetic_energy_in_range, _per_contact,
                        _speed_scales, _step_to_root_again, _unit_near, _vec, chain_matrices, float_system)
from .errors import ImpactInputError, NonTermination

__all__ = ["LZBResult", "lzb_impact", "lzb_chain"]

#: an energy below ENERGY_EPS · E⁰ at the primary contact ends the primary's segment
ENERGY_EPS = 1e-13
#: relative approach speed (in units of the largest initial one) treated as zero at the end
SEPARATION_EPS = 1e-12
#: switch the primary when another contact's energy exceeds SWITCH_FACTOR · E_p
SWITCH_FACTOR = 1.5
#: the pre-impact kinetic energies LZB takes: inside float64 with its energies' powers and squares
ENERGY_RANGE = (1e-200, 1e200)
#: start a new segment each time the primary's energy has fallen by this factor within one
DROP_FACTOR = 1e-3


@dataclass
class LZBResult:
    """Outcome of the LZB model.

    Attributes
    ----------
    impulses : ``P_i`` per contact (k)
    ratios : ``P_j / P_1`` (the convention's ratio against the first row)
    velocity : post-impact generalized velocity (n)
    energy_ratio : ``T⁺ / T⁻``
    duration : elapsed time of the equivalent compliant process, ``∫ dP_p / f_p`` (NaN unless
        ``track_time``)
    segments : integration segments plus (re)starts
    steps, nfev : integrator work
    """

    impulses: np.ndarray
    ratios: np.ndarray
    velocity: np.ndarray
    energy_ratio: float
    duration: float
    segments: int
    steps: int
    nfev: int
    #: the a-posteriori checks passed (:func:`impactsym.termination.check_run`)
    checks: dict | None = None


def _too_many_segments(max_segments: int, e) -> NonTermination:
    """The error for a run past ``max_segments``: no bound on LZB's segments is proved, and with
    ``e < 1`` light bodies pressed between a heavier one and a wall can need more than 10⁵
    (measured in ``docs/compliant_termination.md``, step 7), where the time-domain laws end at once."""
    msg = f"LZB: more than max_segments = {max_segments} segments"
    if np.any(e < 1):
        msg += ("; with restitution < 1 the primary contact can switch back and forth for very many segments "
                "(no bound on them is proved: docs/compliant_termination.md, step 7): raise max_segments, or "
                "use a time-domain law (impactsym.compliant.compliant_impact, --law hunt-crossley)")
    return NonTermination(msg)


def lzb_impact(M, H, v, stiffness, exponent=1.5, restitution=1.0, *, rtol: float = 1e-11, atol: float = 1e-14,
               max_segments: int = 100_000, track_time: bool = False) -> LZBResult:
    """Resolve a multiple impact by the LZB model (impulse domain, primary contact, distributing rule).

    Parameters
    ----------
    M : (n, n) symmetric positive definite mass matrix
    H : (k, n) rows of the closed contacts (each row's effective mass ``1/(H_i M⁻¹ H_iᵀ)`` must lie
        in :data:`impactsym.compliant.SCALE_RANGE`, ``[1e-150, 1e150]``, else ``ImpactInputError``)
    v : (n,) pre-impact velocity; its kinetic energy ``T⁻`` must lie in :data:`ENERGY_RANGE`
        (``[1e-200, 1e200]``: inside float64 with the energies' powers and squares), else
        ``ImpactInputError``; the outcome relative to the speeds does not depend on the units
    stiffness : ``K_i > 0`` per contact (or one number); only ratios matter
    exponent : ``η_i ≥ 1`` per contact (or one number), 3/2 for Hertz
    restitution : energetic coefficients ``e_i ∈ (0, 1]`` per contact (or one number)
    rtol, atol : integrator tolerances (``atol`` relative to the problem's scales)
    max_segments : cap on segments (``NonTermination`` beyond)
    track_time : also integrate the equivalent compliant time ``∫ dP_p / f_p`` (singular at each
        start, so the integrator takes many more steps; default off, ``duration`` is then NaN)

    Returns
    -------
    LZBResult

    Examples
    --------
    A point mass dropped into a corner, a floor (row ``(0, 1)``) and a 45° wall (row
    ``(1, 1)/√2``) touched at once; the compliant Hertz run gives the same velocity:

    >>> import numpy as np
    >>> r = lzb_impact(np.eye(2), [[0, 1], [np.sqrt(0.5), np.sqrt(0.5)]], [0, -1], 1.0)
    >>> r.velocity.round(4).tolist(), round(r.energy_ratio, 9)
    ([0.4287, 0.9035], 1.0)
    """
    Mf, Hf, v0 = float_system(M, H, v)
    n, k = Mf.shape[0], Hf.shape[0]
    K = _per_contact(stiffness, k, "stiffness")
    eta = _per_contact(exponent, k, "exponent")
    e = _per_contact(restitution, k, "restitution")
    if np.any(K <= 0):
        raise ImpactInputError("stiffness", "must be positive")
    if np.any(eta < 1):
        raise ImpactInputError("exponent", "must be >= 1")
    if np.any((e <= 0) | (e > 1)):
        raise ImpactInputError("restitution", "must satisfy 0 < e <= 1")
    w0 = Hf @ v0
    if not np.any(w0 < 0):
        raise ImpactInputError("v", "no contact approaches ((H v)_i < 0 for none): there is no impact")
    # energies, impulses and their squares must stay inside float64 (with T⁻ ~ 1e±255 a run overflowed,
    # divided by an underflowed zero or failed its own checks; at 5e±224 it still gave the outcome of
    # the unit problem, relative to V, to 1e-11)
    T0 = _kinetic_energy_in_range(Mf, v0, ENERGY_RANGE, "LZB's float64 integration")
    _contact_scales_in_range(Mf, Hf, "LZB's float64 integration")

    A = np.linalg.solve(Mf, Hf.T)  # M⁻¹Hᵀ
    mu = 1.0 / np.einsum("ij,ji->i", Hf, A)
    a = K ** (1 / (eta + 1)) * (eta + 1) ** (eta / (eta + 1))
    b = (K / (eta + 1)) ** (1 / (eta + 1))
    inv_e2 = 1.0 / e**2
    elastic = bool(np.all(inv_e2 == 1.0))
    V = float(np.max(-w0[w0 < 0]))
    Eeps = ENERGY_EPS * T0  # set again at every (re)start
    Pscale = float(np.max(mu)) * V
    Vq = _speed_scales(np.linalg.inv(Mf), T0)  # each velocity's own scale (V is in the rows' units)
    Tsc = float(np.min((mu / (K * V ** (eta - 1))) ** (1 / (eta + 1))))  # contact time scale

    v = v0.copy()
    P = np.zeros(k)
    s = np.zeros(k)  # s_j = E_j^{1/(η_j+1)} (≥ 0 in use)
    t_equiv = 0.0
    segments = steps = nfev = 0
    primary = None
    Ep = 0.0
    activated = -1  # the contact whose activation event ended the last segment (it starts live)
    turned, turned_dir = -1, 0.0  # the contact whose turn ended the last segment, and the turn's direction
    # (primary, unit, step size) of the last segment when an event ended it and its primary goes on
    # (a contact's event or the energy drop; not a switch, an end or a restart): the next segment,
    # in the same independent variable, starts with the step size the controller had reached instead
    # of SciPy's initial step. Measured on a one-striker Hertz chain of 100 balls at e = 1: 641 -> 302
    # segments (285 at rtol 1e-13, 290 before), 3021 -> 2086 steps, 1.64 -> 0.84 s; the velocities'
    # error against that run about the same (3.1e-11, before 2.8e-11)
    carry = None

    while True:
        w = Hf @ v
        E = np.maximum(s, 0.0) ** (eta + 1)
        if primary is None:
            if np.all(w >= -SEPARATION_EPS * V):
                break
            # a (re)start: all energies are zero; the fastest approaching contact leads
            s[:] = 0.0
            pp = int(np.argmin(w))
            # the energy threshold is relative to this (sub-)impact: late re-contacts in long chains
            # approach at speeds ~1e-8 and carry energies far below ENERGY_EPS · T⁻ (a fixed threshold
            # would end them at once and restart them for ever)
            # (and to the primary's own approach energy: with a 1e-3 mass between heavy ones, the
            # heavy contacts' energies would otherwise swamp the light primary's first increment)
            # (as (μ w) w: with μ ~ 1e-140 and w ~ 1e155, w² overflowed, Eeps was inf and every start
            # ended at once, restarting until max_segments; with μ ~ 1e144 and w ~ 1e-165 it underflowed)
            Eeps = ENERGY_EPS * 0.5 * (mu[pp] * w[pp]) * w[pp]
            segments += 1
            if segments > max_segments:
                raise _too_many_segments(max_segments, e)
            carry = None
            P0 = 1e-10 * mu[pp] * (-w[pp])
            Ep = -w[pp] * P0
            fp = a[pp] * Ep ** (eta[pp] / (eta[pp] + 1))
            act = w < 0
            act[pp] = False
            # s_j = −w_j b_j (η_p+1) P0^{1/(η_p+1)} / (a_p (−w_p)^{η_p/(η_p+1)})
            ep = eta[pp]
            s[act] = -w[act] * b[act] * (ep + 1) * P0 ** (1 / (ep + 1)) / (a[pp] * (-w[pp]) ** (ep / (ep + 1)))
            fj = a * np.maximum(s, 0.0) ** eta
            dP = np.zeros(k)
            dP[pp] = P0
            dP[act] = fj[act] / fp * P0 * (eta[pp] + 1) / (eta[act] + 1)
            P += dP
            v = v + A @ dP
            if track_time:
                t_equiv += (eta[pp] + 1) * P0 / fp
            s[pp] = Ep ** (1 / (eta[pp] + 1))
            # the primary is the contact with the largest energy from here on: after the first
            # increment E_j/E_p = (w_j/w_p)^(η+1) K_j/K_p (equal η), which exceeds SWITCH_FACTOR when
            # the fastest contact is the softer one. Kept as primary, its energy ran to zero while the
            # other's grew (the switch event, already positive at the start, cannot fire upward) and
            # DOP853's step underflowed: "integrator failed in segment 2" at ordinary masses and stiffnesses
            primary = int(np.argmax(np.maximum(s, 0.0) ** (eta + 1)))
            continue
        pp = primary
        Ep = float(E[pp])
        if Ep <= SWITCH_FACTOR * Eeps:
            # the largest energy left is below the end-of-segment level: it is zero (see above)
            s[:] = 0.0
            primary = None
            continue
        others = np.arange(k) != pp
        # the segment's live contacts: every non-primary contact but those at rest (s_j <= 0 and
        # w_j >= 0). A live contact follows ds_j/dP_p = −c_j w_j b_j/f_p throughout the segment, s_j
        # <= 0 included, and the segment ends when its s_j falls through 0 (``release``): there the
        # rule "inactive at s_j <= 0, w_j >= 0" makes ds_j jump from −c_j w_j b_j/f_p (w_j > 0) to 0,
        # a discontinuity of the right-hand side that DOP853's error control cannot step across once
        # the jump times the smallest step exceeds the tolerance (the step size underflowed so at
        # masses 1, 1/2, 2 and e = 0.9, or did not, by the last bits of the CPU's BLAS kernels). The
        # next segment starts with s_j = 0 exactly. A contact at rest stays at rest (ds_j = 0, as the
        # rule says) until w_j falls through 0 (``activation``, continuous): that ends the segment too,
        # and the next one starts with it live. It is held at rest within the segment (ds_j = 0 at every
        # stage, whatever the sign of w_j there): read off each stage, the rule gave the stages of the
        # step across the activation, past its root, the approaching ds_j, and the dense output at the
        # root an s_j that was not 0, 1e-7 of the primary's on a sweep scene (seed 5, case 4678), whose
        # next segment started live from there and ended 6e-8 off at rtol = 1e-11.
        live = [j != pp and (j == activated or not (float(s[j]) <= 0.0 and float(w[j]) >= 0.0)) for j in range(k)]
        at_rest = ~np.array(live)
        # the turns of the contacts with e_j < 1 (the primary or live ones): where w_j crosses 0, c_j
        # jumps between 1 (compression) and 1/e_j² (expansion), a kink of the right-hand side that
        # DOP853's error estimate does not see. Stepped across, a primary's unloading took 7 steps at
        # rtol = 1e-11 and ended 1e-3 off (20 steps and right at 1e-12). Within the segment such a
        # contact keeps its c_j (the right-hand side is smooth, the last step's dense output too) and
        # the segment ends at its turn, an event: rising through 0 for a compressing contact, falling
        # for an expanding one (a re-compression, stepped across before: 2.6e-8 off at rtol = 1e-11
        # on a sweep scene), and for the contact whose turn ended the last segment, back across it;
        # and a turn there and back inside one step is found on the dense output (_dop853's turns:
        # unseen, a sweep scene was 2.4e-5 off at rtol = 1e-11).
        # Ending at the turn without holding c_j still read the root off a step across the kink (2e-6
        # off). Not a contact at its turn (|w_j| <= SEPARATION_EPS·V, the end test's zero speed; its
        # c_j follows the sign of w_j): a ball between two walls at rest to 2e-20 otherwise alternated
        # empty segments with a release. But the contact whose activation ended the last segment,
        # though its w_j is 0 to rounding, compresses (w_j fell through 0): it holds c_j = 1 and is
        # watched for its turn (taken as at its turn, its later turn was stepped across: a random
        # chain 3.1e-9 off at rtol = 1e-12)
        kinks = []  # (j, row, direction of the crossing that ends the segment, its offset)
        c_pos, c_neg = inv_e2.copy(), np.ones(k)  # c_j where w_j > 0 and where w_j <= 0
        for j in range(k):
            if inv_e2[j] == 1.0 or not (j == pp or live[j]):
                continue
            wj = float(w[j])
            if j == turned:
                d = -turned_dir  # past its turn: watched for the way back
            elif j == activated:
                d = 1.0  # its w_j fell through 0 where the last segment ended: it compresses
            elif wj < -SEPARATION_EPS * V:
                d = 1.0
            elif wj > SEPARATION_EPS * V:
                d = -1.0
            else:
                continue
            c_pos[j] = c_neg[j] = 1.0 if d > 0 else inv_e2[j]
            # the contact whose turn ended the last segment starts with w_j at 0 to rounding, on
            # either side: its way back is watched as w_j crossing −d·SEPARATION_EPS·V, not 0. A
            # grazing turn (w_j touches 0 and goes back) left it at −2e-16 after rising through 0, so
            # the fall through 0 was never seen and it was held expanding (c_j = 1/e_j²) through a
            # whole re-compression: a sweep scene 9e-7 off in other units, its unit problem
            # perturbed by 1e-15 4e-2 off (seed 5, case 5974)
            kinks.append((j, Hf[j], d, d * SEPARATION_EPS * V if j == turned else 0.0))

        # the primary's constants of this segment (the same numbers the formula below would index
        # again at each of the ~12 calls per DOP853 step), as Python floats: the same IEEE products
        # and powers as NumPy's scalars, at a fraction of the cost
        a_pp, expo_pp, Eeps_f = float(a[pp]), float(eta[pp] / (eta[pp] + 1)), float(Eeps)
        i_ep, i_r, N = n + k, n + k + 1, n + 2 * k + 2
        few = k <= 24
        zero_k = np.zeros(k)
        al, bl, cpl, cnl = a.tolist(), b.tolist(), c_pos.tolist(), c_neg.tolist()

        def tail(wl, pl, fp, pp=pp):
            # out[n:] for a few contacts, as Python floats: the same IEEE products and quotients,
            # contact by contact, in the formula's order (rhs below): ds_j = (c w_j) b_j/(−f_p) with
            # c = 1/e_j² where w_j > 0 (a NaN w_j takes c = 1, as np.where on np.greater does), +0.0
            # for the primary and a contact at rest (not live: held at rest within the segment);
            # dE_p = −c_p w_p; f_j/f_p = (a_j s_j⁺^η_j)/f_p (pl: NumPy's powers of np.maximum's s⁺),
            # f_p/f_p for the primary; dt = 1/f_p
            # (one loop, no comprehension: the primary's ds is computed and then replaced by its +0.0,
            # a Python float product or quotient by the non-zero nfp never raises)
            nfp = -fp
            ds, ratio = [], []
            dsa, ra = ds.append, ratio.append
            if elastic:
                for x, y, w, pj, lv in zip(al, bl, wl, pl, live):
                    ra(x * pj / fp)
                    dsa(w * y / nfp if lv else 0.0)
                cwp = wl[pp]
            else:
                for x, y, c, cn, w, pj, lv in zip(al, bl, cpl, cnl, wl, pl, live):
                    ra(x * pj / fp)
                    dsa((c * w if w > 0.0 else cn * w) * y / nfp if lv else 0.0)
                w = wl[pp]
                cwp = cpl[pp] * w if w > 0.0 else cnl[pp] * w
            ratio[pp] = fp / fp
            ds[pp] = 0.0
            ds.append(-cwp)
            ds += ratio
            ds.append(1.0 / fp if track_time else 0.0)
            return ds

        def rhs(_P, y, out=None, pp=pp):
            # dv/dP_p = M⁻¹Hᵀ f/f_p, ds_j/dP_p = −c_j w_j b_j/f_p (0 for an inactive contact and the
            # primary), dE_p/dP_p = −c_p w_p, dP/dP_p = f/f_p, dt/dP_p = 1/f_p, written in place into
            # one array (``out``, a row of DOP853's stage table, or a new one), with the float
            # operations of the formula: −c w b/f_p is computed as (c w b)/(−f_p), equal bit for
            # bit, signed zeros included
            ww = Hf.dot(y[:n])
            ss = y[n:i_ep]
            # below the end-of-segment energy the force is held at its value there (a step may
            # overshoot the event; the true solution never goes below it within the segment)
            fp = a_pp * max(y.item(i_ep), Eeps_f) ** expo_pp
            if out is None:
                out = np.empty(N)
            if few and fp != 0.0:
                # a few contacts as Python floats (tail), written into ``out`` at once, then
                # M⁻¹Hᵀ f/f_p by the same BLAS call as A.dot(ratio), into its place. (fp == 0 would
                # raise in Python: NumPy's path below.)
                pw = np.maximum(ss, zero_k)
                np.power(pw, eta, out=pw)
                out[n:] = tail(ww.tolist(), pw.tolist(), fp)
                A.dot(out[i_r:N - 1], out=out[:n])
                return out
            ratio = out[i_r:N - 1]
            np.maximum(ss, zero_k, out=ratio)
            np.power(ratio, eta, out=ratio)
            np.multiply(a, ratio, out=ratio)  # the forces f_j = a_j s_j^η_j
            ratio[pp] = fp
            np.divide(ratio, np.array(fp), out=ratio)
            out[:n] = A.dot(ratio)
            ds = out[n:i_ep]
            if elastic:  # c = 1 on every contact
                cwp = -ww.item(pp)
                np.multiply(ww, b, out=ds)
            else:
                np.multiply(np.where(np.greater(ww, zero_k), c_pos, c_neg), ww, out=ds)
                cwp = -ds.item(pp)
                np.multiply(ds, b, out=ds)
            np.divide(ds, np.array(-fp), out=ds)
            # a contact at rest (not live) gets +0.0
            np.copyto(ds, zero_k, where=at_rest)
            ds[pp] = 0.0
            out[i_ep] = cwp
            out[N - 1] = 1.0 / fp if track_time else 0.0
            return out

        def bind(y, out):
            # rhs(P, y, out) for the contents of the driver's stage buffer y (a few contacts): the
            # same operations on the same values, with the views and work arrays made once
            if not few:
                return None
            q, ss = y[:n], y[n:i_ep]
            o_v, o_tail, o_ratio = out[:n], out[n:], out[i_r:N - 1]
            # w and (s⁺)^η side by side, read by one tolist (s⁺ = np.maximum(s, 0) in pw, then its power)
            work = np.empty(2 * k)
            ww, pw = work[:k], work[k:]
            maximum, power, item = np.maximum, np.power, y.item

            def stage():
                fp = a_pp * max(item(i_ep), Eeps_f) ** expo_pp
                if fp == 0.0:
                    rhs(None, y, out)
                    return
                Hf.dot(q, ww)
                maximum(ss, zero_k, out=pw)
                power(pw, eta, out=pw)
                wl = work.tolist()
                o_tail[...] = tail(wl[:k], wl[k:], fp)
                A.dot(o_ratio, o_v)

            return stage

        def end_primary(_P, y, pp=pp):
            return y[n + k] - Eeps

        end_primary.terminal = True
        end_primary.direction = -1

        # a new segment (P_p counted from 0 again) each time the primary's energy falls by DROP_FACTOR:
        # near the end of its unloading the increments of P_p that matter are ~1e-17 while the segment's
        # P_p is ~0.1, a few ulps, and DOP853's step size underflows (mass ratios 1e4, stiffness ratios 1e2)
        Ep_drop = DROP_FACTOR * Ep

        def drop(_P, y):
            return y[n + k] - Ep_drop

        drop.terminal = True
        drop.direction = -1

        eta_o1 = eta[others] + 1
        idx_o, zero_o = n + np.flatnonzero(others), np.zeros(k - 1)

        def switch(_P, y, pp=pp, others=others):
            if k == 1:
                return -1.0 - SWITCH_FACTOR * y.item(n + k)
            Eo = np.maximum(y[n:n + k][others], 0.0) ** eta_o1
            return Eo.max().item() - SWITCH_FACTOR * y.item(n + k)

        switch.terminal = True
        switch.direction = 1

        # one event per non-primary contact: a live one's s_j, a resting one's w_j = (H v)_j, each
        # falling through 0; an exact 0 reads 1.0 (a live contact starting from s_j = 0, a resting one
        # at w_j = 0), so that an event never fires at the point where its segment starts
        # (values below reads them by the same operations, so that both agree on every sign)
        watched = [(j, n + j, None) if live[j] else (j, -1, Hf[j]) for j in range(k) if j != pp]

        def contact_event(col, row):
            if row is None:
                def release(_P, y):
                    x = y.item(col)
                    return x if x != 0.0 else 1.0
                ev = release
            else:
                def activation(_P, y):
                    x = float(row.dot(y[:n]))
                    return x if x != 0.0 else 1.0
                ev = activation
            ev.terminal = True
            ev.direction = -1
            return ev

        contact_events = [contact_event(col, row) for _j, col, row in watched]
        # and one per kink (above): its w_j crossing 0 in the kink's direction ends the segment
        def kink_event(row, d, off):
            def turn(_P, y):
                return float(row.dot(y[:n])) - off

            turn.terminal = True
            turn.direction = d
            return turn

        contact_events += [kink_event(row, d, off) for _j, row, d, off in kinks]
        first_kink = 3 + len(watched)
        # each turn's slope dw_j/dP_p = H_j (dv/dP_p), for the turns there and back inside one step
        turns = [(first_kink + i, (lambda f, row=row: float(row.dot(f[:n]))))
                 for i, (_j, row, _d, _off) in enumerate(kinks)]
        Eeps_e, Ep_drop_e = float(Eeps), float(Ep_drop)

        def values(_P, y, others=others):
            # the three events' values at once: end_primary's and drop's differences as Python
            # floats, and switch's with the largest other energy taken by Python's max (the same
            # value; the energies are >= 0, so a NaN among them is one in their sum, and is kept)
            Ey = y.item(n + k)
            if k == 1:
                sw = -1.0 - SWITCH_FACTOR * Ey
            else:
                # the others' s by one take, then (s⁺)^(η+1) in place (np.maximum against zeros: the
                # same values but for the sign of a zero, which the signs read here do not see)
                so = y.take(idx_o)
                np.maximum(so, zero_o, out=so)
                np.power(so, eta_o1, out=so)
                Eo = so.tolist()
                tot = sum(Eo)
                sw = (max(Eo) if tot == tot else tot) - SWITCH_FACTOR * Ey
            out = [Ey - Eeps_e, sw, Ey - Ep_drop_e]
            q = y[:n]
            for _j, col, row in watched:
                x = y.item(col) if row is None else float(row.dot(q))
                out.append(x if x != 0.0 else 1.0)
            for _j, row, _d, off in kinks:
                out.append(float(row.dot(q)) - off)
            return out

        y0 = np.concatenate([v, s, [Ep], P, [t_equiv]])
        sscale = np.maximum(T0, 1e-300) ** (1 / (eta + 1))
        atol_vec = atol * np.concatenate([Vq, sscale, [T0], np.full(k, Pscale), [1.0]])
        atol_vec[-1] = atol * Tsc
        span = 1e3 * Pscale
        # the independent variable in units of the segment's impulse scale when that is small: SciPy
        # locates an event root to an absolute 4·EPS in it (brentq's xtol), which is coarse once a
        # segment's increments of P_p are ~1e-15 (a sub-impact restarted by an approach of 1e-7,
        # or bodies of 1e-6 kg at 1e-6 m/s): the root fell on the segment's start, and the run
        # repeated that empty segment until max_segments (or missed events and drifted with the
        # units). And when it is large: at P_p ~ 1e162 (effective masses of 1e138 at speeds of 1e24)
        # the error norm's squares of derivative/scale, ~1e-151 each, underflowed to zero and the
        # step control divided by it. By a power of two (exact: the same steps, scaled), and only
        # outside [2^-10, 2^10], so that every scale in between integrates exactly as before
        # (the primary's impulse scale: what takes up its energy and its approach's kinetic energy)
        mu_p = float(mu[pp])
        scale_P = math.hypot(math.sqrt(2.0 * mu_p) * math.sqrt(max(Ep, 0.0)), mu_p * float(w[pp]))  # no overflow
        unit = _unit_near(scale_P)
        fun, stage_of = rhs, bind
        if unit != 1.0:
            fun, stage_of = _in_units(rhs, bind, unit)
        sol = _dop853(fun, 0.0, span / unit, y0, rtol, atol_vec, [end_primary, switch, drop] + contact_events,
                      keep_states=False, into=True, values=values, stage=stage_of, turns=turns,
                      first_step=carry[2] if carry is not None and carry[:2] == (pp, unit) else None)
        segments += 1
        steps += sol.steps
        nfev += sol.nfev
        if sol.status == -1:
            raise NonTermination(f"LZB: integrator failed in segment {segments} ({sol.message}); contact time "
                                 "scales that differ by orders of magnitude make the impulse-domain ODE stiff "
                                 "(impactsym.compliant.compliant_impact resolves such cases)")
        if segments > max_segments:
            raise _too_many_segments(max_segments, e)
        fired = [i for i, te in enumerate(sol.t_events) if len(te)] if sol.status == 1 else []
        if fired:
            y = sol.y_events[fired[0]][-1]
            ended = fired[0] == 0
            t_root = float(sol.t_events[fired[0]][-1])
            if 3 <= fired[0] < first_kink and watched[fired[0] - 3][2] is None:
                # a release: f_j = a_j s_j^η_j is not smooth where s_j reaches 0, and DOP853 takes the
                # step to it with an error it underestimates (a random chain 6e-10 off there at
                # rtol = 1e-11, in one step from s_j = 0.04 of its largest value; 2e-12 at 1e-12, where
                # the steps shrank towards the root): the step is taken again, finer
                fine, fine_steps, fine_nfev = _step_to_root_again(fun, sol, t_root, rtol, atol_vec, stage_of)
                if fine is not None:
                    y = fine
                steps += fine_steps
                nfev += fine_nfev
        else:
            y = sol.y_last
            ended = False
        v, s, Ep = y[:n].copy(), y[n:n + k].copy(), float(y[n + k])
        P, t_equiv = y[n + k + 1:n + 2 * k + 1].copy(), float(y[-1])
        s[pp] = max(Ep, 0.0) ** (1 / (eta[pp] + 1))
        activated = turned = -1
        if fired and fired[0] >= first_kink:
            turned, _row, turned_dir, _off = kinks[fired[0] - first_kink]  # past its turn from here
        elif fired and fired[0] >= 3:
            j, _col, row = watched[fired[0] - 3]
            if row is None:
                s[j] = 0.0  # released: at rest from here while it separates
            else:
                activated = j  # approaching: live from here
        if ended:
            # every energy is below SWITCH_FACTOR · ENERGY_EPS · E⁰: set to zero
            s[:] = 0.0
            primary = None
        else:
            Eall = np.maximum(s, 0.0) ** (eta + 1)
            primary = int(np.argmax(Eall))
        carry = (pp, unit, sol.h_abs) if fired and primary == pp else None

    vplus = v
    T1 = 0.5 * float(vplus @ Mf @ vplus)
    ratios = P / P[0] if P[0] != 0 else np.full(k, np.nan)
    # momentum balance, energy and the proved impulse bound (docs/compliant_termination.md, step 7)
    from .termination import check_run

    checks = check_run(Mf, Hf, v0, vplus, P, elastic=bool(np.all(e == 1)), rtol=rtol, law="lzb_impact")
    return LZBResult(P, ratios, vplus, T1 / T0, t_equiv if track_time else float("nan"), segments, steps, nfev,
                     checks)


def lzb_chain(masses, velocities, stiffness, exponent=1.5, restitution=1.0, *, walls=(), rtol: float = 1e-11,
              atol: float = 1e-14, max_segments: int = 100_000, track_time: bool = False) -> LZBResult:
    """LZB for balls on a line, touching, with optional walls (contacts as in ``chain_matrices``).

    Examples
    --------
    >>> r = lzb_chain([1, 1], [1, 0], 1.0)
    >>> r.velocity.round(9).tolist(), round(float(r.impulses[0]), 9)
    ([0.0, 1.0], 1.0)
    """
    M, H, _ = chain_matrices(masses, walls)
    v0 = _vec(velocities, M.shape[0], "velocities")
    return lzb_impact(M, H, v0, stiffness, exponent, restitution, rtol=rtol, atol=atol, max_segments=max_segments,
                      track_time=track_time)
