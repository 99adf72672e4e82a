"""Where the shadow maps look (render/passes/shadow_views.py, docs/shadows.md#shadow-maps):
each view covers every visible receiver a caster can shadow — casters outside the camera's
view included — and little else; cube faces that cannot reach a visible receiver are
skipped; closed surfaces are told from open ones (scene/geometry/solids.py). CPU only."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.render.passes.shadow_views import (
    MAX_SINGLE_VIEW_TAN,
    cube_guard,
    fit_shadow_views,
    smallest_rectangle_angle,
)
from wgpu_shading.render.passes.visible_regions import camera_frustum, clipped_box, visible_receivers, world_box
from wgpu_shading.scene import (
    Camera,
    DirectionalLight,
    PositionalLight,
    Scene,
    SceneObject,
    SpotLight,
    cube,
    plane,
    torus,
    uv_sphere,
)
from wgpu_shading.scene.geometry.solids import solid_orientation
from wgpu_shading.study.shadows import shadow_case

SIZE, MARGIN = 1024, 2.0


def _project(view, points: np.ndarray) -> np.ndarray:
    """(N, 2) window coordinates of world points in a view."""
    local = points @ view.light_from_world[:3, :3].T + view.light_from_world[:3, 3]
    return local[:, :2] if view.orthographic else local[:, :2] / -local[:, 2:3]


def _inside(view, points: np.ndarray) -> np.ndarray:
    x0, y0, x1, y1 = view.window
    uv = _project(view, points)
    return (uv[:, 0] >= x0) & (uv[:, 0] <= x1) & (uv[:, 1] >= y0) & (uv[:, 1] <= y1)


def _ground(size=20.0):
    return SceneObject(plane(size), rotate=(-90.0, 0.0, 0.0))


def _scene(*objects, light=None, camera=None) -> Scene:
    return Scene(objects=objects, lights=(light or DirectionalLight(direction=(0.3, -1.0, 0.2), shadows=True),),
                 camera=camera or Camera(eye=(0.0, 6.0, 8.0), target=(0.0, 0.0, 0.0)), size=(128, 96))


def test_the_directional_window_holds_the_casters_shadow_on_the_visible_ground_and_little_more():
    ball = SceneObject(uv_sphere(1.0, 24, 12), translate=(0.0, 2.0, 0.0))
    scene = _scene(ball, _ground())
    (shadow,) = fit_shadow_views(scene, SIZE, MARGIN)
    (view,) = shadow.views
    assert view.orthographic and view.near == 0.0 and view.far > 0.0
    assert _inside(view, world_box(ball)).all()  # the caster's silhouette (its box's) is covered
    x0, y0, x1, y1 = view.window
    # the 20-unit ground is not: only where the ball's silhouette lies over it (its box: 2 × 2)
    assert (x1 - x0) * (y1 - y0) < 2.0 * 2.0 * 2.0 * 1.2
    # depth: from the caster's nearest corner to the farthest visible receiver point
    local = world_box(ball) @ view.light_from_world[:3, :3].T + view.light_from_world[:3, 3]
    assert (-local[:, 2] >= view.near - 1e-9).all()


def test_a_caster_outside_the_camera_view_still_gets_into_the_window():
    """The camera sees only the ground; the ball above and behind it still shadows it."""
    ball = SceneObject(uv_sphere(1.0, 24, 12), translate=(0.0, 6.0, -6.0))
    camera = Camera(eye=(0.0, 3.0, 4.0), target=(0.0, 0.0, -2.0), fov_y=30.0)
    light = DirectionalLight(direction=(0.0, -1.0, 1.0), shadows=True)  # travels towards +z: the shadow lands in view
    scene = _scene(ball, _ground(), light=light, camera=camera)
    frustum = camera_frustum(scene)
    assert len(clipped_box(world_box(ball), frustum)) == 0, "the ball must be outside the view for this test"
    (view,) = fit_shadow_views(scene, SIZE, MARGIN)[0].views
    assert view is not None and _inside(view, world_box(ball)).any()


def test_nothing_visible_to_shadow_gives_no_view():
    # the ball lies below the ground plane's visible part in light space: it shadows nothing seen
    ball = SceneObject(uv_sphere(1.0, 24, 12), translate=(40.0, 2.0, 0.0))
    scene = _scene(ball, _ground(10.0))
    assert fit_shadow_views(scene, SIZE, MARGIN)[0].views == (None,)
    flat_alone = _scene(_ground(10.0))  # a plane cannot shadow itself
    assert fit_shadow_views(flat_alone, SIZE, MARGIN)[0].views == (None,)


def test_a_narrow_spot_is_one_perspective_view_inside_its_cone_and_a_wide_one_a_cube():
    ball = SceneObject(uv_sphere(1.0, 24, 12), translate=(0.0, 2.0, 0.0))
    narrow = SpotLight(position=(0.0, 6.0, 0.0), direction=(0.0, -1.0, 0.0), cutoff=30.0, shadows=True)
    (shadow,) = fit_shadow_views(_scene(ball, _ground(), light=narrow), SIZE, MARGIN)
    (view,) = shadow.views
    assert shadow.cube_from_world is None and not view.orthographic
    cone = np.tan(np.radians(30.0)) * SIZE / (SIZE - 2 * MARGIN)
    assert max(abs(v) for v in view.window) <= cone + 1e-9
    wide = replace(narrow, position=(0.0, 2.5, 0.0), cutoff=85.0)  # just above the ball: wider than one view
    (shadow,) = fit_shadow_views(_scene(ball, _ground(), light=wide), SIZE, MARGIN)
    assert shadow.cube_from_world is not None and len(shadow.views) == 6
    # the face looking up (+Y) holds nothing the downward cone lights
    assert shadow.views[2] is None
    assert MAX_SINGLE_VIEW_TAN < np.tan(np.radians(85.0))


def test_cube_faces_that_reach_no_visible_receiver_are_skipped():
    boxes = tuple(SceneObject(cube(0.5), translate=(x, 0.25, z)) for x, z in ((2, 0), (-2, 0), (0, 2), (0, -2)))
    light = PositionalLight(position=(0.0, 0.8, 0.0), shadows=True)
    camera = Camera(eye=(0.0, 9.0, 2.0), target=(0.0, 0.0, 0.0))
    (shadow,) = fit_shadow_views(_scene(*boxes, _ground(), light=light, camera=camera), SIZE, MARGIN)
    faces = [view is not None for view in shadow.views]
    # +Y: the light looks up at nothing; −Y: down at ground no box can shadow in that face
    assert faces == [True, True, False, False, True, True]
    for view in shadow.views:
        if view is not None:  # a face covers 90° and a guard band of MARGIN texels of its own
            assert view.window == pytest.approx((-cube_guard(SIZE, MARGIN),) * 2 + (cube_guard(SIZE, MARGIN),) * 2)


@pytest.mark.parametrize("name", ["far_positional_light", "light_past_a_cube_corner"])
def test_a_far_positional_light_has_one_view_that_holds_the_scene_and_little_more(name):
    """40–54 units away the scene takes a few degrees of what the light sees: one perspective
    view aimed at it (a cube face 90° wide gave the box a handful of texels; near a cube's
    corner three faces would each need a corner), and it still holds the caster."""
    scene = shadow_case(name, (64, 64)).scene
    (shadow,) = fit_shadow_views(scene, SIZE, MARGIN)
    assert shadow.cube_from_world is None and len(shadow.views) == 1
    views = list(shadow.views)
    x0, y0, x1, y1 = views[0].window
    assert max(x1 - x0, y1 - y0) < 0.15 * 2.0 * cube_guard(SIZE, MARGIN)
    box = views[0].light_from_world[:3, :3] @ world_box(scene.objects[0]).T + views[0].light_from_world[:3, 3:]
    tangents = box[:2] / -box[2]
    assert (tangents[0] > x0).all() and (tangents[0] < x1).all() and (tangents[1] > y0).all() and (tangents[1] < y1).all()


def test_a_positional_lights_single_view_has_every_visible_receiver_in_front():
    """A single view aimed at the scene reads V = 1 outside its window: a receiver behind it,
    which the light does reach, needs the cube (random scenes 48, 77 and 95 lost their
    shadows when a receiver wholly behind the view was left out)."""
    from wgpu_shading.study.shadows.random_scenes import random_shadow_scene

    singles = 0
    for seed in (48, 77, 95, *range(20)):
        scene = random_shadow_scene(seed).scene
        receivers = np.concatenate(list(visible_receivers(scene).values()))
        for shadow in fit_shadow_views(scene, SIZE, MARGIN):
            light = scene.lights[shadow.light]
            if isinstance(light, PositionalLight) and shadow.cube_from_world is None and shadow.views[0] is not None:
                singles += 1
                view = shadow.views[0]
                local = receivers @ view.light_from_world[:3, :3].T + view.light_from_world[:3, 3]
                assert (local[:, 2] < 0.0).all(), f"seed {seed}: a receiver behind light {shadow.light}'s view"
    assert singles >= 3


def test_a_cubes_faces_share_the_window_each_needs_and_no_more():
    """A light between two boxes on either side, too wide a spread for one view: the faces
    share one window, the union of what each needs (a face holding no caster's part of a
    shadow is skipped), narrower than a whole face, and it holds the boxes."""
    box = SceneObject(cube(0.5), translate=(1.5, 0.25, 0.5))
    other = SceneObject(cube(0.5), translate=(-1.5, 0.25, 0.5))
    light = PositionalLight(position=(0.0, 0.8, 0.0), shadows=True)
    camera = Camera(eye=(0.0, 6.0, 4.0), target=(0.0, 0.0, 0.0))
    ground = replace(_ground(), cast_shadows=False)  # (a casting ground beside the light reaches every face)
    (shadow,) = fit_shadow_views(_scene(box, other, ground, light=light, camera=camera), SIZE, MARGIN)
    assert shadow.cube_from_world is not None
    views = [view for view in shadow.views if view is not None]
    assert views and all(view.window == views[0].window for view in views)
    x0, y0, x1, y1 = views[0].window
    guard = cube_guard(SIZE, MARGIN)
    assert (x1 - x0) * (y1 - y0) < 0.8 * (2.0 * guard) ** 2
    assert [view is not None for view in shadow.views] == [True, True, False, False, False, False]
    face = shadow.views[0]  # +X looks at the box
    local = world_box(box) @ face.light_from_world[:3, :3].T + face.light_from_world[:3, 3]
    tangents = local[:, :2] / -local[:, 2:]
    assert (tangents >= (x0, y0)).all() and (tangents <= (x1, y1)).all()


def test_the_world_box_of_a_mesh_stored_off_its_origin_is_where_its_points_are():
    """Mesh positions are stored relative to mesh.origin and world_from_model puts it back:
    the box must not add it a second time (the maps were fitted one origin away)."""
    from wgpu_shading.scene import Mesh

    sphere = uv_sphere(1.0, 16, 8)
    moved = Mesh.from_arrays(sphere.positions.astype(np.float64) + (40.0, 10.0, -25.0), sphere.indices, sphere.normals)
    assert np.any(np.asarray(moved.origin) != 0.0)
    obj = SceneObject(moved, translate=(-40.0, -8.0, 25.0), rotate=(10.0, 20.0, 30.0), scale=(2.0, 1.0, 1.5))
    model = obj.world_from_model()
    points = moved.positions.astype(np.float64) @ model[:3, :3].T + model[:3, 3]
    box = world_box(obj)
    # the same centre (a sphere: symmetric about it), and every point inside the box
    assert np.allclose(box.mean(axis=0), (points.min(axis=0) + points.max(axis=0)) / 2.0, atol=1e-3)
    assert (points.min(axis=0) >= box.min(axis=0) - 1e-9).all() and (points.max(axis=0) <= box.max(axis=0) + 1e-9).all()


def test_the_winding_number_tells_a_light_in_a_solid_from_one_beside_it():
    """The closed-surface rule holds for a light outside the solid, even inside its box."""
    from wgpu_shading.scene.geometry.solids import winding_number

    ball, ring = uv_sphere(1.0, 33, 16), torus(1.0, 0.3, 48, 24)
    assert winding_number(ball.positions, ball.indices, (0.0, 0.0, 0.0)) == pytest.approx(1.0)
    assert winding_number(ball.positions, ball.indices, (0.72, 0.75, 0.45)) == pytest.approx(0.0, abs=1e-9)  # in the box, not the ball
    assert winding_number(ring.positions, ring.indices, (0.0, 0.0, 0.0)) == pytest.approx(0.0, abs=1e-9)  # the hole
    assert winding_number(ring.positions, ring.indices, (1.0, 0.0, 0.0)) == pytest.approx(1.0)  # in the tube


def test_the_views_do_not_depend_on_the_scene_scale():
    small, large = (fit_shadow_views(shadow_case("sphere_over_plane_10", (64, 64), scale=s).scene, SIZE, MARGIN) for s in (1e-3, 1e3))
    (a,), (b,) = small[0].views, large[0].views
    assert np.allclose(np.array(a.window) * 1e6, np.array(b.window), rtol=1e-6)
    assert np.isclose(a.far * 1e6, b.far, rtol=1e-6)


def test_the_smallest_rectangle_is_found_for_a_turned_square():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    turn = np.radians(30.0)
    rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    angle = smallest_rectangle_angle(square @ rotation.T)
    c, s = np.cos(angle), np.sin(angle)
    turned = (square @ rotation.T) @ np.array([[c, -s], [s, c]])
    assert np.prod(np.ptp(turned, axis=0)) == pytest.approx(1.0)


def test_receivers_outside_the_view_are_not_fitted():
    inside = SceneObject(cube(1.0), translate=(0.0, 0.5, 0.0))
    outside = SceneObject(cube(1.0), translate=(0.0, 0.5, 60.0))  # behind the camera
    regions = visible_receivers(_scene(inside, outside))
    assert set(regions) == {0}
    no_receiver = replace(inside, receive_shadows=False)
    assert visible_receivers(_scene(no_receiver)) == {}


@pytest.mark.parametrize("mesh, expected", [
    (cube(1.0), 1), (uv_sphere(1.0, 12, 7), 1), (uv_sphere(1.0, 256, 128), 1), (torus(1.0, 0.4, 64, 32), 1), (plane(1.0), 0),
])
def test_closed_surfaces_are_told_from_open_ones(mesh, expected):
    assert solid_orientation(mesh.positions, mesh.indices) == expected
    assert solid_orientation(mesh.positions, mesh.indices[:, ::-1]) == -expected  # wound inside out
    if expected:
        assert solid_orientation(mesh.positions, mesh.indices[:-1]) == 0  # a triangle missing: open
    assert mesh.solid == expected


def test_the_shaders_cube_face_turns_are_the_face_rotations(renderer):
    """wgsl/chunks/shadows/lookup.wgsl turns a cube-frame vector into face f's view by
    swizzles; they must be the rows of shadow_views.face_rotation(f), which the shadow pass
    draws each face with. Run on the GPU over every face and a few vectors."""
    import re

    import wgpu

    from wgpu_shading.render.passes.shadow_views import face_rotation
    from wgpu_shading.render.shaders.preprocess import read_source

    chunk = read_source("chunks/shadows/lookup.wgsl")
    function = re.search(r"fn cube_face_turn\(.*?\n}\n", chunk, re.S).group(0)
    vectors = np.array([[0.3, -0.7, 1.9], [-2.0, 0.5, 0.25], [1.0, 2.0, 3.0]], np.float32)
    source = function + """
