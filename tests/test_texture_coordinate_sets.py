"""Every texture reads its own texture coordinates (issue 27, docs/primitives.md#texture-coordinate-sets):
glTF's `texCoord` (TEXCOORD_0..n), overridden by KHR_texture_transform's `texCoord`, with its
own transform; the binding plan carries another set's vertex buffer only where a texture
reads it.

The closed form: a square filling pixels 8..55 of a 64 × 64 image (orthographic, one unit
per pixel) with a 2 × 2 NEAREST texture (red, green / blue, white). TEXCOORD_0 shows it
upright; TEXCOORD_1 is mirrored left to right (u' = 1 − u), so a texture on TEXCOORD_1 shows
green, red / white, blue. Each check has a control that reads TEXCOORD_0 and must fail it
(the way Khronos' MultiUVTest shows an emissive texture on TEXCOORD_1)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gltf_builder import write_gltf
from wgpu_shading import MeshError, load_mesh
from wgpu_shading.render.features import object_features
from wgpu_shading.render.shaders.bindings import binding_plan
from wgpu_shading.scene import Camera, Material, Mesh, Scene, SceneObject, Shading, Texture

SIZE = 64
CAMERA = Camera(eye=(0.0, 0.0, 10.0), projection="orthographic", ortho_height=float(SIZE), near=1.0, far=20.0)
TEXELS = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 255]]], np.uint8)
UPRIGHT = {(16, 16): (255, 0, 0), (16, 48): (0, 255, 0), (48, 16): (0, 0, 255), (48, 48): (255, 255, 255)}  # (row, column)
MIRRORED = {(16, 16): (0, 255, 0), (16, 48): (255, 0, 0), (48, 16): (255, 255, 255), (48, 48): (0, 0, 255)}


def _square(path: Path, material: dict) -> Path:
    positions = np.array([[-24, -24, 0], [24, -24, 0], [24, 24, 0], [-24, 24, 0]], np.float32)
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)  # glTF's v runs down the image
    mirrored = uvs * [-1, 1] + [1, 0]
    primitive = {"positions": positions, "indices": [[0, 1, 2], [0, 2, 3]], "normals": np.tile([0, 0, 1], (4, 1)),
                 "uvs": uvs, "uvs1": mirrored, "material": 0}
    return write_gltf(path, [[primitive]], [material], images=[TEXELS], samplers=[{"magFilter": 9728, "minFilter": 9728}],
                      textures=[{"source": 0, "sampler": 0}], extra={"extensionsUsed": ["KHR_materials_unlit", "KHR_texture_transform"]})


def _pixels(renderer, path: Path) -> np.ndarray:
    mesh = load_mesh(path)
    return renderer.render(Scene(objects=(SceneObject(mesh),), camera=CAMERA, size=(SIZE, SIZE), ambient=(0.0, 0.0, 0.0, 1.0)))


def _shows(image: np.ndarray, expected: dict) -> bool:
    return all(np.abs(image[r, c, :3].astype(int) - colour).max() <= 2 for (r, c), colour in expected.items())


BASE_ON_SET_1 = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}, "extensions": {"KHR_materials_unlit": {}}}
EMISSIVE_ON_SET_1 = {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                     "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0, "texCoord": 1}}
# Khronos' MultiUVTest layout: the base colour texture on TEXCOORD_0, the emissive one on
# TEXCOORD_1 (here black base colour and no light: the pixels are the emissive texels).
MULTI_UV = {**EMISSIVE_ON_SET_1, "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}}
OVERRIDE_TO_SET_1 = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 0, "extensions": {"KHR_texture_transform": {"texCoord": 1}}}},
                     "extensions": {"KHR_materials_unlit": {}}}


@pytest.mark.parametrize("material", [BASE_ON_SET_1, EMISSIVE_ON_SET_1, MULTI_UV, OVERRIDE_TO_SET_1],
                         ids=["base colour", "emissive", "multi uv", "transform override"])
def test_a_texture_reads_the_set_its_texcoord_names_and_the_control_reading_set_0_fails(renderer, tmp_path, material):
    image = _pixels(renderer, _square(tmp_path / "set1.gltf", material))
    assert _shows(image, MIRRORED), {k: image[k][:3].tolist() for k in MIRRORED}
    control = json.loads(json.dumps(material).replace('"texCoord": 1', '"texCoord": 0'))
    control_image = _pixels(renderer, _square(tmp_path / "set0.gltf", control))
    assert _shows(control_image, UPRIGHT) and not _shows(control_image, MIRRORED)


def test_only_a_draw_that_reads_another_set_binds_its_vertex_buffer(renderer, tmp_path):
    """The base colour texture's coordinates are the mesh's uvs whatever set they are; an
    emissive texture on another set needs that set's buffer, and only then."""
    for material, extra in ((MULTI_UV, {"uv_set_1"}), (json.loads(json.dumps(MULTI_UV).replace('"texCoord": 1', '"texCoord": 0')), set()),
                            (BASE_ON_SET_1, set())):
        mesh = load_mesh(_square(tmp_path / "s.gltf", material))
        scene = Scene(objects=(SceneObject(mesh),), camera=CAMERA, size=(SIZE, SIZE))
        features = object_features(scene, scene.objects[0], 0, mesh.parts[0].material)
        names = {buffer.name for buffer in binding_plan(features).vertex_buffers}
        assert {name for name in names if name.startswith("uv_set_")} == extra
        renderer.render(scene)
        assert (renderer.device_cache.gpu_mesh(mesh).uv_set_1 is not None) == bool(extra)


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_maps_on_another_set_draw_what_they_draw_on_set_0_at_every_frequency(renderer, frequency):
    """A checker occlusion map and a gradient base colour texture read set 1 and set 2 of a
    mesh whose uvs are something else; the same textures on set 0 of a mesh whose uvs are
    those sets draw the same pixels, byte for byte (flat shading pulls them from storage
    buffers, Gouraud reads the occlusion map per vertex, Phong per fragment)."""
    from wgpu_shading.scene import DirectionalLight, builtin

    sphere = builtin("builtin:sphere?slices=24&stacks=12")
    rng = np.random.default_rng(3)
    scrambled = rng.random((sphere.vertex_count, 2))
    checker = np.kron(np.indices((4, 4)).sum(axis=0) % 2, np.ones((8, 8)))[:, :, None].repeat(3, 2) * 200 + 40
    gradient = np.stack([*np.meshgrid(np.linspace(0, 255, 16), np.linspace(255, 0, 16)), np.full((16, 16), 128.0)], axis=2)
    occlusion, base = checker.astype(np.uint8), gradient.astype(np.uint8)

    def draw(uvs, extra, occlusion_set, base_set):
        mesh = Mesh.from_arrays(sphere.positions, sphere.indices, sphere.normals, uvs, extra_uvs=extra)
        material = Material(ambient=(0.6, 0.6, 0.6, 1.0), texture=Texture(base, uv_set=base_set), occlusion_map=Texture(occlusion, uv_set=occlusion_set))
        scene = Scene(objects=(SceneObject(mesh, material),), lights=(DirectionalLight(direction=(-0.3, -0.2, -1.0)),),
                      shading=Shading(frequency=frequency), size=(48, 48), ambient=(0.5, 0.5, 0.5, 1.0))
        return renderer.render(scene)

    sets = np.stack([sphere.uvs[:, ::-1], sphere.uvs * [2.0, 1.0]], axis=1)  # set 1: u and v swapped; set 2: u doubled
    on_other_sets = draw(scrambled, sets, 1, 2)
    assert np.array_equal(on_other_sets, draw(sets[:, 0], sets, 0, 2))  # the occlusion map's set as the uvs
    assert np.array_equal(on_other_sets, draw(sets[:, 1], sets, 1, 0))  # the base colour's set as the uvs
    assert not np.array_equal(on_other_sets, draw(scrambled, sets, 0, 0))  # control: both on the scrambled uvs


