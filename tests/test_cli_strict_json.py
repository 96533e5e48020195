"""``strict_json`` (the CLI's JSON path) gives what the plain walk over every leaf gives: its
per-list shortcut (one pass over the entries' types) changes the cost, never the output; and no
NaN or infinity leaks into the JSON (issue 15)."""

from __future__ import annotations

import json
import math
import random

import numpy as np
import pytest

from impactsym.cli.common import dumps_strict, strict_json


def _walk(obj):
    """The reference: one call per leaf (the former implementation)."""
    if isinstance(obj, dict):
        return {str(k): _walk(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_walk(v) for v in obj]
    if isinstance(obj, bool):
        return obj
    if isinstance(obj, int):
        return int(obj)
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, np.ndarray):
        return _walk(obj.tolist())
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        x = float(obj)
        return x if math.isfinite(x) else None
    return obj


_LEAVES = [0, -3, 10**30, True, False, None, "1/3", "", "sqrt(3)/2", 1.5, -0.0, 1e308, float("inf"),
           float("-inf"), float("nan"), np.float64(2.5), np.float64("inf"), np.int64(7), np.bool_(True),
           np.float32(0.25)]


def _random(rng, depth):
    roll = rng.random()
    if depth == 0 or roll < 0.3:
        return rng.choice(_LEAVES)
    if roll < 0.5:  # a row of one kind of leaf, as results mostly are
        kind = rng.choice([["1", "-1/2", "0"], [1.0, -2.5, 0.0], [1.0, float("nan"), None], [1, 2, True],
                           ["a", 1.0, None, float("inf")]])
        row = [rng.choice(kind) for _ in range(rng.randrange(0, 6))]
        return tuple(row) if rng.random() < 0.2 else row
    if roll < 0.6:
        return np.array([rng.choice([1.0, -0.5, float("inf"), float("nan")]) for _ in range(rng.randrange(1, 4))])
    if roll < 0.8:
        return [_random(rng, depth - 1) for _ in range(rng.randrange(0, 4))]
    return {rng.choice(["a", "b", 1, 2.5, None, True]): _random(rng, depth - 1) for _ in range(rng.randrange(0, 4))}


@pytest.mark.parametrize("seed", range(40))
def test_strict_json_is_the_leaf_by_leaf_walk(seed):
    obj = _random(random.Random(seed), 4)
    got, want = strict_json(obj), _walk(obj)
    assert json.dumps(got, allow_nan=False) == json.dumps(want, allow_nan=False)
    assert dumps_strict(obj) == json.dumps(want, allow_nan=False)


def test_rows_of_leaves_keep_their_values_and_drop_non_finite_floats():
    row = [1.5, float("inf"), "1e400", None, True, 3, float("nan"), -0.0]
    out = strict_json(row)
    assert out == [1.5, None, "1e400", None, True, 3, None, -0.0]
    assert math.copysign(1.0, out[-1]) == -1.0
    assert out is not row  # a copy: the caller's list is left as it was
    assert strict_json((float("-inf"),)) == [None]
    assert dumps_strict({"m": [[1.0, float("inf")], ["1", "oo"]]}) == '{"m": [[1.0, null], ["1", "oo"]]}'