@group(0) @binding(0) var<storage, read> vectors: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> turned: array<vec4<f32>>;
@compute @workgroup_size(1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let face = id.x % 6u;  // +X, −X, +Y, −Y, +Z, −Z
    turned[id.x] = vec4<f32>(cube_face_turn(vectors[id.x / 6u].xyz, face < 2u, face == 2u || face == 3u, face % 2u == 0u), 0.0);
}
"""
    device = renderer.device
    inputs = np.zeros((len(vectors), 4), np.float32)
    inputs[:, :3] = vectors
    input_buffer = device.create_buffer_with_data(data=inputs, usage=wgpu.BufferUsage.STORAGE)
    output_buffer = device.create_buffer(size=len(vectors) * 6 * 16, usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC)
    pipeline = device.create_compute_pipeline(layout="auto", compute={"module": device.create_shader_module(code=source), "entry_point": "main"})
    group = device.create_bind_group(layout=pipeline.get_bind_group_layout(0), entries=[
        {"binding": 0, "resource": {"buffer": input_buffer}}, {"binding": 1, "resource": {"buffer": output_buffer}}])
    encoder = device.create_command_encoder()
    compute = encoder.begin_compute_pass()
    compute.set_pipeline(pipeline)
    compute.set_bind_group(0, group)
    compute.dispatch_workgroups(len(vectors) * 6)
    compute.end()
    device.queue.submit([encoder.finish()])
    result = np.frombuffer(device.queue.read_buffer(output_buffer), np.float32).reshape(len(vectors), 6, 4)[..., :3]
    for face in range(6):
        assert np.allclose(result[:, face], vectors @ face_rotation(face).T), face
