"""The float64 reference renderer alone, against values worked out by hand.

Each expected value below is computed in the test from the formulas of
docs/conventions.md for a geometry chosen so that the answer is known in closed form;
the reference must reproduce it to float64 precision.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgpu_shading.study import reference as ref
from wgpu_shading.scene import Mesh, plane, sphere_for_triangles, uv_sphere
from wgpu_shading.scene import (
    Camera,
    DirectionalLight,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    SpotLight,
    Texture,
)

BLACK = (0.0, 0.0, 0.0, 1.0)
TIGHT = 1e-12


def unlit_scene(**overrides) -> Scene:
    """A scene with no global ambient, so only what a test adds contributes."""
    settings = dict(lights=(), ambient=BLACK, size=(16, 16))
    settings.update(overrides)
    return Scene(**settings)


def one_point(vector) -> np.ndarray:
    return np.asarray(vector, dtype=np.float64)[None, :]


def shade_one(scene, material, point, normal, to_viewer):
    ambient_diffuse, specular = ref.shade(one_point(point), one_point(normal), one_point(to_viewer), scene, material)
    return ambient_diffuse[0], specular[0]


# --------------------------------------------------------------------------- guarded operations


def test_guarded_power_limits():
    bases = np.array([0.0, -0.5, 0.5, 0.5, 2.0, 0.0, -1.0])
    exponents = np.array([0.0, 0.0, 0.0, 3.0, 3.0, 2.0, 2.0])
    # base <= 0 gives 0 for every exponent (0^0 too); x^0 = 1 for x > 0; the base is clamped to 1.
    expected = np.array([0.0, 0.0, 1.0, 0.125, 1.0, 0.0, 0.0])
    np.testing.assert_array_equal(ref.guarded_power(bases, exponents), expected)


def test_safe_normalize_falls_back_below_the_threshold():
    vectors = np.array([[3.0, 4.0, 0.0], [0.0, 0.0, 0.0], [1e-16, 0.0, 0.0], [1e-14, 0.0, 0.0]])
    result = ref.safe_normalize(vectors, np.array([0.0, 0.0, 1.0]))
    # |v|² = 1e-32 <= 1e-30 falls back; |v|² = 1e-28 is still a direction.
    np.testing.assert_allclose(result, [[0.6, 0.8, 0.0], [0, 0, 1], [0, 0, 1], [1, 0, 0]], atol=TIGHT)


def test_attenuation_at_a_known_distance():
    # Light 2 units in front of a point, N = L: diffuse = kd·Ld / (kc + kl·d + kq·d²).
    kc, kl, kq = 0.5, 0.25, 0.125
    light = PositionalLight(position=(0.0, 0.0, -3.0), ambient=(0.1, 0.2, 0.3, 1), diffuse=(1, 1, 1, 1), attenuation=(kc, kl, kq))
    scene = unlit_scene(lights=(light,), camera=Camera(eye=(0, 0, 0), target=(0, 0, -1)))
    material = Material(ambient=(1, 1, 1, 1), diffuse=(0.4, 0.5, 0.6, 1))
    ambient_diffuse, specular = shade_one(scene, material, (0, 0, -5), (0, 0, 1), (0, 0, 1))
    factor = 1.0 / (kc + kl * 2.0 + kq * 4.0)
    # The attenuation scales the light's ambient term as well.
    np.testing.assert_allclose(ambient_diffuse, factor * (np.array([0.1, 0.2, 0.3]) + np.array([0.4, 0.5, 0.6])), atol=TIGHT)
    np.testing.assert_array_equal(specular, 0.0)


def test_attenuation_floor_keeps_a_light_at_the_point_finite():
    # kc = 0 and d = 0: the denominator is floored at 1e-20, the light at the point gives L = N.
    light = PositionalLight(position=(0, 0, 0), attenuation=(0.0, 1.0, 0.0), diffuse=(0.5, 0.5, 0.5, 1))
    scene = unlit_scene(lights=(light,))
    material = Material(ambient=BLACK, diffuse=(1, 1, 1, 1))
    point = ref.eye_from_world(scene.camera)[:3, 3]  # the world origin in eye space
    ambient_diffuse, _ = shade_one(scene, material, point, (0, 1, 0), (0, 0, 1))
    np.testing.assert_allclose(ambient_diffuse, 0.5e20, rtol=1e-12)
    rgba = ref.combine(ambient_diffuse[None], np.zeros((1, 3)), material)
    np.testing.assert_array_equal(rgba, [[1.0, 1.0, 1.0, 1.0]])


# --------------------------------------------------------------------------- the lighting equation


def test_head_on_directional_light_on_a_facing_plane():
    """N = L = V = R = (0, 0, 1): color = e + g·ka + La·ka + Ld·kd + Ls·ks, in every pixel."""
    material = Material(
        ambient=(0.2, 0.3, 0.1, 1), diffuse=(0.4, 0.2, 0.3, 0.7), specular=(0.3, 0.1, 0.2, 1),
        emission=(0.05, 0.0, 0.1, 1), shininess=25.0,
    )
    light = DirectionalLight(direction=(0, 0, -1), ambient=(0.1, 0.1, 0.2, 1), diffuse=(0.9, 0.8, 0.7, 1), specular=(0.5, 0.6, 0.7, 1))
    scene = Scene(
        objects=(SceneObject(plane(2.0), material),),
        lights=(light,),
        ambient=(0.3, 0.2, 0.1, 1),
        camera=Camera(eye=(0, 0, 1), fov_y=60.0),  # the plane fills the image
        shading=Shading(frequency="phong", local_viewer=False),
        size=(12, 10),
        background=(0.1, 0.2, 0.3, 0.4),
    )
    ka, kd, ks, ke = (np.array(c[:3]) for c in (material.ambient, material.diffuse, material.specular, material.emission))
    expected_rgb = ke + np.array([0.3, 0.2, 0.1]) * ka + np.array([0.1, 0.1, 0.2]) * ka + np.array([0.9, 0.8, 0.7]) * kd + np.array([0.5, 0.6, 0.7]) * ks
    image = ref.render_reference(scene)
    assert image.covered.all()
    np.testing.assert_allclose(image.color[..., :3], np.broadcast_to(expected_rgb, (10, 12, 3)), atol=TIGHT)
    np.testing.assert_allclose(image.color[..., 3], 1.0, atol=TIGHT)  # opaque (docs/conventions.md#the-lighting-equation), whatever the diffuse alpha
    np.testing.assert_allclose(image.depth, 1.0, atol=TIGHT)
    assert (image.object == 0).all() and set(np.unique(image.triangle)) == {0, 1}


def test_background_where_nothing_is_drawn():
    scene = unlit_scene(objects=(SceneObject(plane(1.0)),), camera=Camera(eye=(0, 0, 5)), background=(0.25, 0.5, 0.75, 0.5))
    image = ref.render_reference(scene)
    assert 0 < image.covered.sum() < image.covered.size
    np.testing.assert_array_equal(image.color[~image.covered], np.tile([0.25, 0.5, 0.75, 0.5], ((~image.covered).sum(), 1)))
    assert np.isinf(image.depth[~image.covered]).all() and (image.triangle[~image.covered] == -1).all()


@pytest.mark.parametrize("angle", [0.0, 30.0, 60.0, 89.0, 120.0])
def test_sphere_centre_pixel_at_a_known_light_angle(angle):
    """The analytic sphere's centre pixel has N = V = (0, 0, 1); a directional light at `angle`
    from the view axis gives diffuse cos(angle) and, R being L mirrored about N = V, Phong
    specular cos(angle)^s."""
    theta = math.radians(angle)
    light = DirectionalLight(direction=(-math.sin(theta), 0.0, -math.cos(theta)), diffuse=(0.6, 0.6, 0.6, 1), specular=(0.3, 0.3, 0.3, 1))
    material = Material(ambient=BLACK, diffuse=(1, 1, 1, 1), specular=(1, 1, 1, 1), shininess=7.0)
    scene = unlit_scene(lights=(light,), size=(33, 33), camera=Camera(eye=(0, 0, 4)))
    image = ref.render_analytic_sphere(scene, (0, 0, 0), 1.0, material)
    n_dot_l = math.cos(theta)
    r_dot_v = math.cos(theta)
    specular = 0.3 * max(r_dot_v, 0.0) ** 7 if n_dot_l > 0 else 0.0
    expected = 0.6 * max(n_dot_l, 0.0) + specular
    np.testing.assert_allclose(image.color[16, 16, :3], expected, atol=1e-12)
    np.testing.assert_allclose(image.depth[16, 16], 3.0, atol=1e-12)


def test_phong_and_blinn_phong_at_a_known_geometry():
    """N = V = (0, 0, 1), L at 60°: R = (−sin 60°, 0, cos 60°), so R·V = 0.5;
    H bisects L and V, at 30° from N: N·H = cos 30°."""
    theta = math.radians(60.0)
    to_light = (math.sin(theta), 0.0, math.cos(theta))
    material = Material(ambient=BLACK, diffuse=BLACK, specular=(1, 1, 1, 1), shininess=10.0)
    light = DirectionalLight(direction=tuple(-c for c in to_light), diffuse=BLACK, specular=(1, 1, 1, 1))
    camera = Camera(eye=(0, 0, 0), target=(0, 0, -1))  # eye space = world space
    for reflection, k_blinn, expected in [
        ("phong", 1.0, 0.5**10),
        ("blinn-phong", 1.0, math.cos(math.radians(30)) ** 10),
        ("blinn-phong", 3.0, math.cos(math.radians(30)) ** 30),
    ]:
        scene = unlit_scene(lights=(light,), camera=camera, shading=Shading(reflection=reflection, blinn_exponent_scale=k_blinn))
        _, specular = shade_one(scene, material, (0, 0, -2), (0, 0, 1), (0, 0, 1))
        np.testing.assert_allclose(specular, expected, rtol=1e-12, err_msg=f"{reflection} k={k_blinn}")


def test_shininess_zero_gives_full_specular_on_the_lit_side_only():
    camera = Camera(eye=(0, 0, 0), target=(0, 0, -1))
    material = Material(ambient=BLACK, diffuse=BLACK, specular=(0.5, 0.5, 0.5, 1), shininess=0.0)
    for reflection in ("phong", "blinn-phong"):
        # Light grazing from the side: R·V and N·H small but positive, and x^0 = 1.
        light = DirectionalLight(direction=(-1.0, 0.0, -0.05), specular=(1, 1, 1, 1))
        scene = unlit_scene(lights=(light,), camera=camera, shading=Shading(reflection=reflection))
        _, lit = shade_one(scene, material, (0, 0, -1), (0, 0, 1), (0, 0, 1))
        np.testing.assert_allclose(lit, 0.5, rtol=1e-12)
        # From behind the surface (N·L < 0): f_i = 0, no highlight at all.
        behind = DirectionalLight(direction=(0.0, 0.0, 1.0), specular=(1, 1, 1, 1))
        scene = unlit_scene(lights=(behind,), camera=camera, shading=Shading(reflection=reflection))
        _, unlit = shade_one(scene, material, (0, 0, -1), (0, 0, 1), (0, 0, 1))
        np.testing.assert_array_equal(unlit, 0.0)


def test_light_at_the_point_uses_the_normal():
    light = PositionalLight(position=(0, 0, -2), diffuse=(0.8, 0.8, 0.8, 1), specular=(1, 1, 1, 1))
    camera = Camera(eye=(0, 0, 0), target=(0, 0, -1))
    material = Material(ambient=BLACK, diffuse=(1, 1, 1, 1), specular=(0.5, 0.5, 0.5, 1), shininess=4.0)
    scene = unlit_scene(lights=(light,), camera=camera)
    normal = np.array([0.0, 0.6, 0.8])
    ambient_diffuse, specular = shade_one(scene, material, (0, 0, -2), normal, (0, 0, 1))
    # L = N: N·L = 1; R = N, R·V = 0.8.
    np.testing.assert_allclose(ambient_diffuse, 0.8, rtol=1e-12)
    np.testing.assert_allclose(specular, 0.5 * 0.8**4, rtol=1e-12)


def test_opposite_light_and_view_give_no_blinn_half_vector():
    """L = −V: H = 0, so N·H = 0 and there is no highlight (Phong still has one)."""
    camera = Camera(eye=(0, 0, 0), target=(0, 0, -1))
    to_light = np.array([0.0, 0.6, -0.8])  # = −V for V below
    to_viewer = -to_light
    normal = np.array([0.0, 1.0, 0.0])  # N·L = 0.6 > 0: the lit side
    light = DirectionalLight(direction=tuple(-to_light), diffuse=BLACK, specular=(1, 1, 1, 1))
    material = Material(ambient=BLACK, diffuse=BLACK, specular=(1, 1, 1, 1), shininess=3.0)
    blinn = unlit_scene(lights=(light,), camera=camera, shading=Shading(reflection="blinn-phong"))
    _, specular = shade_one(blinn, material, (0, 0, -1), normal, to_viewer)
    np.testing.assert_array_equal(specular, 0.0)
    phong = unlit_scene(lights=(light,), camera=camera, shading=Shading(reflection="phong"))
    _, specular = shade_one(phong, material, (0, 0, -1), normal, to_viewer)
    # R = 2(N·L)N − L = (0, 0.6, 0.8); R·V = (0, 0.6, 0.8)·(0, −0.6, 0.8) = 0.28
    np.testing.assert_allclose(specular, 0.28**3, rtol=1e-12)


def test_view_vector_local_and_infinite_and_eye_at_the_point():
    points = np.array([[0.0, 3.0, -4.0], [0.0, 0.0, 0.0]])
    normals = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    np.testing.assert_allclose(ref.view_vectors(points, normals, True), [[0, -0.6, 0.8], [0, 1, 0]], atol=TIGHT)
    np.testing.assert_array_equal(ref.view_vectors(points, normals, False), [[0, 0, 1], [0, 0, 1]])


def test_lights_are_transformed_into_eye_space():
    """A camera looking down −X from +X: world +Z is eye +X... checked on each light kind."""
    camera = Camera(eye=(5, 0, 0), target=(0, 0, 0), up=(0, 1, 0))
    lights = (
        DirectionalLight(direction=(0, 0, -1)),  # travels along world −Z: towards the light is +Z
        PositionalLight(position=(5, 1, 2)),
        SpotLight(position=(0, 0, 0), direction=(-1, 0, 0), cutoff=30.0, exponent=2.0),
    )
    directional, positional, spot = ref.lights_in_eye_space(unlit_scene(lights=lights, camera=camera))
    # Eye axes in world space: x = up × backward = (0,1,0)×(1,0,0) = (0,0,−1), y = (0,1,0), z = (1,0,0).
    np.testing.assert_allclose(directional.to_light, [-1, 0, 0], atol=TIGHT)
    np.testing.assert_allclose(positional.position, [-2, 1, 0], atol=TIGHT)
    np.testing.assert_allclose(spot.position, [0, 0, -5], atol=TIGHT)
    np.testing.assert_allclose(spot.axis, [0, 0, -1], atol=TIGHT)
    assert spot.cutoff_chord_squared == pytest.approx(4 * math.sin(math.radians(15)) ** 2, rel=1e-15)


@pytest.mark.parametrize(
    "angle, cutoff, exponent, expected",
    [
        (0.0, 30.0, 10.0, 1.0),  # on the axis
        (20.0, 30.0, 10.0, math.cos(math.radians(20)) ** 10),  # inside: cos^exponent
        (20.0, 30.0, 0.0, 1.0),  # exponent 0: x^0 = 1 inside
        (29.9, 30.0, 3.0, math.cos(math.radians(29.9)) ** 3),  # just inside the edge
        (30.1, 30.0, 3.0, 0.0),  # just outside
        (45.0, 30.0, 0.0, 0.0),  # outside, exponent 0 does not leak
        (0.0, 0.0, 1.0, 0.0),  # cutoff 0: the open cone lights nothing
        (0.0005, 0.001, 1.0, math.cos(math.radians(0.0005))),  # a tiny cone stays exact (squared chords)
        (0.0015, 0.001, 0.0, 0.0),  # ... and its edge too
        (89.0, 90.0, 1e6, 0.0),  # huge exponent: cos 89°^1e6 underflows to 0, no NaN
    ],
)
def test_spot_cone_and_exponent(angle, cutoff, exponent, expected):
    """A spot at the eye-space origin along −Z; the point at `angle` off the axis, distance 2,
    N = L. Inside the cone everything, ambient included, is scaled by the spot factor."""
    phi = math.radians(angle)
    direction_to_point = np.array([math.sin(phi), 0.0, -math.cos(phi)])
    point = 2.0 * direction_to_point
    light = SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=cutoff, exponent=exponent, ambient=(0.25, 0.25, 0.25, 1), diffuse=(0.5, 0.5, 0.5, 1))
    scene = unlit_scene(lights=(light,), camera=Camera(eye=(0, 0, 0), target=(0, 0, -1)))
    material = Material(ambient=(1, 1, 1, 1), diffuse=(1, 1, 1, 1))
    ambient_diffuse, _ = shade_one(scene, material, point, -direction_to_point, (0, 0, 1))
    np.testing.assert_allclose(ambient_diffuse, 0.75 * expected, rtol=1e-12, atol=1e-300)


def test_emission_and_global_ambient_without_lights():
    material = Material(ambient=(0.5, 0.25, 1.0, 1), emission=(0.1, 0.2, 0.3, 1))
    scene = unlit_scene(ambient=(0.4, 0.4, 0.2, 1))
    ambient_diffuse, specular = shade_one(scene, material, (0, 0, -1), (0, 0, 1), (0, 0, 1))
    np.testing.assert_allclose(ambient_diffuse, [0.1 + 0.2, 0.2 + 0.1, 0.3 + 0.2], atol=TIGHT)
    np.testing.assert_array_equal(specular, 0.0)


# --------------------------------------------------------------------------- textures


def test_texture_modes_with_a_known_texel():
    ambient_diffuse = np.array([[0.5, 0.25, 1.0]])
    specular = np.array([[0.25, 0.5, 0.125]])
    texel = np.array([[0.5, 1.0, 0.25, 0.5]])
    base = dict(diffuse=(0.8, 0.8, 0.8, 0.6), texture=Texture(np.zeros((1, 1, 4), np.uint8)))
    expected = {
        "modulate": [0.5 * 0.5 + 0.25, 1.0 * 0.25 + 0.5, 0.25 * 1.0 + 0.125],
        "modulate_all": [0.5 * 0.75, 1.0 * 0.75, 0.25 * 1.125],
        "blend": [0.25 + 0.375, 0.5 + 0.375, 0.125 + 0.5625],
    }
    for mode, rgb in expected.items():
        rgba = ref.combine(ambient_diffuse, specular, Material(texture_mode=mode, **base), texel)
        np.testing.assert_allclose(rgba[0], [*np.minimum(rgb, 1.0), 1.0], atol=TIGHT, err_msg=mode)  # opaque
        blended = ref.combine(ambient_diffuse, specular, Material(texture_mode=mode, alpha_mode="blend", **base), texel)
        assert blended[0, 3] == pytest.approx(0.6 * 0.5)  # blending: diffuse alpha × texel alpha
    untextured = ref.combine(ambient_diffuse, specular, Material(diffuse=(0.8, 0.8, 0.8, 0.6)))
    np.testing.assert_allclose(untextured[0], [0.75, 0.75, 1.0, 1.0], atol=TIGHT)  # clamped blue, opaque


def test_bilinear_sampling_orientation_centres_and_wrap():
    # A 2×3 (H×W) image; rows top to bottom. v = 0 is the bottom row.
    pixels = np.zeros((2, 3, 4), np.uint8)
    pixels[..., 3] = 255
    pixels[0, :, 0] = [0, 51, 102]  # top row
    pixels[1, :, 0] = [153, 204, 255]  # bottom row
    red = lambda uv: ref.sample_texture_bilinear(pixels, np.array(uv, dtype=float))[:, 0] * 255
    # Texel centres ((i + 0.5)/W, (j + 0.5)/H) give the texel exactly.
    np.testing.assert_allclose(red([[0.5 / 3, 0.25], [2.5 / 3, 0.25], [1.5 / 3, 0.75]]), [153, 255, 51], atol=1e-9)
    # Halfway between two texel centres: the average.
    np.testing.assert_allclose(red([[1.0 / 3, 0.25], [0.5 / 3, 0.5]]), [(153 + 204) / 2, (153 + 0) / 2], atol=1e-9)
    # Repeat: u = 0 lies between the last and the first column; u + 1 and v − 1 change nothing.
    np.testing.assert_allclose(red([[0.0, 0.25]]), [(255 + 153) / 2], atol=1e-9)
    np.testing.assert_allclose(red([[1.2, -0.75], [-0.8, 1.25]]), red([[0.2, 0.25], [0.2, 0.25]]), atol=1e-9)


def test_textured_plane_uses_bilinear_texels_in_each_mode():
    """A facing plane lit head-on; a 1×1 texture makes every texel known: the image is the combine."""
    texel = np.array([[[200, 100, 50, 128]]], np.uint8)
    t = texel[0, 0] / 255.0
    light = DirectionalLight(direction=(0, 0, -1), diffuse=(0.5, 0.5, 0.5, 1), specular=(0.2, 0.2, 0.2, 1))
    for mode in ("modulate", "modulate_all", "blend"):
        material = Material(ambient=BLACK, diffuse=(1, 1, 1, 1), specular=(1, 1, 1, 1), shininess=5, texture=Texture(texel), texture_mode=mode)
        scene = unlit_scene(
            objects=(SceneObject(plane(2.0), material),), lights=(light,), camera=Camera(eye=(0, 0, 1), fov_y=60),
            shading=Shading(local_viewer=False),  # V = N = L: R·V = 1 everywhere
        )
        image = ref.render_reference(scene)
        a, s = 0.5, 0.2
        rgb = {"modulate": t[:3] * a + s, "modulate_all": t[:3] * (a + s), "blend": 0.5 * t[:3] + 0.5 * (a + s)}[mode]
        np.testing.assert_allclose(image.color[image.covered], np.tile([*rgb, 1.0], (image.covered.sum(), 1)), atol=TIGHT, err_msg=mode)


# --------------------------------------------------------------------------- rasterization

# A camera at z = 1 with a 90° field of view sees the plane z = 0 with x_ndc = x, y_ndc = y, so
# a W×W image maps world (x, y) to window ((x + 1)·W/2, (1 − y)·W/2).
SIZE = 16
PIXEL_CAMERA = Camera(eye=(0, 0, 1), target=(0, 0, 0), fov_y=90.0)


def world_from_window(wx: float, wy: float) -> tuple[float, float, float]:
    return (2.0 * wx / SIZE - 1.0, 1.0 - 2.0 * wy / SIZE, 0.0)


def triangle_object(window_corners, material=None) -> SceneObject:
    """One triangle, given in window coordinates (pixels, y down), counter-clockwise in NDC."""
    positions = np.array([world_from_window(*c) for c in window_corners])
    mesh = Mesh.from_arrays(positions, np.array([[0, 1, 2]]))
    return SceneObject(mesh, material or Material())


def coverage(*objects) -> np.ndarray:
    scene = unlit_scene(objects=objects, camera=PIXEL_CAMERA, size=(SIZE, SIZE))
    return ref.render_reference(scene).covered


def test_axis_aligned_quad_covers_exactly_its_pixels():
    # The plane [−0.5, 0.5]² maps to window [4, 12]²: pixel centres 4.5 … 11.5.
    covered = coverage(SceneObject(plane(1.0)))
    expected = np.zeros((SIZE, SIZE), bool)
    expected[4:12, 4:12] = True
    np.testing.assert_array_equal(covered, expected)


def test_triangle_coverage_and_the_top_left_rule():
    rows, cols = np.mgrid[0:SIZE, 0:SIZE]
    # Right angle at the top left; the hypotenuse x + y = 16 is a right/bottom edge, so the
    # centres exactly on it (col + row = 15) are out. The legs x = 4, y = 4 touch no centre.
    lower = coverage(triangle_object([(4, 4), (4, 12), (12, 4)]))
    np.testing.assert_array_equal(lower, (cols >= 4) & (rows >= 4) & (cols + rows <= 14))
    # The mirror image: now the hypotenuse is a top-left edge, and centres on it are in.
    upper = coverage(triangle_object([(12, 4), (4, 12), (12, 12)]))
    np.testing.assert_array_equal(upper, (cols <= 11) & (rows <= 11) & (cols + rows >= 15))


@pytest.mark.parametrize(
    "first, second",
    [
        # A vertical edge through the centres of column 6 (x = 6.5)
        ([(2, 2.5), (2, 12.5), (6.5, 2.5)], [(6.5, 2.5), (2, 12.5), (6.5, 12.5)]),
        ([(6.5, 2.5), (2, 12.5), (6.5, 12.5)], [(6.5, 2.5), (6.5, 12.5), (11, 7.5)]),
        # A horizontal edge through the centres of row 7
        ([(2.5, 2), (12.5, 7.5), (2.5, 7.5)][::-1], [(2.5, 7.5), (12.5, 7.5), (7.5, 13)][::-1]),
        # A diagonal through centres, split both ways
        ([(2.5, 2.5), (2.5, 12.5), (12.5, 12.5)], [(2.5, 2.5), (12.5, 12.5), (12.5, 2.5)]),
        ([(2.5, 12.5), (12.5, 12.5), (12.5, 2.5)], [(2.5, 12.5), (12.5, 2.5), (2.5, 2.5)]),
    ],
)
def test_shared_edges_are_covered_exactly_once(first, second):
    """Pixel centres exactly on a shared edge belong to exactly one of the two triangles."""
    a = coverage(triangle_object(first))
    b = coverage(triangle_object(second))
    both = coverage(triangle_object(first), triangle_object(second))
    assert not (a & b).any(), "a pixel covered by both triangles"
    np.testing.assert_array_equal(a | b, both)
    # The shared edge passes through pixel centres: some of them must be covered at all.
    assert a.sum() + b.sum() == both.sum() > 0


def test_snapping_to_a_256th_of_a_pixel():
    """An edge 1/1024 pixel left of a pixel centre snaps onto it (a left edge: covered);
    3/1024 pixel to the right of the centre, it snaps to 1/256 right of it (not covered)."""
    for offset, covered_centre in [(-1 / 1024, True), (3 / 1024, False)]:
        edge = 6.5 + offset
        mask = coverage(triangle_object([(edge, 2), (edge, 12), (11, 7)]))
        assert mask[7, 6] == covered_centre, offset
        assert mask[7, 7]


def test_nearest_surface_wins_whatever_the_order():
    near = SceneObject(plane(1.0), Material(ambient=BLACK, diffuse=BLACK, emission=(1, 0, 0, 1)), translate=(0.25, 0, 0.5))
    far = SceneObject(plane(1.0), Material(ambient=BLACK, diffuse=BLACK, emission=(0, 1, 0, 1)))
    for objects, near_index in [((near, far), 0), ((far, near), 1)]:
        image = ref.render_reference(unlit_scene(objects=objects, camera=Camera(eye=(0, 0, 3)), size=(32, 32)))
        overlap = image.covered & (image.depth < 2.75)
        assert overlap.sum() > 50
        assert (image.object[overlap] == near_index).all()
        np.testing.assert_array_equal(image.color[overlap], np.tile([1, 0, 0, 1.0], (overlap.sum(), 1)))
        np.testing.assert_allclose(image.depth[overlap], 2.5, atol=TIGHT)


def test_perspective_correct_interpolation_on_a_tilted_plane():
    """A plane tilted 60° away, textured with a ramp along v: the color follows v at the exact
    ray–plane intersection (perspective-correct), not v interpolated linearly on screen."""
    ramp = np.zeros((64, 1, 4), np.uint8)
    ramp[:, 0, 0] = np.arange(64)[::-1] * 4  # row 0 is the top: red = 4·j with j from the bottom
    ramp[..., 3] = 255
    material = Material(ambient=BLACK, diffuse=BLACK, emission=(1, 1, 1, 1), texture=Texture(ramp), texture_mode="blend")
    tilt = 60.0
    scene = unlit_scene(
        objects=(SceneObject(plane(2.0), material, rotate=(-tilt, 0, 0)),), camera=Camera(eye=(0, 0, 2.5), fov_y=50.0), size=(8, 48)
    )
    image = ref.render_reference(scene)
    rows, cols = np.nonzero(image.covered)
    # Exact intersection of each pixel ray with the plane through the origin, normal (0, cos t, sin t)·…
    rays = ref.pixel_rays(scene.camera, scene.size)[rows, cols]
    t = math.radians(tilt)
    normal_eye = np.array([0.0, math.sin(t), math.cos(t)])  # Rx(−t)·(0, 0, 1)
    origin_eye = np.array([0.0, 0.0, -2.5])
    distance = (origin_eye @ normal_eye) / (rays @ normal_eye)
    hits = rays * distance[:, None]
    np.testing.assert_allclose(image.depth[rows, cols], distance, rtol=1e-12)
    along = (hits - origin_eye) @ np.array([0.0, math.cos(t), -math.sin(t)])  # the plane's own y: Rx(−t)·(0, 1, 0)
    v = along / 2.0 + 0.5
    # Between texel centres the ramp is linear: red = 4·(64·v − 0.5) / 255 (blend halves it, plus 0.5).
    inner = (v > 0.5 / 64) & (v < 1 - 0.5 / 64)
    expected = 0.5 * 4 * (64 * v - 0.5) / 255 + 0.5
    np.testing.assert_allclose(image.color[rows, cols, 0][inner], expected[inner], atol=1e-10)
    # Screen-linear interpolation would be visibly off: the test can tell the two apart.
    screen_rows = rows[inner] + 0.5
    top, bottom = screen_rows.min(), screen_rows.max()
    linear_v = np.interp(screen_rows, [top, bottom], [v[inner].max(), v[inner].min()])
    assert np.abs(0.5 * 4 * (64 * linear_v - 0.5) / 255 + 0.5 - expected[inner]).max() > 0.01


# --------------------------------------------------------------------------- shading frequencies


def fan_mesh(normals) -> Mesh:
    """One triangle facing the camera with the given vertex normals (Mesh() bypasses renormalizing)."""
    positions = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, 1.0, 0.0]], np.float32)
    return Mesh(
        positions=positions,
        normals=np.asarray(normals, np.float32),
        indices=np.array([[0, 1, 2]], np.uint32),
    )


def frequency_scene(mesh, frequency, **shading):
    light = DirectionalLight(direction=(0, 0, -1), diffuse=(1, 1, 1, 1), specular=BLACK)
    material = Material(ambient=BLACK, diffuse=(1, 1, 1, 1))
    return unlit_scene(
        objects=(SceneObject(mesh, material),), lights=(light,), camera=Camera(eye=(0, 0, 2), fov_y=90.0),
        shading=Shading(frequency=frequency, **shading), size=(32, 32),
    )


def screen_barycentrics(image_rows, image_cols):
    """Barycentrics of pixel centres in fan_mesh's triangle seen by frequency_scene's camera
    (the plane is parallel to the image, so screen-linear is perspective-correct)."""
    x = (image_cols + 0.5) / 16.0 - 1.0  # world x = 2·x_ndc at distance 2 with tan 45° = 1
    y = 1.0 - (image_rows + 0.5) / 16.0
    x, y = 2 * x, 2 * y
    b1 = (x + 1) / 2
    b2 = (y + 1) / 2
    return np.stack([1 - b1 - b2, b1, b2], axis=-1)


def test_flat_gouraud_phong_on_one_triangle_with_known_normals():
    tilt = math.radians(50.0)
    normals = [[0, 0, 1], [math.sin(tilt), 0, math.cos(tilt)], [0, math.sin(tilt), math.cos(tilt)]]
    mesh = fan_mesh(normals)
    flat = ref.render_reference(frequency_scene(mesh, "flat"))
    gouraud = ref.render_reference(frequency_scene(mesh, "gouraud"))
    phong = ref.render_reference(frequency_scene(mesh, "phong"))
    rows, cols = np.nonzero(flat.covered)
    b = screen_barycentrics(rows, cols)
    n = np.asarray(normals, np.float32).astype(float)
    # flat: the face normal (0, 0, 1) is lit head-on: 1 everywhere.
    np.testing.assert_allclose(flat.color[rows, cols, :3], 1.0, atol=TIGHT)
    # gouraud: vertex colors N·L = (1, cos 50°, cos 50°), interpolated.
    np.testing.assert_allclose(gouraud.color[rows, cols, 0], b @ n[:, 2], atol=1e-12)
    # phong: the interpolated normal renormalized, then N·L.
    mixed = b @ n
    np.testing.assert_allclose(phong.color[rows, cols, 0], mixed[:, 2] / np.linalg.norm(mixed, axis=1), atol=1e-12)
    assert np.abs(gouraud.color[rows, cols, 0] - phong.color[rows, cols, 0]).max() > 0.01


def test_zero_vertex_normals_fall_back_to_facing_the_viewer():
    """Zero vertex normals on a plane turned away from the light: Gouraud and Phong use (0, 0, 1)
    in eye space, which the head-on light hits fully."""
    mesh = fan_mesh(np.zeros((3, 3)))
    for frequency in ("gouraud", "phong"):
        scene = frequency_scene(mesh, frequency)
        turned = Scene(
            objects=(SceneObject(mesh, scene.objects[0].material, rotate=(0, 60, 0)),), lights=scene.lights,
            ambient=BLACK, camera=scene.camera, shading=scene.shading, size=scene.size,
        )
        image = ref.render_reference(turned)
        assert image.covered.sum() > 20
        np.testing.assert_allclose(image.color[image.covered][:, :3], 1.0, atol=TIGHT, err_msg=frequency)


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_two_sided_lighting_of_a_back_face(frequency):
    """A plane turned 180° shows its back to a head-on light: one-sided it gets N·L = −1 (only
    ambient), two-sided it is lit with −N (full diffuse). A mirrored plane still faces front."""
    light = DirectionalLight(direction=(0, 0, -1), ambient=(0.1, 0.1, 0.1, 1), diffuse=(0.5, 0.5, 0.5, 1))
    material = Material(ambient=(1, 1, 1, 1), diffuse=(1, 1, 1, 1))
    base = dict(lights=(light,), ambient=BLACK, camera=Camera(eye=(0, 0, 2)), size=(16, 16))
    cases = [
        (dict(rotate=(0, 180, 0)), False, 0.1),
        (dict(rotate=(0, 180, 0)), True, 0.6),
        (dict(scale=(-1, 1, 1)), False, 0.6),  # mirrored: winding flips, normals stay outward
        (dict(scale=(-1, 1, 1)), True, 0.6),
    ]
    for placement, two_sided, expected in cases:
        scene = Scene(objects=(SceneObject(plane(1.0), material, **placement),), shading=Shading(frequency=frequency, two_sided=two_sided), **base)
        image = ref.render_reference(scene)
        assert image.covered.sum() > 50
        np.testing.assert_allclose(image.color[image.covered][:, :3], expected, atol=TIGHT, err_msg=f"{placement} {two_sided}")


def test_flat_shading_is_constant_per_triangle_and_lit_at_the_centroid():
    mesh = uv_sphere(1.0, 5, 3)  # 20 triangles
    light = PositionalLight(position=(0.5, 1.0, 2.0), diffuse=(0.7, 0.7, 0.7, 1), specular=(1, 1, 1, 1))
    material = Material(ambient=BLACK, diffuse=(1, 1, 1, 1), specular=(0.5, 0.5, 0.5, 1), shininess=8)
    scene = unlit_scene(objects=(SceneObject(mesh, material, rotate=(20, 10, 0)),), lights=(light,), camera=Camera(eye=(0, 0, 3)), shading=Shading(frequency="flat"), size=(48, 48))
    image = ref.render_reference(scene)
    view = ref.eye_from_world(scene.camera) @ ref.world_from_model(scene.objects[0])
    for triangle in np.unique(image.triangle[image.covered]):
        p = mesh.positions[mesh.indices[triangle]].astype(float)
        normal = np.linalg.inv(view[:3, :3]).T @ np.cross(p[1] - p[0], p[2] - p[0])
        normal /= np.linalg.norm(normal)
        centroid = view[:3, :3] @ p.mean(axis=0) + view[:3, 3]
        to_light = ref.eye_from_world(scene.camera)[:3, :3] @ np.array([0.5, 1.0, 2.0]) + ref.eye_from_world(scene.camera)[:3, 3] - centroid
        to_light /= np.linalg.norm(to_light)
        to_viewer = -centroid / np.linalg.norm(centroid)
        n_dot_l = normal @ to_light
        r_dot_v = (2 * n_dot_l * normal - to_light) @ to_viewer
        expected = 0.7 * max(n_dot_l, 0) + (0.5 * max(r_dot_v, 0) ** 8 if n_dot_l > 0 else 0.0)
        pixels = image.color[image.triangle == triangle][:, :3]
        np.testing.assert_allclose(pixels, min(expected, 1.0), atol=1e-12, err_msg=f"triangle {triangle}")


# --------------------------------------------------------------------------- clipping, scale, analytic shapes


def test_near_plane_clipping_matches_the_exact_rectangle():
    """A floor running from behind the camera to beyond the image: triangles cross the near plane."""
    material = Material(ambient=(0.3, 0.3, 0.3, 1), diffuse=(0.6, 0.6, 0.6, 1))
    light = PositionalLight(position=(0, 1, 1), attenuation=(1, 0.2, 0.0))
    scene = Scene(
        objects=(SceneObject(plane(20.0, 2), material, rotate=(-90, 0, 0), translate=(0, -0.5, 0)),),
        lights=(light,), camera=Camera(eye=(0, 0, 3), near=0.5, far=50), size=(32, 32), shading=Shading(frequency="phong"),
    )
    mesh_image = ref.render_reference(scene)
    exact = ref.render_analytic_rectangle(scene, (0, -0.5, 0), (10, 0, 0), (0, 0, -10), material)
    assert exact.covered.sum() > 200
    sure = exact.edge_margin > 0.01  # away from the rectangle's border
    np.testing.assert_array_equal(mesh_image.covered[sure], exact.covered[sure])
    assert (mesh_image.depth[mesh_image.covered] >= 0.5).all()
    np.testing.assert_allclose(mesh_image.color[sure & exact.covered], exact.color[sure & exact.covered], atol=1e-9)


def test_chunked_rasterization_gives_the_same_image(monkeypatch):
    """The candidate pairs are processed in chunks; the chunk size must not change anything."""
    scene = unlit_scene(
        objects=(SceneObject(sphere_for_triangles(3000), Material()), SceneObject(plane(3.0), Material(), translate=(0, 0, -0.5))),
        lights=(PositionalLight(),), camera=Camera(eye=(0.3, 0.2, 3)), size=(40, 32),
    )
    whole = ref.render_reference(scene)
    # Patched where the rasterizer reads it (the package's namespace does not hold it).
    from wgpu_shading.study.reference import raster

    monkeypatch.setattr(raster, "CANDIDATE_CHUNK", 97)
    chunked = ref.render_reference(scene)
    for field in ("color", "covered", "triangle", "object", "depth", "edge_margin"):
        np.testing.assert_array_equal(getattr(chunked, field), getattr(whole, field), err_msg=field)


@pytest.mark.parametrize("reflection", ["phong", "blinn-phong"])
def test_fine_sphere_converges_to_the_analytic_sphere(reflection):
    """Phong shading of a fine tessellation approaches the exact sphere (away from the rim)."""
    material = Material(ambient=(0.2, 0.2, 0.2, 1), diffuse=(0.6, 0.5, 0.4, 1), specular=(0.8, 0.8, 0.8, 1), shininess=30)
    obj = SceneObject(sphere_for_triangles(60_000), material, translate=(0.1, 0, 0), scale=(0.8, 0.8, 0.8))
    scene = Scene(
        objects=(obj,), lights=(PositionalLight(position=(2, 2, 3)), DirectionalLight(direction=(1, 0, -1), diffuse=(0.3, 0.3, 0.3, 1))),
        shading=Shading(frequency="phong", reflection=reflection), size=(64, 64),
    )
    center, radius = ref.sphere_in_world(obj)
    np.testing.assert_allclose(center, [0.1, 0, 0], atol=TIGHT)
    assert radius == pytest.approx(0.8)
    exact = ref.render_analytic_sphere(scene, center, radius, material)
    tessellated = ref.render_reference(scene)
    inner = exact.covered & (exact.edge_margin > 1.5)
    assert inner.sum() > 500 and tessellated.covered[inner].all()
    assert exact.color[inner, :3].max() > 0.95  # the highlight is in view
    np.testing.assert_allclose(tessellated.color[inner], exact.color[inner], atol=0.5 / 255)


def test_texel_footprint_of_a_facing_plane():
    """plane(1) seen by PIXEL_CAMERA spans 8 pixels; a 4×4 texture over it is 0.5 texels per
    pixel step (0 where untextured or uncovered)."""
    texture = Texture(np.full((4, 4, 4), 200, np.uint8))
    scene = unlit_scene(
        objects=(SceneObject(plane(1.0), Material(texture=texture)), SceneObject(plane(2.0), Material(), translate=(0, 0, -0.5))),
        camera=PIXEL_CAMERA, size=(SIZE, SIZE),
    )
    image = ref.render_reference(scene)
    textured = image.object == 0
    assert textured.sum() == 64
    np.testing.assert_allclose(image.texel_footprint[textured], 0.5, atol=1e-12)  # 4 texels over 8 pixels
    np.testing.assert_array_equal(image.texel_footprint[~textured], 0.0)
