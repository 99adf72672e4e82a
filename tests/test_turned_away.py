"""A closed surface seen from outside is drawn with its triangles turned away from the camera
culled by the rasterizer (render/passes/turned_away.py), and shows no face turned away.

The reference is float64 geometry and lighting (wgpu_shading.study.reference): a cube whose
faces each have one colour (a directional light, a viewer at infinity) is rendered from many
random views; every covered pixel must have the colour of a face turned towards the camera,
and every normal of the normals output must be such a face's. Drawing every triangle fails
that on the same views (a face turned away wins the depth test now and then at the
silhouette, by float32 rounding: the speckle this removes), so the views do test it. Frames
where a face turned away could show, and meshes too big to be checked before their first
frame, are not culled.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from pyglm import glm

from wgpu_shading import Camera, Renderer, Scene, SceneObject, load_mesh
from wgpu_shading.render.passes import turned_away
from wgpu_shading.render.passes.color import prepare_draws
from wgpu_shading.scene import DirectionalLight, Material, Mesh, Shading
from wgpu_shading.study import reference as ref

SIZE = (512, 512)  # the speckles are single pixels along silhouettes: more of them at a larger size
MATERIAL = Material(ambient=(0.3, 0.25, 0.2, 1.0), diffuse=(0.8, 0.8, 0.8, 1.0), specular=(0.0, 0.0, 0.0, 1.0))
# A colour for each face of the cube, whatever the view: red, green and blue light the +x,
# +y and +z faces, a grey light the other three, each at its own angle.
LIGHTS = (
    DirectionalLight(direction=(-1.0, -0.3, -0.2), diffuse=(0.8, 0.0, 0.0, 1.0), specular=(0.0, 0.0, 0.0, 1.0)),
    DirectionalLight(direction=(0.3, -1.0, 0.2), diffuse=(0.0, 0.8, 0.0, 1.0), specular=(0.0, 0.0, 0.0, 1.0)),
    DirectionalLight(direction=(0.2, 0.3, -1.0), diffuse=(0.0, 0.0, 0.8, 1.0), specular=(0.0, 0.0, 0.0, 1.0)),
    DirectionalLight(direction=(0.3, 0.6, 0.9), diffuse=(0.5, 0.5, 0.5, 1.0), specular=(0.0, 0.0, 0.0, 1.0)),
)
CUBE = load_mesh("builtin:cube")  # 24 corners, one normal per face: each face one colour
TOLERANCE = 1.5 / 255.0  # float32 lighting and 8-bit rounding


def cube_scene(camera: Camera, mirrored: bool) -> Scene:
    obj = SceneObject(CUBE, material=MATERIAL, scale=(-1.0, 1.0, 1.0) if mirrored else (1.0, 1.0, 1.0))
    return Scene(objects=(obj,), lights=LIGHTS, camera=camera, size=SIZE, background=(0.0, 0.0, 0.0, 1.0),
                 shading=Shading(local_viewer=False))


def random_views(count: int, seed: int) -> list[Camera]:
    rng = np.random.default_rng(seed)
    cameras = []
    for _ in range(count):
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        cameras.append(Camera(eye=tuple(direction * rng.uniform(2.5, 6.0)), target=tuple(rng.uniform(-0.2, 0.2, 3)),
                              up=tuple(rng.normal(size=3)), fov_y=float(rng.uniform(25.0, 60.0)), near=0.1, far=100.0))
    return cameras


def triangle_faces(scene: Scene) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per triangle of the cube, in float64: eye-space unit normal (its winding's), whether it
    is turned towards the camera, and its colour (the lighting equation, viewer at infinity)."""
    obj = scene.objects[0]
    model_view = ref.eye_from_world(scene.camera) @ ref.world_from_model(obj)
    corners = np.asarray(obj.mesh.positions, np.float64)[obj.mesh.indices.astype(np.int64)]  # (F, 3, 3)
    eye = corners @ model_view[:3, :3].T + model_view[:3, 3]
    normals = np.cross(eye[:, 1] - eye[:, 0], eye[:, 2] - eye[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    centres = eye.mean(axis=1)
    towards = np.einsum("ij,ij->i", normals, -centres) > 0.0  # the camera is at the eye-space origin
    ambient_diffuse, specular = ref.shade(centres, normals, np.tile([0.0, 0.0, 1.0], (len(normals), 1)), scene, MATERIAL)
    return normals, towards, np.clip(ambient_diffuse + specular, 0.0, 1.0)


def pixels_of_faces_turned_away(color: np.ndarray, colors: np.ndarray, towards: np.ndarray) -> int:
    """Covered pixels whose colour is no face's turned towards the camera."""
    rgb = color[..., :3].astype(np.int64)
    codes, counts = np.unique((rgb[..., 0] << 16 | rgb[..., 1] << 8 | rgb[..., 2])[(rgb > 0).any(-1)], return_counts=True)
    shown = np.stack([codes >> 16, (codes >> 8) & 255, codes & 255], axis=-1) / 255.0  # a few colours: one a face
    near_front = (np.abs(shown[:, None] - colors[towards][None]) <= TOLERANCE).all(axis=-1).any(axis=-1)
    return int(counts[~near_front].sum())


def every_triangle(renderer: Renderer, scene: Scene, monkeypatch) -> np.ndarray:
    """The colour image with every triangle drawn (no mesh is small enough to be culled)."""
    with monkeypatch.context() as patch:
        patch.setattr(turned_away, "CULLED_MAX_TRIANGLES", -1)
        return renderer.render(replace(scene))  # a new Scene object: not the culled frame's plan


@pytest.mark.parametrize("mirrored", [False, True], ids=["cube", "mirrored cube"])
def test_a_closed_cube_seen_from_outside_shows_only_faces_turned_towards_the_camera(renderer, monkeypatch, mirrored):
    culled, drawing_all = Renderer(renderer.device), Renderer(renderer.device)
    speckled_views = 0
    for number, camera in enumerate(random_views(40, seed=7)):
        scene = cube_scene(camera, mirrored)
        normals, towards, colors = triangle_faces(scene)
        assert 0 < towards.sum() < len(towards)
        # (precondition: the face colours tell the two sides apart)
        distance = np.abs(colors[~towards][:, None] - colors[towards][None]).max(axis=-1).min()
        assert distance > 4 * TOLERANCE, f"view {number}: a face turned away has a front face's colour"

        frame = culled.render_frame(scene, normals="eye")
        everything = every_triangle(drawing_all, scene, monkeypatch)
        # The same coverage: culling opened no hole.
        assert np.array_equal((frame.color[..., :3] > 0).any(-1), (everything[..., :3] > 0).any(-1)), f"view {number}"
        assert pixels_of_faces_turned_away(frame.color, colors, towards) == 0, f"view {number}: a face turned away shows"
        # The normals output shows the same faces: each covered pixel's normal is a front face's.
        shown = frame.normals[frame.ids > 0]
        closest = np.min([np.abs(shown - normal).max(axis=-1) for normal in normals[towards]], axis=0)
        assert closest.max() < 1e-4, f"view {number}: the normals output shows a face turned away"
        speckled_views += pixels_of_faces_turned_away(everything, colors, towards) > 0
    # Drawing every triangle shows faces turned away in some of these views: they test the culling.
    assert speckled_views >= 2, f"only {speckled_views} of the views let a face turned away win a pixel"


def draws_cull(renderer: Renderer, scene: Scene) -> list[bool]:
    draws = prepare_draws(renderer.device_cache, scene, "rgba8", glm.dmat4(scene.camera.eye_from_world()))
    return [draw.entry.key.cull_back for draw in draws if not draw.entry.descriptor.quads]


OUTSIDE = Camera(eye=(0.4, 1.2, 3.5), target=(0.0, 0.0, 0.0), near=0.1, far=50.0)
OPEN_BOX = Mesh(positions=CUBE.positions, normals=CUBE.normals, indices=CUBE.indices[:-2], name="box without a face")


@pytest.mark.parametrize(
    "case, scene",
    [
        ("open mesh", replace(cube_scene(OUTSIDE, False), objects=(SceneObject(OPEN_BOX, material=MATERIAL),))),
        ("camera inside", cube_scene(replace(OUTSIDE, eye=(0.1, 0.2, 0.3)), False)),
        ("near plane cuts the mesh", cube_scene(replace(OUTSIDE, eye=(0.0, 0.0, 1.5), near=1.2), False)),
        ("two-sided lighting", replace(cube_scene(OUTSIDE, False), shading=Shading(two_sided=True))),
        ("blended material", replace(cube_scene(OUTSIDE, False), objects=(
            SceneObject(CUBE, material=replace(MATERIAL, diffuse=(0.7, 0.55, 0.3, 0.5), alpha_mode="blend")),))),
        ("--edges", replace(cube_scene(OUTSIDE, False), shading=Shading(edges=True))),
    ],
    ids=lambda value: value if isinstance(value, str) else "",
)
def test_frames_where_a_face_turned_away_could_show_cull_nothing(renderer, case, scene):
    assert draws_cull(renderer, cube_scene(OUTSIDE, False)) == [True]
    assert draws_cull(renderer, scene) == [False]


def test_a_mesh_above_the_checked_size_is_never_culled_even_once_its_check_has_run(renderer, monkeypatch):
    """Its frames must not change when the check (run for its clusters) finishes."""
    scene = cube_scene(OUTSIDE, False)
    monkeypatch.setattr(turned_away, "CULLED_MAX_TRIANGLES", CUBE.triangle_count - 1)
    assert CUBE.exact_solid == 1  # checked, and closed
    assert draws_cull(renderer, scene) == [False]
