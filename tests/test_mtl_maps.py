"""MTL maps (assets/mesh_formats/mtl.py; docs/real-world-files.md): map_Ks, map_Ns, map_Ke, map_d, norm and
map_Bump/bump told apart by what the image is (normal map, height map, or a photo)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.assets.meshes import load_mesh
from wgpu_shading.scene.maps import classify_bump_image, height_to_normal

OBJ = """mtllib m.mtl
v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
usemtl m
f 1/1 2/2 3/3 4/4
"""


def normal_image() -> np.ndarray:
    rgb = np.full((16, 16, 3), (128, 128, 255), np.uint8)
    rgb[:, 8:] = (200, 128, 230)
    return rgb


def height_image() -> np.ndarray:
    value = np.tile(np.linspace(0, 255, 16).astype(np.uint8), (16, 1))
    return np.repeat(value[:, :, None], 3, axis=2)


def photo_image() -> np.ndarray:
    rng = np.random.default_rng(1)
    return rng.integers(0, 256, (16, 16, 3)).astype(np.uint8)


def material_of(tmp_path, mtl: str, images: dict):
    for name, pixels in images.items():
        Image.fromarray(pixels).save(tmp_path / name)
    (tmp_path / "m.mtl").write_text("newmtl m\nKd 0.8 0.8 0.8\n" + mtl)
    (tmp_path / "q.obj").write_text(OBJ)
    return load_mesh(str(tmp_path / "q.obj")).parts[0].material


def test_classify_bump_images():
    assert classify_bump_image(normal_image()) == "normal"
    assert classify_bump_image(height_image()) == "height"
    assert classify_bump_image(photo_image()) == "other"


def test_map_bump_normal_map_is_used_as_a_normal_map_with_bm(tmp_path):
    material = material_of(tmp_path, "map_Bump -bm 0.5 n.png\n", {"n.png": normal_image()})
    assert material.normal_map is not None and material.normal_scale == 0.5 and material.bump_map is None


def test_bump_height_map_is_a_bump_map(tmp_path):
    material = material_of(tmp_path, "bump -bm 2 h.png\n", {"h.png": height_image()})
    assert material.bump_map is not None and material.bump_scale == 2.0 and material.normal_map is None


def test_a_colour_photo_in_map_bump_is_ignored_with_a_warning(tmp_path):
    with pytest.warns(UserWarning, match="neither a height map"):
        material = material_of(tmp_path, "map_Bump photo.png\n", {"photo.png": photo_image()})
    assert material.bump_map is None and material.normal_map is None


def test_the_other_maps(tmp_path):
    rgba = np.zeros((4, 4, 4), np.uint8)
    rgba[..., 3] = 100
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        material = material_of(
            tmp_path, "Ns 40\nmap_Ks s.png\nmap_Ns ns.png\nmap_Ke e.png\nmap_d d.png\nnorm n.png\n",
            {"s.png": photo_image(), "ns.png": height_image(), "e.png": photo_image(), "d.png": rgba, "n.png": normal_image()},
        )
    assert material.specular[:3] == (1.0, 1.0, 1.0) and material.specular_map is not None  # Ks 1 under map_Ks
    assert material.emission[:3] == (1.0, 1.0, 1.0) and material.emissive_map is not None
    assert material.shininess_map is not None and material.normal_map is not None
    assert material.alpha_mode == "blend" and (material.alpha_map.pixels[..., 0] == 100).all()  # the alpha channel
    assert material.color_space == "display"  # OBJ/MTL keep the OpenGL convention


def test_a_missing_map_image_is_a_warning(tmp_path):
    with pytest.warns(UserWarning, match="not found"):
        material = material_of(tmp_path, "map_Ks nothing.png\n", {})
    assert material.specular_map is None


def test_height_to_normal_by_hand():
    """A ramp rising 1/16 per texel along u in a 16-texel-wide image: ∂h/∂u = 1/16 per texel;
    slope = 1/16 × 16 × BUMP_DEPTH (1/32) × scale 2 = 1/16; n = normalize(−1/16, 0, 1)."""
    ramp = np.tile((np.arange(16) * 16).astype(np.uint8), (16, 1))
    pixels = np.repeat(ramp[:, :, None], 3, axis=2)
    normal = height_to_normal(pixels, 2.0)[8, 8, :3] / 255.0 * 2.0 - 1.0
    expected = np.array([-1 / 16, 0.0, 1.0]) / np.linalg.norm([-1 / 16, 0.0, 1.0])
    assert np.abs(normal - expected).max() < 1.5 / 255 * 2


def test_scene_file_keys_set_maps_on_any_material(tmp_path):
    from wgpu_shading.assets.scenefile import load_scene

    Image.fromarray(normal_image()).save(tmp_path / "n.png")
    Image.fromarray(height_image()).save(tmp_path / "h.png")
    (tmp_path / "s.toml").write_text(
        '[shading]\ncolor_space = "linear"\n'
        '[[objects]]\nmesh = "builtin:cube"\n'
        'material = { base = "gold", normal_map = "n.png", normal_scale = 0.5, occlusion_map = "h.png", '
        'occlusion_strength = 0.7, alpha_map = "h.png" }\n'
    )
    scene = load_scene(str(tmp_path / "s.toml"))
    material = scene.objects[0].material
    assert scene.shading.color_space == "linear"
    assert material.normal_map is not None and material.normal_scale == 0.5 and material.occlusion_strength == 0.7
    assert material.alpha_mode == "blend" and material.alpha_map is not None
    (tmp_path / "bad.toml").write_text('[[objects]]\nmesh = "builtin:cube"\nmaterial = { normal_map = 3 }\n')
    with pytest.raises(Exception, match="normal_map: expected a path"):
        load_scene(str(tmp_path / "bad.toml"))