def test_a_set_the_primitive_lacks_or_one_too_many_is_left_out_with_a_warning(tmp_path):
    missing = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 5}}}
    with pytest.warns(UserWarning, match="reads a TEXCOORD set the primitive does not have"):
        mesh = load_mesh(_square(tmp_path / "missing.gltf", missing))
    assert mesh.parts[0].material.texture is None
    transforms = [{"offset": [0.1 * k, 0.0]} for k in range(6)]
    names = ["normalTexture", "occlusionTexture", "emissiveTexture"]
    five = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": transforms[0]}},
                                     "metallicRoughnessTexture": {"index": 0, "extensions": {"KHR_texture_transform": transforms[1]}}},
            "emissiveFactor": [1, 1, 1],
            **{name: {"index": 0, "extensions": {"KHR_texture_transform": transforms[2 + k]}} for k, name in enumerate(names)}}
    with pytest.warns(UserWarning, match="drawn without it"):
        mesh = load_mesh(_square(tmp_path / "five.gltf", five))
    material = mesh.parts[0].material
    assert mesh.extra_uvs.shape[1] == 3  # four channels: the base colour's and three more
    assert sorted(t.uv_set for t in [material.texture, *material.maps.values()]) == [0, 1, 1, 2, 3]  # (specular and shininess share one)
    assert material.emissive_map is None  # the fifth transform


def test_texture_uv_set_is_checked(tmp_path):
    from wgpu_shading import SceneError

    with pytest.raises(SceneError, match="uv_set"):
        Texture(TEXELS, uv_set=4)
    mesh = Mesh.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], uvs=[[0, 0], [1, 0], [0, 1]])
    scene = Scene(objects=(SceneObject(mesh, Material(texture=Texture(TEXELS, uv_set=1))),))
    with pytest.raises(SceneError, match="texture coordinate set 1"):
        object_features(scene, scene.objects[0])
    with pytest.raises(MeshError, match="extra_uvs"):
        Mesh.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], extra_uvs=np.zeros((2, 1, 2)))
