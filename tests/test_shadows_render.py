"""Shadows as the renderer draws them, beyond the hard cases of test_shadows_gpu.py: only
what the scene calls for (no shadow pass or code without shadows, the same bytes), the
switches per object, every frequency (flat and Gouraud scale each light's share per
fragment), every filter, many lights, a wide spot's cube map — each held to the float64
ray-cast answer (docs/shadows.md)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.errors import SceneError
from wgpu_shading.render.features import object_features
from wgpu_shading.render.passes.frame import frame_passes
from wgpu_shading.render.passes.shadow import ShadowPass
from wgpu_shading.scene import (
    SHADOW_FILTERS,
    DirectionalLight,
    PositionalLight,
    Shading,
    ShadowSettings,
    SpotLight,
    Texture,
)
from wgpu_shading.study.shadows import ShadowReference, check_shadows, shadow_case

pytest.importorskip("embreex")

SIZE = (96, 96)


def without_shadows(scene):
    return replace(scene, lights=tuple(replace(light, shadows=False) for light in scene.lights))


def held_to_the_exact_shadows(renderer, scene, tmp_path, name):
    image = renderer.render_frame(scene, float32=True).color
    shadowless = renderer.render_frame(without_shadows(scene), float32=True).color
    return check_shadows(ShadowReference(scene), image, shadowless, name=name, picture_dir=tmp_path)


# ----------------------------------------------------------------------------- only what the scene calls for


@pytest.mark.parametrize("change", ["no light casts", "nothing casts", "nothing receives"])
def test_a_scene_with_nothing_to_shadow_draws_the_same_bytes_without_a_shadow_pass(renderer, change):
    scene = shadow_case("two_lights", SIZE).scene
    plain = without_shadows(scene)
    if change == "nothing casts":
        scene = replace(scene, objects=tuple(replace(o, cast_shadows=False) for o in scene.objects))
    elif change == "nothing receives":
        scene = replace(scene, objects=tuple(replace(o, receive_shadows=False) for o in scene.objects))
    else:
        scene = plain
    assert not any(isinstance(p, ShadowPass) for p in frame_passes(scene))
    assert all(object_features(scene, obj).shadow_lights == 0 for obj in scene.objects)
    for float32 in (False, True):
        assert np.array_equal(renderer.render_frame(scene, float32=float32).color, renderer.render_frame(plain, float32=float32).color)
    assert any(isinstance(p, ShadowPass) for p in frame_passes(shadow_case("two_lights", SIZE).scene))


def test_an_object_that_does_not_receive_compiles_without_the_lookup_and_is_lit(renderer, tmp_path):
    case = shadow_case("sphere_over_plane_30", SIZE)
    ball, ground = case.scene.objects
    ground = replace(ground, receive_shadows=False)
    scene = replace(case.scene, objects=(ball, ground))
    assert object_features(scene, ground).shadow_lights == 0 and object_features(scene, ball).shadow_lights == 1
    report = held_to_the_exact_shadows(renderer, scene, tmp_path, "ground-does-not-receive")
    assert report.lights[0].matters > 0  # the ball's own shadow side is still checked


def test_an_object_that_does_not_cast_leaves_no_shadow(renderer, tmp_path):
    case = shadow_case("quad_occluder", SIZE)
    quad, ground = case.scene.objects
    scene = replace(case.scene, objects=(replace(quad, cast_shadows=False), ground))
    held_to_the_exact_shadows(renderer, scene, tmp_path, "quad-does-not-cast")
    image = renderer.render(scene)
    assert np.array_equal(image, renderer.render(without_shadows(scene)))  # nothing else can shadow anything here


# ----------------------------------------------------------------------------- frequencies, filters, lights


TEXTURE = Texture(np.full((4, 4, 4), 200, np.uint8))


@pytest.mark.parametrize("frequency", ["flat", "gouraud"])
@pytest.mark.parametrize("variant", ["plain", "two-sided clamped", "textured"])
def test_flat_and_gouraud_shading_scale_each_lights_share_per_fragment(renderer, tmp_path, frequency, variant):
    case = shadow_case("two_lights", SIZE)
    shading = Shading(frequency=frequency, two_sided=variant != "plain", clamp_vertex_colors=variant != "plain")
    scene = replace(case.scene, shading=shading)
    if variant == "textured":  # modulate: the specular share apart from the ambient-diffuse one
        ball, ground = scene.objects
        material = replace(ball.material, specular=(0.5, 0.5, 0.5, 1.0), shininess=30.0, texture=TEXTURE, texture_mode="modulate")
        ball = replace(ball, material=material)
        scene = replace(scene, objects=(ball, ground))
        assert object_features(scene, ball).defines()["SHADOW_SPLIT"]
    held_to_the_exact_shadows(renderer, scene, tmp_path, f"{frequency}-{variant}")


def test_flat_and_gouraud_shading_take_at_most_four_casting_lights():
    scene = shadow_case("sphere_over_plane_30", SIZE).scene
    scene = replace(scene, lights=scene.lights * 5, shading=Shading(frequency="gouraud"))
    with pytest.raises(SceneError, match="at most 4 casting lights"):
        object_features(scene, scene.objects[0])


@pytest.mark.parametrize("shadow_filter", SHADOW_FILTERS)
def test_every_filter_keeps_the_boundary_and_has_no_acne(renderer, tmp_path, shadow_filter):
    case = shadow_case("sphere_over_plane_30", SIZE)
    scene = replace(case.scene, shadows=ShadowSettings(map_size=1024, filter=shadow_filter, bias=3.0))
    held_to_the_exact_shadows(renderer, scene, tmp_path, f"filter-{shadow_filter}")


def test_five_casting_lights_of_every_kind(renderer, tmp_path):
    case = shadow_case("sphere_over_plane_30", SIZE)
    dim = dict(diffuse=(0.25, 0.25, 0.25, 1.0), specular=(0.1, 0.1, 0.1, 1.0), shadows=True)
    lights = (
        DirectionalLight(direction=(0.4, -1.0, 0.3), **dim),
        PositionalLight(position=(-3.0, 6.0, 2.0), **dim),
        SpotLight(position=(2.0, 7.0, -1.0), direction=(-0.2, -1.0, 0.1), cutoff=35.0, **dim),
        DirectionalLight(direction=(-0.6, -1.0, -0.2), **dim),
        PositionalLight(position=(4.0, 3.0, 4.0), **dim),
    )
    held_to_the_exact_shadows(renderer, replace(case.scene, lights=lights), tmp_path, "five-lights")


def test_a_spot_too_wide_for_one_view_shadows_through_a_cube_map(renderer, tmp_path):
    case = shadow_case("sphere_over_plane_30", SIZE)
    spot = SpotLight(position=(0.5, 3.4, 0.3), direction=(0.0, -1.0, 0.0), cutoff=80.0, exponent=1.0, shadows=True)
    held_to_the_exact_shadows(renderer, replace(case.scene, lights=(spot,)), tmp_path, "wide-spot")


def test_antialiased_frames_with_depth_read_the_same_maps(renderer):
    scene = replace(shadow_case("ring_of_boxes", SIZE).scene, samples=4)
    frame = renderer.render_frame(scene, depth=True)
    plain = renderer.render_frame(without_shadows(scene), depth=True)
    assert np.array_equal(frame.depth, plain.depth)  # shadows change colours, not what is where
    assert (frame.color[..., :3].astype(int).sum(-1) < plain.color[..., :3].astype(int).sum(-1)).mean() > 0.2



def test_maps_are_reused_only_while_they_would_be_the_same(renderer):
    """An unchanged scene reuses its maps; a moved caster, another camera or light redraws
    them; frames in flight each see their own (a queue runs its frames in order)."""
    case = shadow_case("sphere_over_plane_30", SIZE)
    ball, ground = case.scene.objects
    moved = replace(case.scene, objects=(replace(ball, translate=(0.6, 2.0, 0.2)), ground))
    lower_sun = replace(case.scene, lights=(replace(case.scene.lights[0], direction=(0.5, -0.4, 0.3)),))
    scenes = [case.scene, moved, case.scene, lower_sun, case.scene]
    alone = [renderer.render(scene) for scene in scenes]
    assert np.array_equal(alone[0], alone[2]) and np.array_equal(alone[0], alone[4])
    assert not np.array_equal(alone[0], alone[1]) and not np.array_equal(alone[0], alone[3])
    fresh = [renderer.render(replace(scene, shadows=ShadowSettings(map_size=1000))) for scene in (moved, lower_sun)]
    assert not np.array_equal(fresh[0], fresh[1])
    in_flight = list(renderer.render_many(scenes, in_flight=3, parallel=1))
    assert all(np.array_equal(a, b.color) for a, b in zip(alone, in_flight))
