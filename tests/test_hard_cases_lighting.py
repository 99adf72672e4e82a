"""Hard cases of the lighting equation (docs/hard-cases.md): each is checked twice.

1. At exact inputs, through the product's own WGSL (tests/wgsl_harness.py runs
   lighting.wgsl's shade() in a compute shader): a light exactly at the point, L = −V,
   pow(0, 0), a zero normal... compared with the float64 reference's limit value.
2. In full renders to a float32 target, against the same-mesh float64 reference.

WGSL lets implementations assume no NaN or Inf, so each guard sits on an input; a test
here fails if its guard is removed (docs/hard-cases.md lists the scratch runs)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from support import EDGE_BAND, compare
from wgsl_harness import gpu_shade, run_kernel
from wgpu_shading.study import reference as ref
from wgpu_shading.scene import Mesh, plane, uv_sphere
from wgpu_shading.scene import (
    Camera,
    DirectionalLight,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    SpotLight,
)

# Camera at the origin looking down -Z: eye space is world space, so inputs are easy to state.
EYE_CAMERA = Camera(eye=(0.0, 0.0, 0.0), target=(0.0, 0.0, -1.0), near=0.01, far=100.0)
SPHERE = uv_sphere(1.0, 32, 16)
SHINY = Material(ambient=(0.2, 0.2, 0.2, 1), diffuse=(0.6, 0.5, 0.4, 1), specular=(0.7, 0.8, 0.9, 1), shininess=30.0)
UP = np.array([[0.0, 0.0, 1.0]])


def kernel_scene(*lights, material: Material = SHINY, **shading) -> Scene:
    return Scene(objects=(SceneObject(SPHERE, material),), lights=lights, camera=EYE_CAMERA, shading=Shading(**shading))


def check_shade(renderer, scene: Scene, points, normals, to_viewer, atol: float = 2e-6) -> tuple[np.ndarray, np.ndarray]:
    """GPU shade() equals the reference's at these exact inputs; returns the GPU's values."""
    points, normals, to_viewer = (np.atleast_2d(np.asarray(a, dtype=np.float64)) for a in (points, normals, to_viewer))
    gpu_ambient_diffuse, gpu_specular = gpu_shade(renderer.device, scene, points, normals, to_viewer)
    expected = ref.shade(points, normals, to_viewer, scene, scene.objects[0].material)
    for got, want, part in ((gpu_ambient_diffuse, expected[0], "ambient+diffuse"), (gpu_specular, expected[1], "specular")):
        assert np.isfinite(got).all(), f"{part}: NaN or Inf from the GPU: {got}"
        np.testing.assert_allclose(got, want, rtol=2e-5, atol=atol, err_msg=part)
    return gpu_ambient_diffuse, gpu_specular


def _fan(count: int = 41) -> np.ndarray:
    """Unit normals tilted from +Z towards +X by -20..20 degrees."""
    angles = np.radians(np.linspace(-20.0, 20.0, count))
    return np.stack([np.sin(angles), np.zeros_like(angles), np.cos(angles)], axis=1)


# --------------------------------------------------------------------------- exact inputs


@pytest.mark.parametrize("shininess", [0.0, 0.5, 1.0, 100.0, 1e4])
@pytest.mark.parametrize("reflection", ["phong", "blinn-phong"])
def test_shininess_extremes(renderer, shininess, reflection):
    """pow(0, 0) is undefined in WGSL: 0^s = 0 for every s and x^0 = 1 for x > 0 are the limits
    chosen. Shininess below 1 widens the lobe, 1e4 makes it a needle; nothing may be NaN."""
    light = DirectionalLight(direction=(-0.2, 0.0, -1.0))
    scene = kernel_scene(light, material=replace(SHINY, shininess=shininess), reflection=reflection)
    normals = _fan()
    points = np.tile([0.0, 0.0, -2.0], (len(normals), 1))
    # float32 pow(x, s) has a relative error of about s·2^-24 (x itself is rounded): 1e4 gives
    # ~1e-3 relative, up to 6e-4 absolute here (0.15/255).
    atol = 2e-6 if shininess < 1e3 else 1e-3
    _, specular = check_shade(renderer, scene, points, normals, np.tile([0.0, 0.0, 1.0], (len(normals), 1)), atol=atol)
    if shininess == 0.0:
        # Every lit point facing the mirror direction gets the full highlight: specular_light × specular_material.
        np.testing.assert_allclose(specular, np.tile([0.7, 0.8, 0.9], (len(normals), 1)), rtol=1e-6)


def test_shininess_zero_gives_no_highlight_on_the_unlit_side(renderer):
    scene = kernel_scene(DirectionalLight(direction=(0.0, 0.0, 1.0)), material=replace(SHINY, shininess=0.0))
    _, specular = check_shade(renderer, scene, [[0, 0, -2]], UP, UP)  # light from behind the surface
    assert (specular == 0.0).all()


def test_light_exactly_at_the_point(renderer):
    """L = normalize(0) is undefined; the light is treated as straight above (L = N)."""
    light = PositionalLight(position=(0.0, 0.0, -2.0), diffuse=(0.5, 0.5, 0.5, 1))
    ambient_diffuse, _ = check_shade(renderer, kernel_scene(light), [[0.0, 0.0, -2.0]], UP, UP)
    # global 0.2 × 0.2 + full diffuse 0.5 × material diffuse
    np.testing.assert_allclose(ambient_diffuse[0], 0.04 + 0.5 * np.array([0.6, 0.5, 0.4]), rtol=1e-6)


def test_light_at_distance_zero_with_no_constant_attenuation(renderer):
    """1/(kq·d²) at d = 0 is infinite: the denominator's floor keeps it finite and huge, so
    the final color saturates; nothing divides by zero."""
    light = PositionalLight(position=(0.0, 0.0, -2.0), attenuation=(0.0, 0.0, 1.0))
    ambient_diffuse, _ = check_shade(renderer, kernel_scene(light), [[0.0, 0.0, -2.0]], UP, UP)
    assert (ambient_diffuse > 1e18).all()
    color = run_kernel(
        renderer.device,
        kernel_scene(light),
        np.array([[0.0, 0.0, -2.0, 0.0, 0.0, 1.0]]),
        "    write_vector(0u, clamp(shade(input_vector(0u), input_vector(3u), input_vector(3u)).ambient_diffuse, vec3<f32>(0.0), vec3<f32>(1.0)));",
        3,
    )
    np.testing.assert_array_equal(color, [[1.0, 1.0, 1.0]])


def test_light_exactly_at_the_eye(renderer):
    light = PositionalLight(position=(0.0, 0.0, 0.0))
    check_shade(renderer, kernel_scene(light), [[0.3, -0.2, -2.0]], [[0.1, 0.0, 0.995]], [[-0.148, 0.099, 0.984]])


def test_eye_exactly_at_the_point(renderer):
    """V = normalize(-P) with P = 0: the viewer is taken to look along the normal."""
    view = run_kernel(
        renderer.device,
        kernel_scene(DirectionalLight()),
        np.array([[0.0, 0.0, 0.0, 0.6, 0.0, 0.8]]),
        "    write_vector(0u, view_direction(input_vector(0u), input_vector(3u)));",
        3,
    )
    np.testing.assert_allclose(view, [[0.6, 0.0, 0.8]], rtol=1e-6)
    check_shade(renderer, kernel_scene(PositionalLight(position=(1, 1, 1))), [[0.0, 0.0, 0.0]], [[0.6, 0.0, 0.8]], [[0.6, 0.0, 0.8]])


@pytest.mark.parametrize("shininess, expected", [(30.0, 0.0), (0.0, 0.0)])
def test_light_opposite_the_viewer_has_no_half_vector(renderer, shininess, expected):
    """Blinn-Phong with L = −V: H = normalize(0). No highlight (N·H = 0, and 0^s = 0 for every s)."""
    light = DirectionalLight(direction=(0.0, 0.0, 1.0))  # travels towards the viewer: L = (0, 0, -1)
    scene = kernel_scene(light, material=replace(SHINY, shininess=shininess), reflection="blinn-phong", local_viewer=False)
    normal = [[0.0, 0.0, -1.0]]  # facing the light (a back face lit two-sidedly, say)
    _, specular = check_shade(renderer, scene, [[0.0, 0.0, -2.0]], normal, UP)
    np.testing.assert_allclose(specular[0], expected * np.array([0.7, 0.8, 0.9]), rtol=1e-6)


def test_grazing_light_from_both_sides(renderer):
    """N·L through zero: diffuse goes continuously to 0; the highlight is cut at N·L = 0
    (f_i), although a Phong lobe seen at the mirror angle is at its maximum there."""
    epsilons = np.array([-1e-3, -1e-6, 0.0, 1e-6, 1e-3])
    light = DirectionalLight(direction=(0.0, 0.0, -1.0))  # L = (0, 0, 1)
    normals = np.stack([-np.sqrt(1.0 - epsilons**2), np.zeros_like(epsilons), epsilons], axis=1)  # N·L = epsilon
    mirror = 2.0 * epsilons[:, None] * normals - [0.0, 0.0, 1.0]  # R = reflect(-L, N): the viewer sits on it
    points = np.tile([0.0, 0.0, -2.0], (len(epsilons), 1))
    ambient_diffuse, specular = check_shade(renderer, kernel_scene(light), points, normals, mirror)
    assert (specular[epsilons <= 0] == 0).all()
    assert (specular[epsilons > 0] > 0.9 * np.array([0.7, 0.8, 0.9])).all()  # the lobe's peak
    np.testing.assert_allclose(ambient_diffuse, 0.04, atol=1e-3)  # diffuse ~0 on both sides


def test_no_highlight_on_the_unlit_side(renderer):
    """Light just below the horizon, viewer at the mirror angle above it: R·V = cos 2a > 0,
    so an ungated Phong term would show a full highlight on a surface the light cannot reach."""
    a = np.radians(3.0)
    light = DirectionalLight(direction=(-np.cos(a), 0.0, np.sin(a)))  # L = (cos a, 0, -sin a)
    to_viewer = [[-np.cos(a), 0.0, np.sin(a)]]
    scene = kernel_scene(light)
    _, specular = check_shade(renderer, scene, [[0.0, 0.0, -2.0]], UP, to_viewer)
    assert (specular == 0.0).all()


def test_zero_normal_falls_back_to_facing_the_viewer(renderer):
    normal = run_kernel(
        renderer.device,
        kernel_scene(DirectionalLight()),
        np.array([[0.0, 0.0, 0.0], [1e-20, 0.0, 0.0], [0.0, 3.0, 4.0]]),
        "    write_vector(0u, safe_normalize(input_vector(0u), FALLBACK_NORMAL));",
        3,
    )
    np.testing.assert_allclose(normal, [[0, 0, 1], [0, 0, 1], [0, 0.6, 0.8]], rtol=1e-6)


def _spot_points(angles_degrees) -> np.ndarray:
    """Points 2 units from a spot at the origin pointing down -Z, at the given angles off its axis."""
    angles = np.radians(np.asarray(angles_degrees, dtype=np.float64))
    return np.stack([2 * np.sin(angles), np.zeros_like(angles), -2 * np.cos(angles)], axis=1)


@pytest.mark.parametrize(
    "cutoff, exponent, angles, lit",
    [
        (0.0, 0.0, [0.0, 1e-4, 1.0], [False, False, False]),  # a cone of zero width lights nothing
        (90.0, 0.0, [0.0, 89.9, 90.0, 90.1], [True, True, False, False]),  # open hemisphere
        (20.0, 0.0, [0.0, 19.99, 20.01], [True, True, False]),
        (0.01, 0.0, [0.0, 0.009, 0.011], [True, True, False]),  # exact where cos rounds to 1 in float32
        (30.0, 1000.0, [0.0, 2.0, 5.0], [True, True, True]),
    ],
)
def test_spot_cone_limits(renderer, cutoff, exponent, angles, lit):
    spot = SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=cutoff, exponent=exponent,
                     ambient=(0.1, 0.1, 0.1, 1), diffuse=(0.5, 0.5, 0.5, 1))
    points = _spot_points(angles)
    normals = -points / np.linalg.norm(points, axis=1, keepdims=True)  # facing the light
    # float32 pow(cos, e) carries a relative error of about e·2^-24 (6e-5 for e = 1000).
    ambient_diffuse, _ = check_shade(renderer, kernel_scene(spot), points, normals, normals, atol=2e-6 + 1e-7 * exponent)
    light_part = ambient_diffuse - 0.04  # minus global ambient × material ambient
    # The spot's smallest contribution here is ≥ 0.02 × cos^1000(10°) ≈ 1e-9 relative... so use
    # a threshold above float32's rounding of 0.2 × 0.2 (1e-9) but far below any lit value.
    np.testing.assert_array_equal(light_part.max(axis=1) > 1e-6, lit)
    if exponent == 1000.0:
        expected = np.cos(np.radians(angles)) ** 1000  # relative to the on-axis value
        np.testing.assert_allclose(light_part[:, 0] / light_part[0, 0], expected, rtol=1e-4, atol=1e-30)


# --------------------------------------------------------------------------- full renders


def render_and_compare(renderer, scene: Scene, what: str) -> np.ndarray:
    frame = renderer.render_frame(scene, float32=True, depth=True)
    assert np.isfinite(frame.color).all() and frame.color.min() >= 0 and frame.color.max() <= 1
    compare(frame, ref.render_reference(scene), EDGE_BAND, what)
    return frame.color


def sphere_scene(material: Material, frequency: str, reflection: str = "phong") -> Scene:
    return Scene(
        objects=(SceneObject(SPHERE, material),),
        lights=(PositionalLight(position=(2.0, 2.0, 3.0)),),
        camera=Camera(eye=(0.0, 0.0, 3.0), fov_y=45.0, near=0.5, far=10.0),
        shading=Shading(frequency=frequency, reflection=reflection),
        size=(64, 64),
    )


@pytest.mark.parametrize("shininess", [0.0, 0.3, 1e4])
@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_shininess_extremes_render(renderer, shininess, frequency):
    render_and_compare(renderer, sphere_scene(replace(SHINY, shininess=shininess), frequency, "blinn-phong"), f"shininess {shininess}")


@pytest.mark.parametrize("two_sided", [False, True])
@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_back_faces(renderer, two_sided, frequency):
    """A square seen from behind, lit from the viewer's side. OpenGL's default lights the back
    with the front normal (so only ambient shows); two-sided lighting flips it (fully lit)."""
    scene = Scene(
        objects=(SceneObject(plane(2.0, 4), SHINY),),
        lights=(PositionalLight(position=(0.5, 0.5, -3.0)),),
        camera=Camera(eye=(0.0, 0.0, -3.0), target=(0.0, 0.0, 0.0), near=0.5, far=10.0),
        shading=Shading(frequency=frequency, two_sided=two_sided),
        size=(48, 48),
    )
    color = render_and_compare(renderer, scene, f"back faces, two_sided={two_sided}")
    centre = color[24, 24, :3]
    if two_sided:
        assert centre[0] > 0.3
    else:
        np.testing.assert_allclose(centre, 0.2 * np.array([0.2, 0.2, 0.2]), atol=1e-5)  # global × material ambient only


def test_cancelling_vertex_normals_on_a_thin_sheet(renderer):
    """Both sides of a sheet share vertices, so the unit face normals cancel; the vertex takes
    the largest adjacent face's normal instead of normalize(0).

    The two sides are coincident triangles, and without culling (OpenGL's default) which one
    wins the depth test is a tie broken by rounding: for Gouraud and Phong both sides have
    the same vertex normals, so the picture is the same either way; for flat shading their
    face normals are opposite, so each pixel must show one side or the other."""
    square = plane(2.0, 2)
    faces = square.indices.astype(np.int64)
    sheet = Mesh.from_arrays(square.world_positions(), np.concatenate([faces, faces[:, ::-1]]))
    assert np.isfinite(sheet.normals).all() and np.allclose(np.linalg.norm(sheet.normals, axis=1), 1.0)
    for frequency in ("gouraud", "phong"):
        scene = replace(sphere_scene(SHINY, frequency), objects=(SceneObject(sheet, SHINY, rotate=(-20.0, 30.0, 0.0)),))
        render_and_compare(renderer, scene, f"thin sheet, {frequency}")
    scene = replace(sphere_scene(SHINY, "flat"), objects=(SceneObject(sheet, SHINY, rotate=(-20.0, 30.0, 0.0)),))
    # Each side alone, with the sheet's (shared) vertex data: the float64 reference breaks
    # the exact depth tie by rounding too, so compare against each side separately.
    sides = []
    for side_faces in (faces, faces[:, ::-1]):
        side = Mesh.from_arrays(square.world_positions(), side_faces, normals=sheet.normals)
        sides.append(ref.render_reference(replace(scene, objects=(replace(scene.objects[0], mesh=side),))))
    color = renderer.render(scene, float32=True).astype(np.float64)
    assert np.isfinite(color).all()
    inside = sides[0].covered & (sides[0].edge_margin > 1 / 16) & (sides[1].edge_margin > 1 / 16)
    error = np.minimum(*(np.abs(color - side.color).max(axis=2) for side in sides))
    assert error[inside].max() <= 1 / 255, "a flat-shaded pixel shows neither side of the sheet"


def test_zero_length_normals_in_a_file(renderer, tmp_path):
    """`vn 0 0 0` in an OBJ: those normals are recomputed instead of reaching normalize(0)."""
    from wgpu_shading import load_mesh

    body = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n"
    (tmp_path / "zero.obj").write_text(body.replace("v -1 -1 0", "vn 0 0 0\nv -1 -1 0"))
    (tmp_path / "none.obj").write_text(body.replace("//1", ""))
    zero, none = load_mesh(tmp_path / "zero.obj"), load_mesh(tmp_path / "none.obj")
    np.testing.assert_allclose(zero.normals, none.normals)
    scene = replace(sphere_scene(SHINY, "phong"), objects=(SceneObject(zero, SHINY),))
    render_and_compare(renderer, scene, "zero normals in a file")


def test_interpolated_normal_through_zero(renderer):
    """Opposite normals at the two sides of a square: the interpolated normal crosses zero
    along the middle. Either side is lit per its (renormalized) normal; the zero itself
    takes the fallback, never NaN."""
    square = plane(2.0, 1)
    positions = square.world_positions()
    normals = np.where(positions[:, :1] < 0, [[0.0, 0.0, 1.0]], [[0.0, 0.0, -1.0]])
    mesh = Mesh.from_arrays(positions, square.indices, normals=normals)
    scene = replace(sphere_scene(SHINY, "phong"), objects=(SceneObject(mesh, SHINY),), size=(65, 65))
    color = render_and_compare(renderer, scene, "normal through zero")
    assert color[32, 10, 0] > color[32, 54, 0]  # the left half faces the light, the right away


def test_light_on_the_surface(renderer):
    """A point light lying on the plane it lights, with inverse-square falloff and kc = 0:
    grazing everywhere except at the light itself, where the attenuation is infinite."""
    light = PositionalLight(position=(0.0, 0.0, 0.0), attenuation=(0.0, 0.0, 1.0), ambient=(0.05, 0.05, 0.05, 1))
    scene = Scene(
        objects=(SceneObject(plane(2.0, 4), SHINY),),
        lights=(light,),
        camera=Camera(eye=(0.0, 0.0, 3.0), near=0.5, far=10.0),
        size=(65, 65),  # odd: the centre pixel's ray hits the light exactly
    )
    color = render_and_compare(renderer, scene, "light on the surface")
    assert (color[32, 32, :3] == 1.0).all()  # saturated at the light


@pytest.mark.parametrize("cutoff, exponent", [(0.0, 0.0), (90.0, 0.0), (90.0, 1000.0), (15.0, 0.0)])
def test_spot_extremes_render(renderer, cutoff, exponent):
    spot = SpotLight(position=(0.0, 0.0, 1.0), direction=(0.0, 0.0, -1.0), cutoff=cutoff, exponent=exponent, ambient=(0.1, 0.1, 0.1, 1))
    scene = Scene(
        objects=(SceneObject(plane(3.0, 6), SHINY),),
        lights=(spot,),
        camera=Camera(eye=(0.0, 0.0, 3.0), near=0.5, far=10.0),
        size=(48, 48),
    )
    color = render_and_compare(renderer, scene, f"spot cutoff {cutoff} exponent {exponent}")
    if cutoff == 0.0:
        np.testing.assert_allclose(color[:, :, :3], 0.04, atol=1e-6)  # nothing from the spot at all
