"""Threads: one Renderer shared by several threads returns exactly the images that
sequential rendering returns; a lost default device is replaced by a fresh one."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import DeviceError, Renderer, SceneError, load_scene
from wgpu_shading.render import device as device_module

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SCENES = [
    "gold_torus_phong.toml",
    "gold_torus_flat.toml",
    "red_spotlight.toml",
    "two_lights.toml",
    "checker_sphere_modulate.toml",
    "opengl_init_sphere_emission.toml",
]


def _distinct_scenes() -> list:
    """Distinct pictures: different feature sets, sizes, cameras and object counts."""
    scenes = []
    for index, name in enumerate(SCENES):
        scene = load_scene(EXAMPLES / name)
        size = (48 + 8 * index, 40 + 4 * index)
        scene = replace(scene, size=size, camera=replace(scene.camera, eye=tuple(e * (1 + 0.05 * index) for e in scene.camera.eye)))
        scenes.append(scene)
    return scenes


def test_threads_sharing_a_renderer_get_the_images_of_sequential_rendering(renderer):
    scenes = _distinct_scenes()
    expected = [renderer.render(scene) for scene in scenes]
    assert len({e.tobytes() for e in expected}) == len(scenes)  # every picture differs
    shared = Renderer(device=renderer.device)
    jobs = [(index % len(scenes)) for index in range(48)]
    barrier = threading.Barrier(6)

    def render(index: int) -> tuple[int, np.ndarray]:
        if index < 6:
            barrier.wait()  # start the first frames together
        return index, shared.render(scenes[index])

    with ThreadPoolExecutor(max_workers=6) as pool:
        results = list(pool.map(render, jobs))
    wrong = [index for index, image in results if not np.array_equal(image, expected[index])]
    assert not wrong, f"{len(wrong)} of {len(results)} images differ from sequential rendering (scenes {wrong[:8]})"


def test_render_many_in_one_thread_and_render_in_another_do_not_mix(renderer):
    scenes = _distinct_scenes()
    expected = [renderer.render(scene) for scene in scenes]
    shared = Renderer(device=renderer.device)
    errors: list[str] = []

    def batch() -> None:
        for round_ in range(3):
            for index, frame in enumerate(shared.render_many(scenes, parallel=1)):
                if not np.array_equal(frame.color, expected[index]):
                    errors.append(f"render_many round {round_} scene {index}")

    def single() -> None:
        for round_ in range(3):
            for index in reversed(range(len(scenes))):
                if not np.array_equal(shared.render(scenes[index]), expected[index]):
                    errors.append(f"render round {round_} scene {index}")

    threads = [threading.Thread(target=batch), threading.Thread(target=single)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []


def test_rendering_something_that_is_not_a_scene_is_a_clear_error(renderer):
    with pytest.raises(SceneError, match=r"render: expected a Scene, got dict"):
        renderer.render({"objects": []})
    with pytest.raises(SceneError, match=r"expected a Scene, got str \(load a scene file with load_scene"):
        renderer.render("scene.toml")
    with pytest.raises(SceneError, match=r"render_many: scene 1: expected a Scene, got int"):
        list(renderer.render_many([_distinct_scenes()[0], 3]))


def test_a_lost_default_device_is_replaced_by_a_fresh_one():
    # "llvmpipe" is its own selector, so this test's default device is not the session's.
    scene = replace(load_scene(EXAMPLES / "gold_torus_phong.toml"), size=(32, 32))
    first = Renderer(adapter="llvmpipe")
    before = first.render(scene)
    first.device.destroy()  # what a driver reset or a lost GPU does to it
    with pytest.raises(DeviceError, match="the wgpu device was lost"):
        first.render(replace(scene, size=(33, 32)))
    second = Renderer(adapter="llvmpipe")
    assert second.device is not first.device
    np.testing.assert_array_equal(second.render(scene), before)
    assert device_module.default_device("llvmpipe") is second.device


def test_threads_playing_animations_and_drawing_points_edges_and_shadows_match_sequential(renderer):
    """The newer features from several threads at once, scenes made in the threads too: one
    AnimationFrames shared by all (its parsed file is posed under a lock), a point cloud,
    edges over shading, shadows; every image equal to the one drawn alone, in order."""
    from wgpu_shading.assets.animation_frames import AnimationFrames
    from wgpu_shading.assets.view_loader import load_view
    from wgpu_shading.scene.view.options import ViewOptions

    data = Path(__file__).resolve().parent / "data" / "real"
    size = (40, 32)

    def animations():
        return [AnimationFrames(str(data / "khronos" / "SimpleSkin.gltf"), ViewOptions(size=size), fps=2.0),
                AnimationFrames(str(data / "khronos" / "AnimatedMorphCube.gltf"), ViewOptions(size=size, shadows=True), fps=2.0)]

    views = [
        lambda: load_view(str(data / "primitives" / "ply_points_ascii.ply"), ViewOptions(size=size, point_size=5)),
        lambda: load_view("builtin:torus", ViewOptions(size=size, edges=True, edge_width=2)),
        lambda: load_view(str(EXAMPLES / "two_lights.toml"), ViewOptions(size=size, shadows=True, shadow_filter="pcf3")),
    ]
    alone = animations()
    tasks = [(kind, index) for kind in range(2) for index in range(len(alone[kind]))] + [(2 + v, 0) for v in range(len(views))]
    expected = [renderer.render(alone[kind][index] if kind < 2 else views[kind - 2]()) for kind, index in tasks]
    assert len({image.tobytes() for image in expected}) > len(tasks) // 2  # they move

    shared_frames, shared = animations(), Renderer(device=renderer.device)
    order = list(reversed(tasks)) * 2

    def draw(task):
        kind, index = task
        return task, shared.render(shared_frames[kind][index] if kind < 2 else views[kind - 2]())

    with ThreadPoolExecutor(max_workers=6) as pool:
        results = list(pool.map(draw, order))
    wrong = [task for task, image in results if not np.array_equal(image, expected[tasks.index(task)])]
    assert not wrong, f"{len(wrong)} of {len(results)} images differ from sequential rendering: {wrong[:8]}"
