"""One name per matrix: Camera.eye_from_world() and SceneObject.world_from_model() (float64
numpy, column vectors); the old view_matrix()/model_matrix() still work, with a warning. The
float64 reference (study/reference/transforms.py) uses the same two names."""

from __future__ import annotations

import numpy as np
import pytest
from pyglm import glm

from wgpu_shading.scene import Camera, SceneObject
from wgpu_shading.scene.geometry.builtins import cube


def test_eye_from_world_by_hand():
    camera = Camera(eye=(0.0, 0.0, 5.0), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
    expected = np.eye(4)
    expected[2, 3] = -5.0  # the eye looks down −z from z = 5: the origin is 5 in front
    np.testing.assert_array_equal(camera.eye_from_world(), expected)


def test_world_from_model_by_hand():
    obj = SceneObject(cube(), translate=(1.0, 2.0, 3.0), scale=(2.0, 2.0, 2.0))
    point = obj.world_from_model() @ np.array([*(np.array([0.5, 0.0, 0.0]) - obj.mesh.origin), 1.0])
    np.testing.assert_allclose(point[:3], [2.0, 2.0, 3.0])


def test_the_old_names_warn_and_agree():
    camera = Camera(eye=(1.0, 2.0, 5.0))
    obj = SceneObject(cube(), rotate=(10.0, 20.0, 30.0))
    with pytest.warns(DeprecationWarning, match="eye_from_world"):
        assert camera.view_matrix() == glm.dmat4(camera.eye_from_world())
    with pytest.warns(DeprecationWarning, match="world_from_model"):
        assert obj.model_matrix() == glm.dmat4(obj.world_from_model())


def test_the_float64_reference_uses_the_same_names_and_agrees():
    """study/reference derives its matrices itself (numpy, from docs/conventions.md) under the
    same names; the scene's pyglm-built ones must match them."""
    from wgpu_shading.study import reference

    camera = Camera(eye=(1.0, 2.0, 5.0), target=(0.5, 0.0, -1.0))
    obj = SceneObject(cube(), translate=(1.0, -2.0, 0.5), rotate=(10.0, 20.0, 30.0), scale=(1.0, 2.0, 3.0))
    np.testing.assert_allclose(reference.eye_from_world(camera), camera.eye_from_world(), atol=1e-12)
    np.testing.assert_allclose(reference.world_from_model(obj), obj.world_from_model(), atol=1e-12)
    assert not hasattr(reference, "view_matrix") and not hasattr(reference, "model_matrix")
