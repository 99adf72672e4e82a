"""Material maps and colour spaces: the GPU against the float64 reference (docs/conventions.md,
"Material maps" and "Colour spaces"), for every map and shading frequency, with the same
acceptance criterion as tests/test_gpu_vs_reference.py (1/255 on 99.9 % of the covered
pixels away from triangle edges). Maps are small, smooth and magnified, so the reference's
bilinear level-0 sampling is what the GPU does."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.render.features import object_features
from wgpu_shading.scene import Camera, DirectionalLight, Material, PositionalLight, Scene, SceneObject, Shading, Texture, cube, plane, torus
from wgpu_shading.scene.maps import srgb_decode, srgb_encode
from wgpu_shading.study import reference as ref

from support import EDGE_BAND, compare, smooth_texture


def _grid(size: int = 8):
    i, j = np.meshgrid(np.arange(size), np.arange(size), indexing="xy")
    return 2 * np.pi * i / size, 2 * np.pi * j / size


def smooth_normal_map() -> Texture:
    """Gentle bumps, seamless under repeat: small steps between texels keep lavapipe's
    8-bit filtering within rounding of the exact bilinear value."""
    u, v = _grid()
    x, y = 0.25 * np.sin(u), 0.25 * np.cos(v)
    z = np.sqrt(1.0 - x**2 - y**2)
    rgb = np.stack([x, y, z], axis=-1) * 0.5 + 0.5
    return Texture(np.round(rgb * 255.0).astype(np.uint8), name="normals", encoding="linear")


def smooth_grey(low: float, high: float) -> Texture:
    u, v = _grid()
    value = low + (high - low) * (0.5 + 0.25 * np.sin(u) + 0.25 * np.cos(v))
    return Texture(np.round(np.repeat(value[:, :, None], 3, axis=2) * 255.0).astype(np.uint8), name="grey")


def smooth_height() -> Texture:
    """A gentle height field (32 × 32, smooth) for the bump map."""
    u, v = _grid(32)
    value = 0.5 + 0.2 * np.sin(u) * np.cos(v)
    return Texture(np.round(np.repeat(value[:, :, None], 3, axis=2) * 255.0).astype(np.uint8), name="height")


def maps(name: str) -> dict:
    return {
        "normal_map": dict(normal_map=smooth_normal_map(), normal_scale=0.8),
        "bump_map": dict(bump_map=smooth_height(), bump_scale=3.0),
        "specular_map": dict(specular_map=smooth_texture()),
        "shininess_map": dict(shininess_map=smooth_grey(0.3, 1.0)),
        "emissive_map": dict(emissive_map=smooth_texture(), emission=(0.4, 0.3, 0.2, 1)),
        "occlusion_map": dict(occlusion_map=smooth_grey(0.2, 1.0), occlusion_strength=0.8),
        # mask with cutoff 0: the map is compiled in and nothing is discarded (the float32
        # target cannot blend); test_alpha_map_sets_the_output_alpha checks the values.
        "alpha_map": dict(alpha_map=smooth_grey(0.4, 1.0), alpha_mode="mask", alpha_cutoff=0.0),
    }[name]


def scene_with(material: Material, frequency: str, color_space: str = "auto", two_sided: bool = False) -> Scene:
    lights = (
        DirectionalLight(direction=(-1.0, -0.6, -1.0), ambient=(0.2, 0.2, 0.2, 1), diffuse=(0.5, 0.5, 0.45, 1), specular=(0.6, 0.6, 0.6, 1)),
        PositionalLight(position=(1.2, 1.0, 2.5), diffuse=(0.4, 0.35, 0.3, 1), specular=(0.5, 0.5, 0.5, 1)),
    )
    objects = (
        # (A torus, not a uv sphere: a sphere's poles minify every map, where the GPU uses mipmaps.)
        SceneObject(torus(0.45, 0.2, 32, 16), material, rotate=(50, 30, 0), translate=(-0.5, 0.2, 0)),
        SceneObject(cube(0.8), material, rotate=(30, 40, 0), translate=(0.6, 0.1, -0.3)),
        # Seen from behind: lit with −N when two-sided, a mirrored tangent frame.
        SceneObject(plane(1.2, 2), material, rotate=(-60, 170 if two_sided else 10, 0), translate=(0.0, -0.6, 0.2)),
    )
    return Scene(
        objects=objects, lights=lights, ambient=(0.3, 0.3, 0.3, 1), camera=Camera(eye=(0.1, 0.3, 3.0), target=(0, 0, 0)),
        size=(112, 96), background=(0.1, 0.1, 0.1, 1),
        shading=Shading(frequency=frequency, reflection="blinn-phong", two_sided=two_sided, color_space=color_space),
    )


def mapped_material(name: str, **extra) -> Material:
    settings = dict(ambient=(0.3, 0.25, 0.2, 1), diffuse=(0.7, 0.6, 0.5, 0.8), specular=(0.6, 0.6, 0.6, 1), shininess=30.0)
    return Material(**(settings | maps(name) | extra))


MAPS = ["normal_map", "bump_map", "specular_map", "shininess_map", "emissive_map", "occlusion_map", "alpha_map"]


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
@pytest.mark.parametrize("name", MAPS)
def test_each_map_matches_the_reference(renderer, name, frequency):
    scene = scene_with(mapped_material(name), frequency, two_sided=name in ("normal_map", "bump_map"))
    features = object_features(scene, scene.objects[0])
    per_fragment_normal = name in ("normal_map", "bump_map")
    # Compiled in only where it changes pixels: normal and bump maps need per-fragment normals.
    assert getattr(features, name) == (frequency == "phong" or not per_fragment_normal)
    reference = ref.render_reference(scene)
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    if per_fragment_normal and frequency == "phong":
        # lavapipe filters the RGBA8 normal map in 8-bit fixed point: a normal off by ~1/255
        # moves a highlight's steep flank by up to ~3/255 (docs/conventions.md).
        normal_map_criterion(gpu, reference, f"{name} / {frequency}")
    else:
        compare(gpu, reference, EDGE_BAND, f"{name} / {frequency}")
    if getattr(features, name) and name != "alpha_map":  # the map is visible: the image differs from the one without it
        plain = renderer.render(scene_with(mapped_material(name, **{name: None}), frequency, two_sided=scene.shading.two_sided), float32=True)
        assert np.abs(plain - gpu.color).max() > 0.05


def normal_map_criterion(gpu, reference, what: str) -> None:
    compared = reference.covered & (reference.edge_margin >= EDGE_BAND)
    error = np.abs(gpu.color.astype(np.float64) - reference.color).max(axis=-1)[compared]
    assert (error <= 1.0 / 255.0).mean() >= 0.9, f"{what}: {(error <= 1 / 255).mean():.4%} within 1/255"
    assert (error <= 4.0 / 255.0).mean() >= 0.999, f"{what}: max error {error.max() * 255:.2f}/255"


@pytest.mark.parametrize("two_sided", [False, True])
def test_a_tilted_normal_map_turns_the_normal_by_hand(renderer, two_sided):
    """A plane facing the viewer, uv = (x, y) (so T = +x, B = +y), a constant map normal
    (0.6, 0, 0.8): N = (0.6, 0, 0.8), and a light from +x gives diffuse 0.6 exactly. Seen
    from behind with two-sided lighting, the back is the mirror image: N = (0.6, 0, −0.8)
    in the plane's frame turned around, still 0.6 towards +x."""
    texel = np.array([[[round(0.8 * 255), 128, round(0.9 * 255)]]], np.uint8)  # (0.6, 0, 0.8) encoded (nearly)
    mapped = (texel[0, 0] / 255.0) * 2.0 - 1.0
    expected = mapped[0] / np.linalg.norm(mapped)
    material = Material(ambient=(0, 0, 0, 1), diffuse=(1, 1, 1, 1), normal_map=Texture(texel, encoding="linear"))
    light = DirectionalLight(direction=(-1, 0, 0), diffuse=(1, 1, 1, 1))
    scene = Scene(objects=(SceneObject(plane(1.0), material, rotate=(0, 180 if two_sided else 0, 0)),), lights=(light,), ambient=(0, 0, 0, 1),
                  camera=Camera(eye=(0, 0, 2.0)), size=(32, 32), shading=Shading(two_sided=two_sided))
    image = renderer.render(scene, float32=True)
    assert image[16, 16, 0] == pytest.approx(expected, abs=1.5 / 255)


