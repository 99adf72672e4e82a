"""The exact shadows of the float64 reference against closed forms (docs/shadows.md#the-exact-answer):
the sphere's elliptic shadow on a plane (semi-axes r and r/sin(elevation)), the contact
point of a resting sphere, the two-light region worked out by hand, and the rules of
docs/shadows.md (what casts, what receives, what a shadow leaves alone). These prove the
reference that the GPU's shadows are then held to (test_shadows_gpu.py)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.scene import Camera, DirectionalLight, Material, Scene, SceneObject, plane, uv_sphere
from wgpu_shading.study import reference as ref
from wgpu_shading.study.shadows import ELEVATIONS, SHADOW_CASE_NAMES, ground_view, plane_points, shadow_case
from wgpu_shading.study.reference.analytic_scene import ray_sphere
from wgpu_shading.study.shadows.check import boundary_midpoints, pixels_near

pytest.importorskip("embreex")


@pytest.mark.parametrize("elevation", ELEVATIONS)
def test_the_ray_cast_shadow_of_a_sphere_is_the_closed_form_ellipse(elevation):
    """Seen by the case's own camera: every plane pixel's ray-cast state is the ellipse's,
    except within a pixel of the ellipse's boundary (and the 256×128 sphere's facets,
    3e-4·r inside the exact sphere, are far below that)."""
    case = shadow_case(f"sphere_over_plane_{elevation:g}", (160, 160))
    image = ref.render_reference(case.scene)
    on_plane = image.object == 1
    exact = np.zeros(on_plane.shape, dtype=bool)
    exact[on_plane] = case.ellipse.contains(plane_points(case.scene)[on_plane])
    band = pixels_near(exact.shape, boundary_midpoints(exact, on_plane), 1.0)
    ray_cast = image.shadow_mask(0)
    assert exact.sum() > 20, "the shadow must be in view"
    wrong = on_plane & (ray_cast != exact) & ~band
    assert not wrong.any(), f"{wrong.sum()} plane pixels disagree with the ellipse, first {np.argwhere(wrong)[:3].tolist()}"
    # The closed-form spheres agree with the closed-form ellipse to float64 rounding.
    analytic = ref.render_analytic_scene(case.scene, case.shapes)
    both = on_plane & (analytic.object == 1)
    assert (analytic.visibility[0][both] < 0.5).tolist() == exact[both].tolist()


@pytest.mark.parametrize("elevation", ELEVATIONS)
def test_the_shadow_ellipse_has_the_closed_form_axes_and_area(elevation):
    """From straight below (the sphere hidden behind the plane): the shadow spans 2r/sin(e)
    along the light and 2r across, within a pixel, and its area is π·r²/sin(e) within
    one pixel along the perimeter."""
    case = shadow_case(f"sphere_over_plane_{elevation:g}")
    scene, pixel = ground_view(case)
    mask = ref.render_reference(scene).shadow_mask(0)
    rows = np.flatnonzero(mask.any(axis=1))
    columns = np.flatnonzero(mask.any(axis=0))
    assert abs((rows[-1] - rows[0] + 1) * pixel - 2 * case.ellipse.semi_major) <= pixel
    assert abs((columns[-1] - columns[0] + 1) * pixel - 2 * case.ellipse.semi_minor) <= pixel
    a, b = case.ellipse.semi_major, case.ellipse.semi_minor
    perimeter = math.pi * (3 * (a + b) - math.sqrt((3 * a + b) * (a + 3 * b)))  # Ramanujan
    assert abs(mask.sum() * pixel**2 - case.ellipse.area) <= perimeter * pixel


def test_a_resting_sphere_shadows_its_contact_point_without_a_gap():
    """The sphere touches the plane at its foot; the exact ellipse contains the foot with a
    margin of r·(1 − cos e)/sin e, so every plane pixel near the foot is shadowed: no
    light leaks under the sphere."""
    case = shadow_case("sphere_on_plane")
    scene, pixel = ground_view(case)
    image = ref.render_reference(scene)
    points = plane_points(scene)
    near_foot = (np.linalg.norm(points - np.array([0.0, 0.0, 0.0]), axis=-1) < 0.25) & image.covered
    assert near_foot.sum() > 30
    assert image.shadow_mask(0)[near_foot].all()
    assert case.ellipse.contains(np.zeros((1, 3)))[0]


def test_a_region_hidden_from_one_light_is_ambient_emission_and_the_other_light():
    """Worked out by hand for the ground (N = +Y, no specular): where light 0 is hidden and
    light 1 is not, the colour is emission + global ambient + both lights' ambient + light
    1's attenuated diffuse, to float64 precision."""
    case = shadow_case("two_lights", (96, 96))
    scene = case.scene
    image = ref.render_reference(scene)
    only_first_hidden = (image.object == 1) & (image.visibility[0] < 0.5) & (image.visibility[1] > 0.5)
    assert only_first_hidden.sum() > 50
    points = plane_points(scene)[only_first_hidden]
    ground = scene.objects[1].material
    _, second = scene.lights
    m_ambient, m_diffuse = np.array(ground.ambient[:3]), np.array(ground.diffuse[:3])
    offset = np.asarray(second.position) - points
    distance = np.linalg.norm(offset, axis=1)
    kc, kl, kq = second.attenuation
    attenuation = 1.0 / (kc + kl * distance + kq * distance**2)
    n_dot_l = offset[:, 1] / distance
    expected = (np.array(ground.emission[:3]) + np.array(scene.ambient[:3]) * m_ambient
                + np.array(scene.lights[0].ambient[:3]) * m_ambient
                + attenuation[:, None] * (np.array(second.ambient[:3]) * m_ambient + n_dot_l[:, None] * np.array(second.diffuse[:3]) * m_diffuse))
    assert np.abs(image.color[only_first_hidden][:, :3] - np.clip(expected, 0, 1)).max() < 1e-12


