"""The one JSON conversion of the package (bearing_gym/serialization.py)."""

import json
import math

import numpy as np

from bearing_gym.serialization import to_jsonable


def test_numbers_containers_and_complex_values_become_json():
    data = {1: (np.float64(1.5), np.int64(3), np.bool_(True)), "a": np.array([[1.0, np.nan]]),
            "mu": complex(-0.5, 0.25), "nmu": np.complex128(complex(math.inf, 2.0)),
            "bad": [math.nan, -math.inf], "s": "text", "none": None, "flag": False, "n": 7}
    out = to_jsonable(data)
    assert out == {"1": [1.5, 3, True], "a": [[1.0, None]], "mu": [-0.5, 0.25],
                   "nmu": [None, 2.0], "bad": [None, None], "s": "text", "none": None,
                   "flag": False, "n": 7}
    assert type(out["1"][1]) is int and type(out["1"][2]) is bool and type(out["1"][0]) is float
    # strict JSON (no NaN or Infinity tokens) round-trips
    assert json.loads(json.dumps(out, allow_nan=False)) == out
