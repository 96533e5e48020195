"""The sequential law's limits and the names it uses for the exact arithmetic.

The fields and the linear algebra are :mod:`impactsym.arithmetic`'s; the short private names below
are the ones the search and the selection were written with.
"""

from __future__ import annotations

import numpy as np

from ...arithmetic import AlgebraicField as _Algebraic
from ...arithmetic import RationalField as _Rational
from ...arithmetic import all_rational as _all_rational
from ...arithmetic.linalg import dot as _dot
from ...arithmetic.linalg import independent as _independent
from ...arithmetic.linalg import kernel_basis as _kernel_basis
from ...arithmetic.linalg import matvec as _matvec
from ...arithmetic.linalg import minner as _minner
from ...arithmetic.linalg import nullspace as _nullspace
from ...arithmetic.linalg import rank as _rank
from ...arithmetic.linalg import rref as _rref
from ...arithmetic.linalg import solve_columns as _solve_columns

__all__ = ["READINGS", "TWO_SURFACE_PATHS", "AUTO_ITERATE_MAX_COUNT", "DEFAULT_MAX_REFLECTIONS", "MAX_STATE_BITS",
           "MAX_COORDINATES",
           "FLOAT_SAFETY", "_Rational", "_Algebraic", "_all_rational", "_rref", "_kernel_basis", "_nullspace",
           "_solve_columns", "_rank", "_independent", "_dot", "_matvec", "_minner"]

#: the two readings of the feasible set (see the package docstring)
READINGS = ("energy", "cone")
#: how two independent surfaces are resolved (see ``resolve_sequential(two_surface=...)``)
TWO_SURFACE_PATHS = ("auto", "closed-form", "iterate")
#: ``two_surface="auto"`` iterates exact rational data when the paper's bound ``N`` (the longest
#: branch for any velocity) is certainly at most this; the closed form otherwise. Measured
#: (``benchmarks/two_surface.py``, "path by the certified count"): once the closed form is handed
#: the checked data (no second validation) the two cost the same near N = 7 (about 0.6 ms);
#: beyond, the iteration's cost grows with the count and its numbers, the closed form's does not
AUTO_ITERATE_MAX_COUNT = 7
#: default cap on the reflections of any one ordering
DEFAULT_MAX_REFLECTIONS = 10_000
#: largest total size (bits of numerators and denominators) of the exact velocities the rational
#: search keeps; beyond it the search raises NonTermination naming this limit (32 MiB)
MAX_STATE_BITS = 1 << 28
#: largest number of coordinates (size of M) the resolver accepts. Exact rational input is read
#: and searched in sparse form (:mod:`.sparse`): a one-striker cradle costs about linear time in
#: its balls (1000 balls: well under a second for the law), so the limit only guards against
#: inputs whose exact linear algebra is dense (a dense n×n M costs O(n³) exact operations to
#: check and factor, and every state of the search O(n)); larger systems are refused up front
MAX_COORDINATES = 10_000
#: safety factor on the float sign-test bound
FLOAT_SAFETY = 4.0
_EPS = float(np.finfo(float).eps)
