"""Validation of scene values (scene/values.py): the shortcut for tuples already normalized
(every view of a dataset derives its scene from another) accepts exactly what the full
checks accept."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgpu_shading.errors import SceneError
from wgpu_shading.scene.values import finite_numbers


@pytest.mark.parametrize("value", [(1.0, 2.0, 3.0), (1e308, 1e308, -1e308), (-0.0, 0.0, 5e-324)])
def test_finite_float_tuples_come_back_as_they_are(value):
    assert finite_numbers(value, "eye", (3,)) == value  # a sum that overflows still passes: its items are finite


@pytest.mark.parametrize("value", [(1.0, math.nan, 0.0), (math.inf, 0.0, 0.0), (1.0, -math.inf, math.inf)])
def test_a_tuple_with_nan_or_infinity_is_refused_naming_the_key(value):
    with pytest.raises(SceneError, match="eye: expected finite numbers"):
        finite_numbers(value, "eye", (3,))


@pytest.mark.parametrize("value, message", [((1.0, 2.0), "expected 3 numbers"), ((1.0, 2.0, True), "expected numbers"),
                                            ("abc", "expected a list")])
def test_other_shapes_and_types_still_get_their_own_error(value, message):
    with pytest.raises(SceneError, match=message):
        finite_numbers(value, "eye", (3,))


def test_lists_and_numpy_numbers_become_float_tuples():
    result = finite_numbers([1, np.float32(0.5), np.int64(2)], "eye", (3,))
    assert result == (1.0, 0.5, 2.0) and all(type(item) is float for item in result)
