"""Which contacts take part in a multiple impact, and which impulse ratios must vanish
(Acary & Taha, sec. 5, eqs. 41–45).

* **Eq. 41 (participation).** A contact takes part only if the pre-impact velocity lies in the
  opposite of its tangent cone: ``H_i v⁻ ≤ 0`` (approaching or grazing). The paper prints the
  cone as ``T_i = {p | −∇h_i·p ≥ 0}``; with that sign, ``−v ∈ T_i`` would mean *leaving*, which
  contradicts the sentence after eq. 41 and sec. 5.1 (``τ ≥ π/2 ⇒ v₁ ∈ T₁`` and no impact). The
  tangent cone of ``{h_i ≥ 0}`` is ``{p | ∇h_i·p ≥ 0}``; with it, eq. 41 and eq. 44 are the same
  condition, ``H_i v⁻ ≤ 0``, used here. An impact happens at all only when some contact strictly
  approaches (``H_i v⁻ < 0``); the law's primary contact (row 1) must (eq. 44).
* **Eq. 43 (coupling).** Two constraints may be coupled iff ``n_i·n_j < 0`` in the kinetic
  metric, i.e. ``cos θ_ij < 0`` (kinetic angle, :func:`impactsym.mechanics.kinetic_angle_cos`).
  Its sign is the sign of ``W_ij = H_i M⁻¹ H_jᵀ`` (the denominator of ``cos θ_ij`` is positive),
  decided exactly.
* **Eq. 45 (degree).** In an open planar chain (contact ``i`` between balls ``i`` and ``i+1``), a
  multiple impact of degree ``k`` needs the ``k−1`` first kinetic angles ``θ_{i,i+1} > π/2``:
  :func:`impact_degree` counts them, after eq. 44.
* **When a ratio must be zero.** The paper's rule, generalized from the chain: contact ``j`` can
  receive impulse only through a path of coupled, participating contacts from the primary
  contact. For an open chain (``W_{i,i+2} = 0``) this is exactly eq. 45. Every other ratio
  ``α_1j`` is set to zero by :func:`apply_coupling`, which reports each one it sets.

Examples
--------
>>> import sympy as sp
>>> from impactsym.models.acary_taha import pool, chain3
>>> sc = pool(sp.pi / 2)
>>> ratios, notes = apply_coupling(sc.M, sc.H, sc.v, ["1/2"])
>>> ratios, notes[0]["contact"], notes[0]["cos_kinetic_angle"]
([0], 2, '0')
>>> impact_degree(chain3().M, chain3().H, chain3().v)
2

References
----------
Acary & Taha, eqs. 39–45 and sec. 4.1.1 (θ ≥ π/2 forces ``α₁₂ = 0``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import sympy as sp

from ..mechanics import check_gradients, check_mass_matrix, check_velocity, kinetic_angle_cos
from ..numbers import exact_str, is_exact, to_exact_matrix, to_float_array
from .delassus import delassus, exact_data, sign_of

__all__ = [
    "participating_contacts",
    "coupled_pairs",
    "impact_degree",
    "CouplingDecision",
    "coupling_decision",
    "apply_coupling",
]


def _checked(M, H, v=None):
    exact = is_exact(M, H) and (v is None or is_exact(v))
    Mx = check_mass_matrix(M, exact=exact)
    n = Mx.shape[0]
    Hx = check_gradients(H, n, exact=exact)
    vx = None if v is None else check_velocity(v, n, exact=exact)
    return exact, Mx, Hx, vx


def _exact_w_and_W(Mx, Hx, vx):
    _, (Mq, Hq, vq) = exact_data(Mx, Hx, vx)
    return Hq * vq, delassus(Mq, Hq)


def participating_contacts(H, v) -> list[bool]:
    """Eq. 41 with the tangent cone's sign corrected: contact ``i`` takes part iff ``H_i v⁻ ≤ 0``.

    >>> participating_contacts("-1,1,0;0,-1,1", "1,0,0")
    [True, True]
    >>> participating_contacts("-1,1,0;0,-1,1", "1,0,1")
    [True, False]
    """
    exact = is_exact(H, v)
    raw = to_exact_matrix(H, "gradients") if exact else np.atleast_2d(to_float_array(H, "gradients"))
    Hx = check_gradients(raw, raw.shape[1], exact=exact)
    vx = check_velocity(v, Hx.shape[1], exact=exact)
    _, (Hq, vq) = exact_data(Hx, vx)
    w = Hq * vq
    return [sign_of(w[i, 0]) <= 0 for i in range(Hx.shape[0])]


def coupled_pairs(M, H) -> dict:
    """Eq. 43: ``{(i, j): cos θ_ij < 0}`` for ``i < j`` (0-based rows), decided exactly.

    >>> coupled_pairs("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1")
    {(0, 1): True}
    """
    _, Mx, Hx, _ = _checked(M, H)
    _, (Mq, Hq) = exact_data(Mx, Hx)
    W = delassus(Mq, Hq)
    k = Hx.shape[0]
    return {(i, j): sign_of(W[i, j]) < 0 for i in range(k) for j in range(i + 1, k)}


def impact_degree(M, H, v) -> int:
    """Eqs. 44–45 for an open planar chain (row ``i`` the contact of balls ``i``, ``i+1``):
    0 if the first contact does not approach (no impact), else ``1 +`` the number of leading
    consecutive kinetic angles ``θ_{i,i+1} > π/2``.

    >>> from impactsym.models.acary_taha import pool
    >>> sc = pool(sp.pi / 3)
    >>> impact_degree(sc.M, sc.H, sc.v)
    2
    >>> sc = pool(sp.pi / 2)
    >>> impact_degree(sc.M, sc.H, sc.v)
    1
    """
    _, Mx, Hx, vx = _checked(M, H, v)
    _, (Mq, Hq, vq) = exact_data(Mx, Hx, vx)
    w = Hq * vq
    if sign_of(w[0, 0]) >= 0:
        return 0
    W = delassus(Mq, Hq)
    degree = 1
    for i in range(Hx.shape[0] - 1):
        if sign_of(W[i, i + 1]) < 0:
            degree += 1
        else:
            break
    return degree


@dataclass
class CouplingDecision:
    """The outcome of the sec. 5 criteria for one scene.

    Attributes
    ----------
    participating : per contact, ``H_i v⁻ ≤ 0`` (eq. 41)
    approaching : per contact, ``H_i v⁻ < 0``
    coupled : ``{(i, j): cos θ_ij < 0}`` (eq. 43), 0-based, ``i < j``
    cosines : ``{(i, j): cos θ_ij}`` (exact SymPy or float)
    reachable : per contact, connected to the primary contact (row 1) through coupled,
        participating contacts; the primary contact is reachable iff it participates
    """

    participating: list
    approaching: list
    coupled: dict
    cosines: dict
    reachable: list = field(default_factory=list)


def coupling_decision(M, H, v) -> CouplingDecision:
    """Apply eqs. 41 and 43 to a scene (exact decisions; see the module docstring).

    >>> from impactsym.models.acary_taha import chain3
    >>> d = coupling_decision(chain3().M, chain3().H, chain3().v)
    >>> d.participating, d.approaching, d.reachable, d.cosines[(0, 1)]
    ([True, True], [True, False], [True, True], -1/2)
    """
    exact, Mx, Hx, vx = _checked(M, H, v)
    if exact:
        # a pure function of the exact scene: remembered per scene (the coupled and the uncoupled
        # request, and every ratio, on one scene share it); a fresh copy of the containers each time
        d = _exact_decision(sp.ImmutableMatrix(Mx), sp.ImmutableMatrix(Hx), sp.ImmutableMatrix(vx))
        return CouplingDecision(list(d.participating), list(d.approaching), dict(d.coupled), dict(d.cosines),
                                list(d.reachable))
    return _decide(Mx, Hx, vx)


@lru_cache(maxsize=256)
def _exact_decision(Mx, Hx, vx) -> CouplingDecision:
    """:func:`coupling_decision` of an exact, checked scene (immutable, hashable matrices),
    remembered; ``paper_checks.mutations.clear_caches`` forgets it with every other memo."""
    return _decide(Mx, Hx, vx)


def _decide(Mx, Hx, vx) -> CouplingDecision:
    w, W = _exact_w_and_W(Mx, Hx, vx)
    k = Hx.shape[0]
    sw = [sign_of(w[i, 0]) for i in range(k)]
    participating = [s <= 0 for s in sw]
    approaching = [s < 0 for s in sw]
    coupled = {(i, j): sign_of(W[i, j]) < 0 for i in range(k) for j in range(i + 1, k)}
    cosines = {}
    for i in range(k):
        for j in range(i + 1, k):
            cosines[(i, j)] = kinetic_angle_cos(Mx, Hx[i, :], Hx[j, :])
    reachable = [False] * k
    if participating[0]:
        reachable[0] = True
        frontier = [0]
        while frontier:
            i = frontier.pop()
            for j in range(k):
                if not reachable[j] and participating[j] and coupled[(min(i, j), max(i, j))]:
                    reachable[j] = True
                    frontier.append(j)
    return CouplingDecision(participating, approaching, coupled, cosines, reachable)


def apply_coupling(M, H, v, ratios):
    """Set to zero every ratio ``α_1j`` whose contact cannot receive impulse (eqs. 41, 43, 45).

    Parameters
    ----------
    M, H, v : the scene (mass matrix, closed-contact gradient rows, pre-impact velocity)
    ratios : the ``k−1`` ratios ``α_12, ..., α_1k``, or ``None`` (every ratio not forced to zero
        must then be given: an error names the first one missing)

    Returns
    -------
    (ratios, notes) : the ratios after the criteria (exact numbers or floats, as given; a forced
        zero is ``0``), and one note per ratio set to zero: ``{"contact", "ratio", "reason",
        "cos_kinetic_angle", "equation"}`` (contacts numbered from 1, as in the paper).

    >>> apply_coupling("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", ["1/2"])
    (['1/2'], [])
    """
    _, Mx, Hx, vx = _checked(M, H, v)
    k = Hx.shape[0]
    given = None if ratios is None else list(ratios)
    if given is not None and len(given) != k - 1:
        from ..errors import ImpactInputError

        raise ImpactInputError("ratios", f"expected {k - 1} ratio(s) alpha_12, ..., alpha_1{k} for {k} closed contacts, got {len(given)}")
    d = coupling_decision(Mx, Hx, vx)
    out, notes = [], []
    for j in range(1, k):
        if d.reachable[j]:
            if given is None:
                from ..errors import ImpactInputError

                raise ImpactInputError("ratios", f"alpha_1{j + 1} is needed: contact {j + 1} is coupled to the primary contact")
            out.append(given[j - 1])
            continue
        c = d.cosines[(0, j)]
        if not d.participating[j]:
            reason = f"contact {j + 1} does not take part: H_{j + 1} v- > 0 (eq. 41)"
            eq = "41"
        elif not d.participating[0]:
            reason = "the primary contact does not take part (eq. 44): no impact, no impulse is transmitted"
            eq = "44"
        else:
            reason = (f"contact {j + 1} is not coupled to the primary contact through contacts with "
                      f"n_i.n_j < 0 (eq. 43)")
            eq = "43"
        out.append(0)
        notes.append({"contact": j + 1, "ratio": f"alpha_1{j + 1}", "reason": reason,
                      "cos_kinetic_angle": exact_str(c) if isinstance(c, sp.Basic) else float(c),
                      "equation": eq, "given": None if given is None else str(given[j - 1])})
    return out, notes

