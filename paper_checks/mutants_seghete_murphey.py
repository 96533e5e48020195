"""Mutations used by the claims of ``paper_checks/seghete_murphey.py`` (see :mod:`paper_checks.mutations`).

Each mutant is a wrong but well-typed version of one derivation or law: it returns the same kind
of object as the original (a :class:`~derivations.reflection.Derivation` whose root is off, a
:class:`~impactsym.laws.sequential.SequentialResolution` whose exit velocities break energy
conservation, a bound one too small, ...), so that a claim resting on it reaches another verdict
or raises, instead of failing on a type error.

>>> from paper_checks.mutations import MUTATIONS
>>> sorted(k for k in MUTATIONS if k.startswith("sm."))[:3]
['sm.area_step_counterexample', 'sm.balls_on_line', 'sm.block_determinant_lemma']
"""

from __future__ import annotations

import dataclasses
import functools

import sympy as sp

from .mutations import EPS, corrupting, mutation  # noqa: F401


def _marked(wrong):
    wrong.__wrapped_mutant__ = True
    return wrong


@mutation("sm.derive_single_impact", "derivations.reflection:derive_single_impact",
          "eqs. 1a-1b solved wrongly: λ scaled by 1 + 1/97, q̇⁺ (and G = ∂q̇⁺/∂q̇⁻) taken at λ(1 + 2/97), "
          "so neither the momentum balance nor the energy balance holds; the flags are recomputed")
def _derive_single_impact(original):
    from derivations import reflection as drefl

    @functools.wraps(original)
    def wrong(n):
        d = original(n)
        lam = d.lam * (1 + EPS)
        # the same wrong q̇⁺ and G as (q̇⁻ − λ(1 + 2/97)M⁻¹uᵀ).applyfunc(cancel) and its Jacobian, built
        # the way the derivation builds its own (flint's cancel, the Jacobian of a linear map read off
        # column by column, checked); the zero root decided by the exact zero test (simplify as fallback)
        qplus = (d.qminus - d.lam * (1 + 2 * EPS) * d.M.LUsolve(d.u.T)).applyfunc(drefl.cancel)
        G = drefl._jacobian_of_linear(qplus, d.qminus)
        roots = [r if drefl.is_zero(r) else lam for r in d.roots]
        out = dataclasses.replace(d, lam=lam, qplus=qplus, G=G, roots=roots)
        out.matches_printed_G = drefl._matrix_is_zero(G - drefl.printed_G(d.M, d.u))
        out.matches_printed_lambda = drefl._is_zero_rational(lam - drefl.printed_lambda(d.M, d.u, d.qminus))
        return out

    return _marked(wrong)


@mutation("sm.derive_general", "derivations.reflection:derive_general",
          "general-n derivation with λ and G = 1 − 2(1 + 1/97)WU/s off by 1/97 (q̇⁺ = Q − λW kept)")
def _derive_general(original):
    from derivations import reflection as drefl

    @functools.wraps(original)
    def wrong(restitution=False):
        d = original(restitution)
        lam = d.lam * (1 + EPS)
        G = 1 - (2 if not restitution else 1 + drefl.e_) * (1 + EPS) * drefl.W * drefl.U / drefl.s_
        out = dataclasses.replace(d, lam=lam, G=G)
        coeff = 2 if not restitution else 1 + drefl.e_
        out.matches_printed_lambda = sp.simplify(lam - coeff * drefl.c_ / drefl.s_) == 0
        return out

    return _marked(wrong)


@mutation("sm.run_proof", "derivations.reflection:run_proof",
          "every machine proof of a property of G_u reports proven=False")
def _run_proof(original):
    @functools.wraps(original)
    def wrong(name, dimension):
        return dataclasses.replace(original(name, dimension), proven=False)

    return _marked(wrong)


def _corrupt_velocity(v, k: int):
    out = sp.Matrix(v)
    out[0] = out[0] + k * EPS
    return out


@mutation("sm.resolve_sequential", "impactsym.laws.sequential:resolve_sequential",
          "sequential resolution whose exit velocities are off by 1/97 (energy no longer conserved), "
          "whose selection is off by 2/97, and which counts every ordering twice")
def _resolve_sequential(original):
    @functools.wraps(original)
    def wrong(*args, **kwargs):
        r = original(*args, **kwargs)
        outs = tuple(dataclasses.replace(o, velocity=_corrupt_velocity(o.velocity, 1)) for o in r.outcomes)
        sel = tuple(_corrupt_velocity(v, 2) for v in r.selected)
        return dataclasses.replace(r, outcomes=outs, selected=sel, orderings=2 * r.orderings)

    return _marked(wrong)


@mutation("sm.termination_bound", "impactsym.laws.sequential:termination_bound",
          "the two-surface bound N = ⌈π/β⌉ of sec. III-C one too small")
def _termination_bound(original):
    @functools.wraps(original)
    def wrong(*args, **kwargs):
        return original(*args, **kwargs) - 1

    return _marked(wrong)


@mutation("sm.newton_moreau", "impactsym.laws.classical:newton_moreau",
          "Newton-Moreau law whose post-impact velocity is off by 1/97 in its first entry")
def _newton_moreau(original):
    @functools.wraps(original)
    def wrong(*args, **kwargs):
        r = original(*args, **kwargs)
        return dataclasses.replace(r, velocity=_corrupt_velocity(r.velocity, 1))

    return _marked(wrong)


@mutation("sm.kinetic_energy", "impactsym.mechanics:kinetic_energy",
          "kinetic energy scaled by 1 + 1/97")
def _kinetic_energy(original):
    @functools.wraps(original)
    def wrong(M, v):
        return original(M, v) * (1 + EPS)

    return _marked(wrong)


@mutation("sm.balls_on_line", "impactsym.scenes:balls_on_line",
          "scene builder that gives every closed contact the gradient of the first one")
def _balls_on_line(original):
    @functools.wraps(original)
    def wrong(*args, **kwargs):
        sc = original(*args, **kwargs)
        H = sp.Matrix(sc.H)
        for i in range(1, H.rows):
            H[i, :] = H[0, :]
        return dataclasses.replace(sc, H=H)

    return _marked(wrong)


@mutation("sm.block_determinant_lemma", "derivations.algebra:block_determinant_lemma",
          "the block identity behind the determinant lemma reported as not verified")
def _block_determinant_lemma(original):
    @functools.wraps(original)
    def wrong():
        product, _ok = original()
        return product, False

    return _marked(wrong)


@mutation("sm.reachable_arc_lengths", "derivations.two_surface:reachable_arc_lengths",
          "reachable arcs that grow by an extra π/97 at every iteration")
def _reachable_arc_lengths(original):
    @functools.wraps(original)
    def wrong(beta_over_pi, iterations):
        return [L + k * sp.pi * EPS for k, L in enumerate(original(beta_over_pi, iterations))]

    return _marked(wrong)


@mutation("sm.area_step_counterexample", "derivations.two_surface:area_step_counterexample",
          "the sphere counterexample with the union area computed as 2·cap (the mirror caps overlapping)")
def _area_step_counterexample(original):
    @functools.wraps(original)
    def wrong():
        cx = original()
        return {**cx, "union_area": cx["two_max"]}

    return _marked(wrong)


@mutation("sm.bound_versus_count", "derivations.two_surface:bound_versus_count",
          "exact reflection counts one more than the true maximum (so they exceed N)")
def _bound_versus_count(original):
    @functools.wraps(original)
    def wrong(beta_over_pi):
        r = original(beta_over_pi)
        return {**r, "max_count": r["max_count"] + 1}

    return _marked(wrong)
