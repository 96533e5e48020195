"""The float path of the impulse-ratio family never returns NaN or a silently wrong outcome when
float64 overflows (issue 15's cost model found energetic returning NaN on a dense 64x64 M)."""

from __future__ import annotations

import numpy as np
import pytest

from impactsym import lawbook
from impactsym.cost_model import dense_system
from impactsym.errors import DomainError
from impactsym.resolution import System


def _floats(problem):
    return (np.array(problem.M.tolist(), dtype=float), np.array(problem.H.tolist(), dtype=float),
            np.array(problem.v.tolist(), dtype=float).ravel())


def test_energetic_float_path_huge_exact_direction_is_scaled_not_overflowed():
    """The default direction (the elastic Newton/Moreau impulse, exact) has entries near 1e168 on
    this system; the float outcome must be finite and agree with the exact one."""
    p = dense_system(64)
    fl = lawbook.resolve("energetic", System(*_floats(p)))
    ex = lawbook.resolve("energetic", System(p.M, p.H, p.v))
    vf = np.asarray(fl.answer.velocity, dtype=float)
    ve = np.array([float(x) for x in ex.answer.velocity])
    assert np.all(np.isfinite(vf))
    assert np.max(np.abs(vf - ve)) <= 1e-9 * np.max(np.abs(ve))


@pytest.mark.parametrize("speed", [1e155, 1e200])
def test_float_overflow_of_the_energy_balance_raises(speed):
    """At v = (1e155, 0, 0) the energy balance's coefficients overflow float64 (B^2 = inf, and
    (1 - e) T = 0 * inf = NaN at e = 1): the law refuses instead of returning the plastic
    outcome a NaN discriminant used to produce."""
    system = System(np.eye(3), np.array([[-1.0, 1, 0], [0, -1, 1]]), np.array([speed, 0, 0]))
    with pytest.raises(DomainError, match="float path overflowed"):
        lawbook.resolve("energetic", system)


def test_float_path_ordinary_direction_is_unchanged():
    """A ratio direction of ordinary size is not rescaled: the reported A, B, C and ratios are the
    given direction's (a = (1, 1/2): r = H^T a = (-1, 1/2, 1/2), A = r.r/2 = 3/4, B = a.Hv = -1)."""
    from impactsym.laws.impulse_ratio import impulse_ratio_law
    r = impulse_ratio_law(np.eye(3), np.array([[-1.0, 1, 0], [0, -1, 1]]), np.array([1.0, 0, 0]), 1.0, [0.5])
    assert tuple(r.coefficients) == (0.75, -1.0, 0.0)
    assert [float(x) for x in r.ratios] == [1.0, 0.5]
