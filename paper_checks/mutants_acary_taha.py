"""Mutations used by the claims of ``paper_checks/acary_taha.py`` (see :mod:`paper_checks.mutations`).

Each mutant is a plausible wrong version of one law, derivation or scene: it returns a result of
the right type that is wrong, so every claim built on it must reach another verdict (or raise).

* ``at.impulse_ratio_law`` and ``at.general_quadratic``: the energy line taken from eq. 12 as
  printed (``½q̇⁺ᵀMq̇⁺ = e q̇⁻ᵀMq̇⁻``, i.e. ``T⁺ = 2eT⁻``), in the package's law and in the
  symbolic derivation;
* ``at.chain3_scene``, ``at.pool_scene``, ``at.pool_positions``: the scenes with one wrong entry
  (a gradient row, the incidence velocity, a ball centre); ``at.pool_incidence``: the pool built
  with the incidence velocity as printed in sec. 4.1;
* ``at.newton_moreau``, ``at.poisson``, ``at.han_gilmore``: the classical laws with a wrong
  post-impact velocity;
* ``at.delassus`` (off-diagonal entries of ``W = HM⁻¹Hᵀ`` negated) and ``at.kinetic_angle_cos``
  (negated): the coupling criteria of sec. 5;
* ``at.validity_domain``: the domain shifted down by 1/97 in ``e``;
* ``at.chain_impact``: compliant ratios with a spurious dependence on the first mass.

>>> from paper_checks.mutations import applied
>>> from impactsym.models.acary_taha import chain3
>>> with applied("at.chain3_scene"):
...     from impactsym.models import acary_taha
...     acary_taha.chain3().H[0, 0]
-96/97
>>> chain3().H[0, 0]
-1
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import sympy as sp

from .mutations import EPS, corrupt, corrupting, mutation  # noqa: F401


def _wrapped(original, wrong):
    out = functools.wraps(original)(wrong)
    out.__wrapped_mutant__ = True
    return out


# --------------------------------------------------------------------------- impulse-ratio law
@mutation("at.impulse_ratio_law", "impactsym.laws.impulse_ratio:impulse_ratio_law",
          "the energy line of eq. 12 as printed (no ½ on the right: T⁺ = 2eT⁻)")
def _impulse_ratio_law(original):
    from impactsym.laws import impulse_ratio as mod

    def wrong(mass_matrix, gradients, velocity, restitution=1, ratios=None, *, allow_invalid=False, coupling=False):
        exact = mod.is_exact(mass_matrix, gradients, velocity, restitution) and (
            ratios is None or isinstance(ratios, str) or mod.is_exact(list(ratios)))
        Mx = mod.check_mass_matrix(mass_matrix, exact=exact)
        Hx = mod.check_gradients(gradients, Mx.shape[0], exact=exact)
        vx = mod.check_velocity(velocity, Mx.shape[0], exact=exact)
        ex = mod.check_restitution(restitution, exact=exact)
        notes = []
        if coupling:
            given = [x for x in ratios.split(",") if x.strip()] if isinstance(ratios, str) else ratios
            ratios, notes = mod.apply_coupling(Mx, Hx, vx, given) if Hx.shape[0] > 1 else ([], [])
        a = mod._ratio_vector(ratios, Hx.shape[0], exact)
        return mod.energy_balance_along(Mx, Hx, vx, 2 * ex, a, exact=exact, allow_invalid=allow_invalid, notes=notes)

    return _wrapped(original, wrong)


@mutation("at.general_quadratic", "derivations.impulse_ratio:general_quadratic",
          "the symbolic law derived from eq. 12 as printed (T⁺ = 2eT⁻)")
def _general_quadratic(original):
    def wrong(M, H, v, e, alphas, **kw):
        return original(M, H, v, 2 * sp.sympify(e), alphas, **kw)

    return _wrapped(original, wrong)


# --------------------------------------------------------------------------- scenes
@mutation("at.chain3_scene", "impactsym.models.acary_taha:chain3",
          "the chain with h₁'s gradient entry for q₁ shifted by 1/97")
def _chain3(original):
    def wrong(*args, **kwargs):
        sc = original(*args, **kwargs)
        H = sp.Matrix(sc.H)
        H[0, 0] += EPS
        return dataclasses.replace(sc, H=H)

    return _wrapped(original, wrong)


@mutation("at.pool_scene", "impactsym.models.acary_taha:pool",
          "the pool (and Bernoulli's problem) with ball 1's incidence velocity ẋ₁⁻ shifted by 1/97")
def _pool(original):
    def wrong(*args, **kwargs):
        sc = original(*args, **kwargs)
        v = sp.Matrix(sc.v)
        v[0] += EPS
        return dataclasses.replace(sc, v=v)

    return _wrapped(original, wrong)


@mutation("at.pool_incidence", "impactsym.models.acary_taha:pool",
          "the pool (and Bernoulli's problem) built with the printed incidence −(cos(θ+τ), sin(θ+τ)) by default")
def _pool_incidence(original):
    def wrong(theta, tau=0, **kwargs):
        if kwargs.get("incidence", "theta-minus-tau") == "theta-minus-tau":
            kwargs["incidence"] = "printed"
        return original(theta, tau, **kwargs)

    return _wrapped(original, wrong)


@mutation("at.pool_positions", "impactsym.models.acary_taha:pool_positions",
          "ball 1's centre with x shifted by 1/97")
def _pool_positions(original):
    def wrong(*args, **kwargs):
        G1, G2, G3 = original(*args, **kwargs)
        G1 = sp.Matrix(G1)
        G1[0] += EPS
        return G1, G2, G3

    return _wrapped(original, wrong)


# --------------------------------------------------------------------------- classical laws
def _velocity_shifted(original):
    def wrong(*args, **kwargs):
        r = original(*args, **kwargs)
        return dataclasses.replace(r, velocity=corrupt(r.velocity))

    return _wrapped(original, wrong)


@mutation("at.newton_moreau", "impactsym.laws.classical:newton_moreau", "q̇₁⁺ shifted by 1/97")
def _newton(original):
    return _velocity_shifted(original)


@mutation("at.poisson", "impactsym.laws.classical:poisson", "q̇₁⁺ shifted by 1/97")
def _poisson(original):
    return _velocity_shifted(original)


@mutation("at.han_gilmore", "impactsym.laws.classical:han_gilmore", "q̇₁⁺ of every outcome shifted by 1/97")
def _han_gilmore(original):
    def wrong(*args, **kwargs):
        r = original(*args, **kwargs)
        outs = [dataclasses.replace(o, velocity=corrupt(o.velocity)) for o in r.outcomes]
        return dataclasses.replace(r, outcomes=outs)

    return _wrapped(original, wrong)


# --------------------------------------------------------------------------- coupling
@mutation("at.delassus", "impactsym.laws.delassus:delassus",
          "W = HM⁻¹Hᵀ with its off-diagonal entries negated (the angles between normals reversed)")
def _delassus(original):
    import flint

    def wrong(M, H):
        W = original(M, H)
        if isinstance(W, flint.fmpq_mat):
            k = W.nrows()
            return flint.fmpq_mat(k, k, [W[i, j] if i == j else -W[i, j] for i in range(k) for j in range(k)])
        if isinstance(W, sp.MatrixBase):
            return sp.Matrix(W.rows, W.cols, lambda i, j: W[i, j] if i == j else -W[i, j])
        W = np.array(W, dtype=float, copy=True)
        return np.diag(np.diag(W)) * 2 - W

    return _wrapped(original, wrong)


@mutation("at.kinetic_angle_cos", "impactsym.mechanics:kinetic_angle_cos", "cos θ_ij negated")
def _kinetic_angle_cos(original):
    def wrong(*args, **kwargs):
        return -original(*args, **kwargs)

    return _wrapped(original, wrong)


# --------------------------------------------------------------------------- domains, compliant
@mutation("at.validity_domain", "impactsym.domains:validity_domain",
          "the domain shifted down by 1/97 in e (membership and extent)")
def _validity_domain(original):
    def wrong(*args, **kwargs):
        dom = original(*args, **kwargs)
        member = dom._member
        region = dict(dom.region)
        if isinstance(region.get("e"), tuple):
            lo, hi = region["e"]
            region["e"] = (lo - EPS, hi)
        shifted = None if member is None else (lambda a, ee: member(a, ee + EPS))
        return dataclasses.replace(dom, _member=shifted, region=region)

    return _wrapped(original, wrong)


@mutation("at.chain_impact", "impactsym.compliant:chain_impact",
          "compliant ratios scaled by (1 + m₁/97): a spurious dependence on the absolute mass")
def _chain_impact(original):
    def wrong(masses, *args, **kwargs):
        r = original(masses, *args, **kwargs)
        ratios = np.array(r.ratios, dtype=float, copy=True)
        ratios[1:] *= 1 + float(masses[0]) / 97
        return dataclasses.replace(r, ratios=ratios)

    return _wrapped(original, wrong)