def _sphere_and_plane(**sphere_options):
    light = DirectionalLight(direction=(-0.5, -1.0, -0.2), shadows=True)
    sphere = SceneObject(uv_sphere(1.0, 48, 24), Material(specular=(0.5, 0.5, 0.5, 1.0), shininess=20.0, emission=(0.1, 0, 0, 1)),
                         translate=(0.0, 2.0, 0.0), **sphere_options)
    ground = SceneObject(plane(10.0), Material(emission=(0.0, 0.05, 0.0, 1.0)), rotate=(-90.0, 0.0, 0.0))
    return Scene(objects=(sphere, ground), lights=(light,), camera=Camera(eye=(2.0, 7.0, 6.0), target=(-0.5, 0.5, 0.0)), size=(64, 64))


def test_what_a_shadow_changes_and_what_it_leaves_alone():
    scene = _sphere_and_plane()
    shadowed = ref.render_reference(scene)
    plain = ref.render_reference(replace(scene, lights=(replace(scene.lights[0], shadows=False),)))
    mask = shadowed.shadow_mask(0)
    assert mask.sum() > 30 and plain.visibility is not None and (plain.visibility == 1).all()
    # Outside the shadow nothing changes; inside it, only the light's diffuse and specular go:
    # what is left is exactly emission + global ambient (the light has no ambient).
    assert np.array_equal(shadowed.color[~mask], plain.color[~mask])
    on_ground = mask & (shadowed.object == 1)
    assert np.allclose(shadowed.color[on_ground][:, :3], [0.2 * 0.2, 0.2 * 0.2 + 0.05, 0.2 * 0.2], atol=1e-12)
    # The sphere's side turned away from the light (N·L < 0 by a margin: the facets' normals
    # are within a few degrees of the exact ones used here) looks the same either way.
    points = sphere_points(scene)
    to_light = -np.asarray(scene.lights[0].direction) / np.linalg.norm(scene.lights[0].direction)
    unlit = (shadowed.object == 0) & (((points - np.array([0.0, 2.0, 0.0])) @ to_light) < -0.1)
    assert (mask & unlit).sum() >= 5
    assert np.array_equal(shadowed.color[unlit], plain.color[unlit])


