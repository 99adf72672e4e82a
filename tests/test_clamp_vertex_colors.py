"""[shading] clamp_vertex_colors (docs/conventions.md#shading-frequencies): the seeds' GLSL interpolates unclamped vertex
colors (default); OpenGL fixed-function clamps each vertex's color first. Both rules on the
GPU against the float64 reference, which implements both (reference_lighting.clamp_vertex_colors):
within 1/255 on 99.9 % of the covered pixels, as every same-mesh comparison."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.scene import cube, DirectionalLight, Material, PositionalLight, Scene, SceneObject, Shading, uv_sphere
from wgpu_shading.study import reference as ref

from support import EDGE_BAND, compare, smooth_texture


def over_lit_scene(frequency: str, texture_mode: str | None, clamp: bool) -> Scene:
    # Two strong lights: vertex colors well above 1 on the lit side, so clamping before or
    # after interpolation gives visibly different gradients on a coarse sphere.
    surface = Material(ambient=(0.3, 0.25, 0.2, 1), diffuse=(0.9, 0.7, 0.5, 1), specular=(0.8, 0.8, 0.8, 1), shininess=12.0)
    # The texture goes on a cube (its faces magnify it: the reference samples level 0 only).
    textured = replace(surface, texture=smooth_texture(), texture_mode=texture_mode) if texture_mode else surface
    return Scene(
        objects=(
            SceneObject(uv_sphere(0.55, slices=10, stacks=6), surface, rotate=(15, 20, 0), translate=(0.6, 0.1, 0)),
            SceneObject(cube(1.1), textured, rotate=(30, 40, 0), translate=(-0.5, -0.1, 0)),
        ),
        lights=(
            DirectionalLight(direction=(-0.4, -0.6, -1.0), diffuse=(1.2, 1.1, 1.0, 1)),
            PositionalLight(position=(2.0, 1.5, 2.5), diffuse=(0.8, 0.8, 0.8, 1), specular=(1.5, 1.5, 1.5, 1)),
        ),
        size=(112, 96),
        shading=Shading(frequency=frequency, clamp_vertex_colors=clamp),
    )


@pytest.mark.parametrize("texture_mode", [None, "modulate", "modulate_all"])
@pytest.mark.parametrize("frequency", ["gouraud", "flat"])
@pytest.mark.parametrize("clamp", [False, True])
def test_gpu_matches_the_reference_with_and_without_the_vertex_clamp(renderer, frequency, texture_mode, clamp):
    scene = over_lit_scene(frequency, texture_mode, clamp)
    reference = ref.render_reference(scene)
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    compare(gpu, reference, EDGE_BAND, f"{frequency} / texture {texture_mode} / clamp {clamp}")


@pytest.mark.parametrize("texture_mode", [None, "modulate"])
def test_the_clamp_changes_gouraud_where_vertex_colors_exceed_one(renderer, texture_mode):
    seeds = renderer.render(over_lit_scene("gouraud", texture_mode, False), float32=True)
    opengl = renderer.render(over_lit_scene("gouraud", texture_mode, True), float32=True)
    difference = np.abs(seeds - opengl)[:, :, :3].max(axis=-1)
    assert difference.max() > 20 / 255  # the seeds' interpolation keeps more of the over-bright colour
    assert (opengl[:, :, :3] <= seeds[:, :, :3] + 1e-6).all()  # clamping first never brightens


def test_phong_ignores_the_flag_and_shares_its_pipeline(renderer):
    phong = over_lit_scene("phong", None, False)
    clamped = replace(phong, shading=replace(phong.shading, clamp_vertex_colors=True))
    assert renderer.features(phong) == renderer.features(clamped)
