"""Dispatch for the generated NumPy kernels (hand-written, not generated; imported by every
generated NumPy module in impactsym/kernels/ that has a plain-Python form; that folder holds
generated files only).

A call whose arguments are all Python or NumPy scalars goes to the kernel's plain-Python form
(38-640x faster on one point); a batch larger than ``2 * CHUNK`` points is evaluated ``CHUNK``
points at a time (cache); both measured in ``benchmarks/results/scalar_dispatch.md``.

>>> _scalars(1.0, 2), _scalars(1.0, numpy.ones(2))
(True, False)
"""

import numpy

_SCALAR_TYPES = (float, int, numpy.float64)

#: batches larger than 2 * CHUNK points are evaluated CHUNK points at a time
#: (benchmarks/results/scalar_dispatch.md)
CHUNK = 65536


def _scalars(*xs):
    """Every argument a Python or NumPy float or int: the call goes to the plain-Python form."""
    return all(type(x) in _SCALAR_TYPES for x in xs)


def _large(*xs):
    return max(numpy.size(x) for x in xs) > 2 * CHUNK and numpy.broadcast_shapes(*(numpy.shape(x) for x in xs))


def _chunked(f, xs, n_out):
    """``f(*xs)`` evaluated CHUNK broadcast points at a time (same values: the kernels are pointwise)."""
    shape = numpy.broadcast_shapes(*(numpy.shape(x) for x in xs))
    flat = [numpy.broadcast_to(numpy.asarray(x, dtype=float), shape).reshape(-1) for x in xs]
    size = flat[0].size
    outs = [numpy.empty(size) for _ in range(n_out)]
    for start in range(0, size, CHUNK):
        part = f(*(x[start:start + CHUNK] for x in flat))
        for o, r in zip(outs, part if n_out > 1 else (part,)):
            o[start:start + CHUNK] = r
    outs = [o.reshape(shape) for o in outs]
    return tuple(outs) if n_out > 1 else outs[0]
