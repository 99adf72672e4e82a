"""Frame plans (render/gpu/frame_plans.py): a Scene object drawn again reuses what the colour
pass prepared for it, never after the caches its draws use have changed, and never keeps an
upload or a scene alive. The reference for every image is a new Scene object equal to the
old one (which always takes the full path), on a Renderer of its own."""

from __future__ import annotations

import gc
import weakref
from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading import Camera, PositionalLight, Renderer, Scene, SceneObject, Texture, load_mesh, material
from wgpu_shading.render.gpu.caches import ObjectCache
from wgpu_shading.render.passes import color


def torus_scene(segments: int = 24, **changes) -> Scene:
    scene = Scene(
        objects=(SceneObject(load_mesh(f"builtin:torus?segments={segments}"), material("gold"), rotate=(35, 0, 0)),),
        lights=(PositionalLight(position=(5, 2, 2)),),
        camera=Camera(eye=(0, 0, 3), fov_y=50),
        size=(48, 40),
    )
    return replace(scene, **changes)


@pytest.fixture
def counted(monkeypatch) -> list[int]:
    """How many object uniform blocks the colour pass has computed (one per draw it prepares)."""
    calls = [0]
    original = color.object_uniforms

    def counting(*args, **kwargs):
        calls[0] += 1
        return original(*args, **kwargs)

    monkeypatch.setattr(color, "object_uniforms", counting)
    return calls


def test_the_same_scene_object_is_prepared_once_and_drawn_the_same(counted):
    ours, reference = Renderer(), Renderer()
    scene = torus_scene()
    images = [ours.render(scene) for _ in range(4)]
    assert counted[0] == 1, "frames after the first prepared their draws again"
    expected = reference.render(replace(scene))
    for image in images:
        np.testing.assert_array_equal(image, expected)
    other = replace(scene, camera=Camera(eye=(0, 1, 3), fov_y=50))  # a new object: prepared anew
    np.testing.assert_array_equal(ours.render(other), reference.render(replace(other)))
    assert counted[0] == 4  # once for each new object, on each renderer


def test_every_variant_of_a_frame_keeps_its_own_plan(counted):
    """Colour, float colour, depth and 4× MSAA of one scene object: each drawn from the plan
    of its own format and samples, equal to a new object's frame."""
    ours, reference = Renderer(), Renderer()
    scene = torus_scene(samples=1)
    msaa = torus_scene(samples=4)
    for _ in range(2):
        for frame_of in (lambda r, s: r.render_frame(s, depth=True), lambda r, s: r.render_frame(s, float32=True)):
            frame, expected = frame_of(ours, scene), frame_of(reference, replace(scene))
            np.testing.assert_array_equal(frame.color, expected.color)
        frame, expected = ours.render_frame(msaa, depth=True), reference.render_frame(replace(msaa), depth=True)
        np.testing.assert_array_equal(frame.color, expected.color)
        np.testing.assert_array_equal(frame.depth, expected.depth)


def test_a_plan_is_not_used_once_its_upload_was_evicted():
    """With room for one mesh upload, drawing another scene evicts the first scene's upload;
    drawing the first again must upload it again, not draw the evicted buffers."""
    ours, reference = Renderer(), Renderer()
    cache = ours.device_cache
    cache.meshes = ObjectCache(1)  # room for one upload
    first, second = torus_scene(16), torus_scene(20)
    expected = [reference.render(replace(first)), reference.render(replace(second))]
    np.testing.assert_array_equal(ours.render(first), expected[0])
    upload = cache.meshes.get(first.objects[0].mesh)
    np.testing.assert_array_equal(ours.render(second), expected[1])
    assert cache.meshes.get(first.objects[0].mesh) is None  # evicted
    evicted = weakref.ref(upload)
    del upload
    gc.collect()
    assert evicted() is None, "a kept plan holds the evicted upload alive"
    np.testing.assert_array_equal(ours.render(first), expected[0])
    assert cache.meshes.get(first.objects[0].mesh) is not None  # uploaded again


def test_a_plan_goes_with_its_scene_and_the_plans_are_bounded():
    ours = Renderer()
    scene = torus_scene()
    ours.render(scene)
    assert len(ours.device_cache.frame_plans) == 1
    gone = weakref.ref(scene)
    del scene
    gc.collect()
    assert gone() is None, "the plan keeps its scene alive"
    assert len(ours.device_cache.frame_plans) == 0
    first = torus_scene()
    kept = [replace(first, camera=Camera(eye=(0, 0, 3 + k / 10), fov_y=50)) for k in range(20)]  # one mesh
    for scene in kept:
        ours.render(scene)
    from wgpu_shading.render.gpu.caches import FRAME_PLAN_ENTRIES

    assert len(ours.device_cache.frame_plans) == FRAME_PLAN_ENTRIES


def test_a_new_texture_upload_drops_the_plans_made_before_it(counted):
    """Any change to the uploads (here a texture's first upload) drops every plan: a plan is
    only used against the caches it was made with."""
    ours = Renderer()
    scene = torus_scene()
    ours.render(scene)
    pixels = np.full((4, 4, 4), 200, np.uint8)
    plane = load_mesh("builtin:plane")
    textured = replace(scene, objects=(SceneObject(plane, replace(material("silver"), texture=Texture(pixels))),))
    ours.render(textured)
    assert len(ours.device_cache.frame_plans) == 1  # the textured scene's only
    before = counted[0]
    ours.render(scene)
    assert counted[0] == before + 1


def test_the_same_scene_object_gets_its_clusters_when_they_are_built(monkeypatch):
    """A plan is kept only once no cluster build can start or finish (each frame asks for
    them): the same scene object drawn over and over still switches to the clustered
    upload, and draws the same pixels as every triangle does."""
    from pyglm import glm

    from benchmarks.scenes import TINY_SPHERE_TRIANGLES, settle, sphere_scene

    monkeypatch.delenv("WGPU_SHADING_CLUSTERS", raising=False)
    scene = sphere_scene(64, TINY_SPHERE_TRIANGLES)
    ours = Renderer()
    settle(ours, scene)  # the frames that pay for the clusters, then their build
    image = ours.render(scene)
    plan = color.color_plan(ours.device_cache, scene, "rgba8", glm.dmat4(scene.camera.eye_from_world()))
    assert plan.draws[0].ranges is not None, "the scene's draws stayed those made before its clusters"
    assert ours.device_cache.frame_plans.get(scene, ("colour", "rgba8", 1, True)) is plan  # and it is kept
    monkeypatch.setenv("WGPU_SHADING_CLUSTERS", "0")  # read per frame: the plan's key holds it
    np.testing.assert_array_equal(ours.render(scene), image)
    plan = color.color_plan(ours.device_cache, scene, "rgba8", glm.dmat4(scene.camera.eye_from_world()))
    assert plan.draws[0].ranges is None