def sphere_points(scene: Scene) -> np.ndarray:
    """(H, W, 3) world points where each pixel's ray first meets the exact unit sphere at (0, 2, 0)."""
    width, height = scene.size
    columns, rows = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    origins, directions = ref.window_rays(scene.camera, scene.size, columns, rows)
    to_world = np.linalg.inv(ref.eye_from_world(scene.camera))
    origins = (origins @ to_world[:3, :3].T + to_world[:3, 3]).reshape(-1, 3)
    directions = directions @ to_world[:3, :3].T
    directions = (directions / np.linalg.norm(directions, axis=-1, keepdims=True)).reshape(-1, 3)
    near, _ = ray_sphere(origins, directions, (0.0, 2.0, 0.0), 1.0)
    return (origins + np.nan_to_num(near)[:, None] * directions).reshape(height, width, 3)


def test_cast_and_receive_switches():
    scene = _sphere_and_plane()
    no_cast = ref.render_reference(_sphere_and_plane(cast_shadows=False))
    assert not no_cast.shadow_mask(0).any()
    ground = replace(scene.objects[1], receive_shadows=False)
    no_receive = ref.render_reference(replace(scene, objects=(scene.objects[0], ground)))
    assert not (no_receive.shadow_mask(0) & (no_receive.object == 1)).any()


def test_casters_outside_the_view_cast():
    scene = _sphere_and_plane()
    looking_at_the_shadow = replace(scene, camera=Camera(eye=(-1.0, 1.2, -0.4), target=(-1.0, 0.0, -0.4), up=(0.0, 0.0, 1.0)))
    image = ref.render_reference(looking_at_the_shadow)
    assert not (image.object == 0).any(), "the sphere must be out of view"
    assert image.shadow_mask(0).sum() > 100


@pytest.mark.parametrize("flip", [False, True])
def test_a_zero_thickness_quad_casts_from_both_sides(flip):
    """The same quad facing up or down (mirrored winding) casts the same shadow."""
    case = shadow_case("quad_occluder", (64, 64))
    quad = case.scene.objects[0]
    if flip:
        quad = replace(quad, scale=(1.0, -1.0, 1.0))  # mirrored: its triangles face the other way
    image = ref.render_reference(replace(case.scene, objects=(quad,) + case.scene.objects[1:]))
    reference = ref.render_reference(case.scene)
    on_ground = (image.object == 1) & (reference.object == 1)
    assert image.shadow_mask(0)[on_ground].sum() > 100
    assert np.array_equal(image.shadow_mask(0)[on_ground], reference.shadow_mask(0)[on_ground])


@pytest.mark.parametrize("scale", [1e-3, 1e3])
@pytest.mark.parametrize("name", ["sphere_over_plane_10", "torus_self_shadow", "ring_of_boxes"])
def test_the_exact_shadows_do_not_depend_on_the_scene_scale(name, scale):
    """Every length × 1e-3 or 1e3 (lights, objects, camera): the same visibility, pixel for
    pixel, but for a rare pixel whose ray grazes an edge (float64 rounding differs)."""
    unit = ref.render_reference(shadow_case(name, (64, 64)).scene)
    scaled = ref.render_reference(shadow_case(name, (64, 64), scale=scale).scene)
    assert np.array_equal(unit.covered, scaled.covered)
    differ = unit.visibility != scaled.visibility
    assert differ.sum() <= 2, f"{differ.sum()} pixels change state at scale {scale:g}"


def test_the_catalogue_builds_every_case_with_shadows_in_view():
    for name in SHADOW_CASE_NAMES:
        for projection in ("perspective", "orthographic"):
            # sliver_shadow's shadow is a line under a pixel wide at 128 pixels: most pixel centres miss it.
            case = shadow_case(name, (256, 256) if name == "sliver_shadow" else (48, 48), projection=projection)
            image = ref.render_reference(case.scene)
            shadowed = sum(image.shadow_mask(i).sum() for i in range(len(case.scene.lights)))
            assert shadowed > 10 and (~image.shadow_mask(0) & image.covered).sum() > 10, case.name


