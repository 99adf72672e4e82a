"""The per-texel maps a glTF metallic-roughness texture becomes (docs/real-world-files.md: a
specular map, a shininess map and the base colour texture × the diffuse factor) are
computed a block of texel rows at a time (assets/gltf/materials.py): the same bytes as the
whole-image computation written out here from the formulas, with float64 temporaries of a
block only (docs/reliability.md#peak-memory-of-a-textured-gltf)."""

from __future__ import annotations

import tracemalloc
from types import SimpleNamespace

import numpy as np
from PIL import Image

from wgpu_shading.assets.gltf import materials
from wgpu_shading.assets.gltf.materials import gltf_material, shininess_of
from wgpu_shading.scene.maps import srgb_decode, srgb_encode

ROW = {"material": {"pbrMetallicRoughness": {
    "baseColorFactor": [0.8, 0.6, 0.4, 1.0], "metallicFactor": 0.9, "roughnessFactor": 0.7,
    "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}}}}


def _images(height: int, width: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray, SimpleNamespace]:
    rng = np.random.default_rng(seed)
    colour, packed = (rng.integers(0, 256, (height, width, 4), np.uint8) for _ in range(2))
    return colour, packed, SimpleNamespace(baseColorTexture=Image.fromarray(colour, "RGBA"),
                                           metallicRoughnessTexture=Image.fromarray(packed, "RGBA"))


def test_the_maps_are_the_whole_image_formulas_byte_for_byte(monkeypatch):
    monkeypatch.setattr(materials, "_BLOCK_ROWS", 16)  # 100 rows: six blocks and a part
    colour, packed, images = _images(100, 37)
    material = gltf_material({}, ROW, images, "m", [])
    base = np.array([0.8, 0.6, 0.4])
    metallic, roughness = 0.9 * (packed[:, :, 2] / 255.0), 0.7 * (packed[:, :, 1] / 255.0)  # glTF §3.9.2: B metal, G rough
    share = metallic * (1.0 - roughness**2)
    specular = 0.04 * (1.0 - metallic)[:, :, None] + base * share[:, :, None]
    top = np.maximum(specular.reshape(-1, 3).max(axis=0), 1e-6)
    shininess = shininess_of(roughness)
    as_bytes = lambda values: np.round(np.clip(values, 0.0, 1.0) * 255.0).astype(np.uint8)  # noqa: E731
    np.testing.assert_array_equal(material.specular_map.pixels[:, :, :3], as_bytes(specular / top))
    np.testing.assert_array_equal(material.shininess_map.pixels[:, :, :3], np.repeat(as_bytes(shininess / shininess.max())[:, :, None], 3, 2))
    assert (material.specular_map.pixels[:, :, 3] == 255).all() and material.shininess == shininess.max()
    np.testing.assert_allclose(material.specular[:3], top)
    expected_colour = as_bytes(srgb_encode(srgb_decode(colour[:, :, :3] / 255.0) * (1.0 - share)[:, :, None]))
    np.testing.assert_array_equal(material.texture.pixels[:, :, :3], expected_colour)
    np.testing.assert_array_equal(material.texture.pixels[:, :, 3], colour[:, :, 3])


def test_a_large_texture_costs_a_few_bytes_a_texel_not_a_float64_image_of_each_step():
    """1024² textures: the computation peaked at 172 bytes a texel (float64 images of every
    intermediate step), now at ~40 (the four 8-bit results, the float64 diffuse factor, a
    block's temporaries)."""
    _, _, images = _images(1024, 1024)
    tracemalloc.start()
    try:
        gltf_material({}, ROW, images, "m", [])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak / (1024 * 1024) < 64, f"{peak / (1024 * 1024):.0f} bytes a texel"
