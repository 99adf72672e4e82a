"""The GPU's shadows against the exact ones (docs/shadows.md#guarantees), on every hard case
of the catalogue, at scales 1e-3, 1 and 1e3, with perspective and orthographic cameras.

These tests run as soon as the renderer draws shadows (its FeatureSet has a shadow field);
until then they are skipped, saying so. Each renders the case with and without shadows
(the shadowless image absorbs what is not about shadows) and holds the pair to the float64
ray-cast visibility with `check_shadows`, which writes a picture on failure."""

from __future__ import annotations

from dataclasses import fields, replace

import numpy as np
import pytest

from wgpu_shading.render.features import FeatureSet
from wgpu_shading.study.shadows import SHADOW_CASE_NAMES, ShadowReference, check_shadows, shadow_case

pytest.importorskip("embreex")

GPU_DRAWS_SHADOWS = any("shadow" in f.name for f in fields(FeatureSet))
needs_gpu_shadows = pytest.mark.skipif(not GPU_DRAWS_SHADOWS, reason="the renderer draws no shadows yet (FeatureSet has no shadow field)")
SIZE = (128, 128)
VARIANTS = [(1.0, "perspective"), (1.0, "orthographic"), (1e-3, "perspective"), (1e3, "orthographic")]


def without_shadows(scene):
    return replace(scene, lights=tuple(replace(light, shadows=False) for light in scene.lights))


@needs_gpu_shadows
@pytest.mark.parametrize("scale, projection", VARIANTS, ids=[f"{s:g}-{p}" for s, p in VARIANTS])
@pytest.mark.parametrize("name", SHADOW_CASE_NAMES)
def test_gpu_shadows_meet_the_guarantees(renderer, tmp_path, name, scale, projection):
    case = shadow_case(name, SIZE, scale=scale, projection=projection)
    image = renderer.render_frame(case.scene, float32=True).color
    shadowless = renderer.render_frame(without_shadows(case.scene), float32=True).color
    check_shadows(ShadowReference(case.scene), image, shadowless, name=case.name.replace("/", "-"), picture_dir=tmp_path)


@needs_gpu_shadows
def test_the_same_scene_gives_the_same_picture(renderer):
    scene = shadow_case("ring_of_boxes", SIZE).scene
    first = renderer.render_frame(scene).color
    assert all(np.array_equal(first, renderer.render_frame(scene).color) for _ in range(2))


SHADOWLESS_VARIANTS = [(name, 1.0, "perspective") for name in SHADOW_CASE_NAMES] + [
    ("sphere_over_plane_10", scale, projection) for scale, projection in VARIANTS[1:]
]


@pytest.mark.parametrize("name, scale, projection", SHADOWLESS_VARIANTS)
def test_every_case_without_shadows_matches_the_reference(renderer, name, scale, projection):
    """What the shadow check stands on: the GPU's shadowless image of each case is the
    reference's shadowless image (so the check's predictions are this scene's)."""
    from wgpu_shading.study.shadows import measure_shadows

    case = shadow_case(name, (96, 96), scale=scale, projection=projection)
    shadowless = renderer.render_frame(without_shadows(case.scene), float32=True).color
    report = measure_shadows(ShadowReference(case.scene), shadowless, shadowless)
    assert report.unrelated <= 0.002 * report.compared, f"{case.name}: {report.unrelated} pixels differ without shadows"