def test_a_pixel_point_a_hair_off_its_triangle_is_moved_onto_it():
    """The exact answer's point lies on its visible triangle (docs/shadows.md#the-exact-answer).
    A pixel centre the fixed-point rasterizer gives to a triangle can meet its plane a hair
    beyond an edge (random scene 236: weights −0.002); in a valley that point lies under the
    other slope, whose facet then hid every light from it. Closed form: a floor y = 0 for
    x ≤ 0 and a wall rising at 45° from its edge x = 0, a light straight above: the floor's
    points, its edge included, are lit; a point 0.002 beyond the edge is under the wall."""
    from wgpu_shading.scene import Mesh
    from wgpu_shading.study.reference.shading import on_triangle
    from wgpu_shading.study.reference.visibility import ShadowRays

    corners = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    valley = Mesh.from_arrays(corners, np.array([[0, 1, 2], [0, 3, 1]]), name="valley")
    scene = Scene(objects=(SceneObject(valley),), lights=(DirectionalLight(direction=(0.0, -1.0, 0.0), shadows=True),))
    weights = np.array([[0.501, 0.501, -0.002], [0.25, 0.25, 0.5]])
    moved = on_triangle(weights)
    assert (moved >= 0.0).all() and np.allclose(moved.sum(axis=1), 1.0) and np.allclose(moved[1], weights[1])
    floor = corners[[0, 1, 2]]
    rays = ShadowRays(scene)
    beyond = weights @ floor
    assert beyond[0, 0] == pytest.approx(0.002)
    assert rays.visibility(beyond, np.zeros(2, int), np.zeros(2, int)).tolist() == [[0.0, 1.0]]  # under the wall
    assert rays.visibility(moved @ floor, np.zeros(2, int), np.zeros(2, int)).tolist() == [[1.0, 1.0]]


def test_a_face_of_a_closed_solid_turned_from_the_light_is_in_its_shadow_up_to_its_edges():
    """Closed form: a unit cube lit by a directional light 0.57° below the horizon, from −X.
    Its top face is turned from the light, so every point of it is in the cube's own shadow:
    the segment towards the light enters the cube at once and leaves it through the −X face.
    Next to the −X edge that exit lies nearer than the ray cast's float32 guard, and on the
    edge itself the segment only touches the cube (random scenes 190, 258): the pixel's point
    belongs to the top face, shadowed up to its edge. The −X face, facing the light, is lit;
    a positional light inside the cube shadows none of its faces."""
    from wgpu_shading.scene import PositionalLight, cube
    from wgpu_shading.study.reference.visibility import ShadowRays

    box = SceneObject(cube(1.0))
    travel = (1.0, 0.01, 0.0)
    scene = Scene(objects=(box,), lights=(DirectionalLight(direction=travel, shadows=True),))
    mesh = box.mesh
    corners = mesh.positions[mesh.indices].astype(np.float64)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    up = normals[:, 1] > 0.5 * np.linalg.norm(normals, axis=1)
    top = int(np.flatnonzero(up & ((corners[:, :, 0] == corners[:, :, 0].min()).sum(axis=1) == 2))[0])  # a −X edge
    side = int(np.flatnonzero(normals[:, 0] < -0.5 * np.linalg.norm(normals, axis=1))[0])
    near_edge = corners[top][np.argsort(corners[top][:, 0])[:2]].mean(axis=0)  # the middle of that edge
    points = np.array([near_edge, near_edge + (1e-9, 0.0, 0.0), corners[top].mean(axis=0), corners[side].mean(axis=0)])
    triangles = np.array([top, top, top, side])
    assert near_edge[0] == pytest.approx(-0.5) and near_edge[1] == pytest.approx(0.5)
    visibility = ShadowRays(scene).visibility(points, np.zeros(4, int), triangles)
    assert visibility.tolist() == [[0.0, 0.0, 0.0, 1.0]]
    inside = replace(scene, lights=(PositionalLight(position=(0.0, 0.0, 0.0), shadows=True),))
    assert ShadowRays(inside).visibility(points, np.zeros(4, int), triangles).tolist() == [[1.0, 1.0, 1.0, 1.0]]