@pytest.mark.parametrize("frequency", ["flat", "phong"])
def test_alpha_map_sets_the_output_alpha(renderer, frequency):
    """Blending needs the 8-bit target: over a transparent background the output alpha is the
    material's alpha × the map's, which the reference gives unblended."""
    material = Material(diffuse=(0.7, 0.6, 0.5, 0.9), alpha_map=smooth_grey(0.2, 1.0), alpha_mode="blend")
    scene = Scene(objects=(SceneObject(plane(1.5, 2), material),), lights=(DirectionalLight(direction=(0, 0, -1)),),
                  camera=Camera(eye=(0, 0, 2.0)), size=(64, 64), background=(0, 0, 0, 0), shading=Shading(frequency=frequency))
    reference = ref.render_reference(scene)
    gpu = renderer.render_frame(scene, depth=True)
    compared = reference.covered & (reference.edge_margin >= EDGE_BAND)
    alpha = gpu.color[..., 3].astype(np.float64) / 255.0
    assert np.abs(alpha - reference.color[..., 3])[compared].max() <= 2.0 / 255.0
    assert reference.color[..., 3][compared].min() < 0.4  # the map shows


@pytest.mark.parametrize("frequency", ["gouraud", "phong"])
def test_every_map_at_once_in_linear_colour_space_matches_the_reference(renderer, frequency):
    everything = {}
    for name in MAPS:
        everything |= maps(name)
    material = Material(ambient=(0.3, 0.25, 0.2, 1), diffuse=(0.7, 0.6, 0.5, 0.8), specular=(0.6, 0.6, 0.6, 1), shininess=30.0,
                        texture=smooth_texture(), **everything)
    scene = scene_with(material, frequency, color_space="linear")
    scene = replace(scene, objects=scene.objects[2:])  # the torus and cube silhouettes minify the base texture
    gpu, reference = renderer.render_frame(scene, float32=True, depth=True), ref.render_reference(scene)
    if frequency == "phong":
        normal_map_criterion(gpu, reference, f"all maps / {frequency}")
    else:
        compare(gpu, reference, EDGE_BAND, f"all maps / {frequency}")


def test_srgb_helpers_round_trip_and_match_the_standard():
    values = np.linspace(0.0, 1.0, 1001)
    assert np.allclose(srgb_decode(srgb_encode(values)), values, atol=1e-12)
    assert srgb_encode(0.2176) * 255.0 == pytest.approx(128.5, abs=0.1)  # the unlit Blender orange's green
    assert srgb_decode(0.5) == pytest.approx(0.21404, abs=1e-5)
