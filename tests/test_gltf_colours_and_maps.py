"""glTF colours and maps as glTF viewers show them (docs/real-world-files.md, "glTF materials"):
linear factors with sRGB-encoded output, the default material, rough metals, and every map
(normal, emissive, occlusion, metallic-roughness) read from small files built here."""

from __future__ import annotations

import numpy as np
import pytest

from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.assets.meshes import load_mesh
from wgpu_shading.scene import Camera, DirectionalLight, Scene, SceneObject, Shading

from gltf_builder import quad, write_gltf
from test_file_parts import _checker, head_on, pixel


def square(**extra) -> dict:
    positions, indices = quad(-1.0, -1.0, 2.0)
    uvs = (positions[:, :2] + 1.0) / 2.0
    return {"positions": positions, "indices": indices, "normals": np.tile([0.0, 0.0, 1.0], (4, 1)), "uvs": uvs} | extra


def facing_scene(path, lights=None, **shading) -> Scene:
    """The file's square filling the view, lit head-on (or by `lights`)."""
    mesh = load_mesh(str(path))
    lights = lights if lights is not None else (DirectionalLight(direction=(0, 0, -1), diffuse=(1, 1, 1, 1), specular=(0, 0, 0, 1)),)
    return Scene(objects=(SceneObject(mesh),), lights=lights, ambient=(0, 0, 0, 1), camera=Camera(eye=(0, 0, 2.0), fov_y=40.0),
                 size=(48, 48), shading=Shading(**shading))


def test_the_unlit_blender_orange_is_255_128_0(renderer, tmp_path):
    material = {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.2176, 0.0, 1.0]}, "extensions": {"KHR_materials_unlit": {}}}
    path = write_gltf(tmp_path / "orange.gltf", [[square(material=0)]], materials=[material], extra={"extensionsUsed": ["KHR_materials_unlit"]})
    image = renderer.render(mesh_scene(str(path), (64, 64), None))
    centre = image[32, 32, :3].astype(int)
    assert np.abs(centre - [255, 128, 0]).max() <= 1, centre
    # --color-space display (the OpenGL convention) writes the factor as it is: (255, 55, 0).
    scene = mesh_scene(str(path), (64, 64), None)
    from dataclasses import replace

    display = renderer.render(replace(scene, shading=replace(scene.shading, color_space="display")))
    assert np.abs(display[32, 32, :3].astype(int) - [255, 55, 0]).max() <= 1


def test_a_primitive_without_material_is_the_glTF_default_an_even_grey(renderer, tmp_path):
    path = write_gltf(tmp_path / "plain.gltf", [[square()]])
    mesh = load_mesh(str(path))
    material = mesh.parts[0].material
    assert material is not None and material.color_space == "linear"
    assert material.diffuse[:3] == (1.0, 1.0, 1.0) and max(material.specular[:3]) == 0.0
    image = renderer.render(facing_scene(path))[8:40, 8:40, :3].astype(int)
    # White lit head-on by a white light: 255, grey and even (not gold, no hot spot).
    assert (image.max(axis=2) - image.min(axis=2)).max() <= 1 and image.min() >= 250


def test_rough_metal_is_an_even_grey_not_black_with_a_hot_spot(renderer, tmp_path):
    rough = {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0]}}  # metallic 1, roughness 1 by default
    path = write_gltf(tmp_path / "metal.gltf", [[square(material=0)]], materials=[rough])
    light = DirectionalLight(direction=(-0.3, -0.2, -1.0), diffuse=(1, 1, 1, 1), specular=(1, 1, 1, 1))
    image = renderer.render(facing_scene(path, lights=(light,)))[10:38, 10:38, :3].astype(float)
    # diffuse = base (s = 0): linear 0.5 × cos ≈ 0.46, encoded ≈ 181; the same everywhere.
    assert 165 < image.mean() < 195 and image.max() - image.min() <= 2


def _write_textured(tmp_path, name: str, material: dict, image: np.ndarray):
    return write_gltf(tmp_path / f"{name}.gltf", [[square(material=0)]], materials=[material], images=[image])


def test_emissive_texture_is_a_map_not_its_mean_colour(renderer, tmp_path):
    pixels = np.zeros((8, 8, 3), np.uint8)
    pixels[:, 4:] = 255  # right half glows
    material = {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                "emissiveFactor": [1.0, 0.5, 0.0], "emissiveTexture": {"index": 0}}
    image = renderer.render(facing_scene(_write_textured(tmp_path, "glow", material, pixels), lights=()))
    left, right = image[24, 12, :3].astype(int), image[24, 36, :3].astype(int)
    assert left.max() <= 1
    assert np.abs(right - [255, 188, 0]).max() <= 1  # linear (1, 0.5, 0) encoded


def test_normal_texture_turns_the_shading(renderer, tmp_path):
    pixels = np.zeros((8, 8, 3), np.uint8)
    pixels[:, :4] = [128, 128, 255]  # left: straight up
    pixels[:, 4:] = [round((0.6 + 1) / 2 * 255), 128, round((0.8 + 1) / 2 * 255)]  # right: tilted to +x
    material = {"pbrMetallicRoughness": {"metallicFactor": 0.0}, "normalTexture": {"index": 0, "scale": 1.0}}
    path = _write_textured(tmp_path, "normals", material, pixels)
    assert load_mesh(str(path)).parts[0].material.normal_map is not None
    light = DirectionalLight(direction=(-1, 0, 0), diffuse=(1, 1, 1, 1), specular=(0, 0, 0, 1))  # grazing, from +x
    image = renderer.render(facing_scene(path, lights=(light,), color_space="display"), float32=True)
    assert image[24, 12, 0] < 0.02  # the flat half faces away from a grazing light
    assert image[24, 36, 0] == pytest.approx(0.6, abs=0.02)  # N·L = 0.6 × diffuse 1 (a dielectric: diffuse = base)


def test_occlusion_texture_darkens_the_ambient_only(renderer, tmp_path):
    pixels = np.full((8, 8, 3), 255, np.uint8)
    pixels[:, :4] = 0  # left fully occluded
    material = {"pbrMetallicRoughness": {"metallicFactor": 0.0}, "occlusionTexture": {"index": 0, "strength": 0.5}}
    path = _write_textured(tmp_path, "occlusion", material, pixels)
    scene = facing_scene(path, lights=(), color_space="display")
    from dataclasses import replace

    image = renderer.render(replace(scene, ambient=(0.5, 0.5, 0.5, 1)), float32=True)
    assert image[24, 36, 0] == pytest.approx(0.5, abs=0.01)
    assert image[24, 12, 0] == pytest.approx(0.25, abs=0.01)  # 1 + 0.5·(0 − 1) = 0.5 of the ambient


def test_metallic_roughness_texture_applies_per_texel(renderer, tmp_path):
    pixels = np.zeros((8, 8, 3), np.uint8)
    pixels[:, :4] = [0, 255, 0]  # left: dielectric, rough
    pixels[:, 4:] = [0, 60, 255]  # right: metal, smooth
    material = {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicRoughnessTexture": {"index": 0}}}
    path = _write_textured(tmp_path, "mr", material, pixels)
    loaded = load_mesh(str(path)).parts[0].material
    assert loaded.specular_map is not None and loaded.shininess_map is not None
    light = DirectionalLight(direction=(0, 0, -1), diffuse=(0, 0, 0, 1), specular=(1, 1, 1, 1))  # highlight only
    image = renderer.render(facing_scene(path, lights=(light,), color_space="display", local_viewer=False), float32=True)
    # R·V = 1 everywhere (infinite viewer): the highlight is the texel's specular colour,
    # 0.04 for the dielectric, 0.8 · (1 − 0.235²) for the smooth metal.
    assert image[24, 12, 0] == pytest.approx(0.04, abs=0.01)
    assert image[24, 36, 0] == pytest.approx(0.8 * (1 - (60 / 255) ** 2), abs=0.01)


def test_a_bare_gltf_gets_the_viewer_lights_in_linear_light_unless_its_materials_are_replaced(tmp_path):
    from wgpu_shading.assets.view_loader import load_view
    from wgpu_shading.scene.maps import srgb_decode
    from wgpu_shading.scene.view.options import ViewOptions
    from wgpu_shading.scene.view.bare_mesh import KEY_DIFFUSE

    path = write_gltf(tmp_path / "plain.gltf", [[square()]])
    for options in (ViewOptions(), ViewOptions(camera_position=(0.0, 0.0, 5.0))):  # the lights follow the camera
        scene = load_view(str(path), options)
        assert scene.lights[0].diffuse[0] == pytest.approx(srgb_decode(KEY_DIFFUSE[0]))
        assert scene.ambient[0] == pytest.approx(srgb_decode(0.2))
    gold = load_view(str(path), ViewOptions(material="gold"))  # a classic material: display values
    assert gold.lights[0].diffuse[0] == pytest.approx(KEY_DIFFUSE[0]) and gold.ambient[0] == pytest.approx(0.2)


def test_khr_materials_specular_textures_colour_the_highlight_per_texel(renderer, tmp_path):
    pixels = np.zeros((8, 8, 3), np.uint8)
    pixels[:, :4] = (255, 0, 0)
    pixels[:, 4:] = (0, 0, 255)
    material = {"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.3},
                "extensions": {"KHR_materials_specular": {"specularColorFactor": [10, 10, 10], "specularColorTexture": {"index": 0}}}}
    path = _write_textured(tmp_path, "specular", material, pixels)
    loaded = load_mesh(str(path)).parts[0].material
    assert loaded.specular_map is not None
    light = DirectionalLight(direction=(0, 0, -1), diffuse=(0, 0, 0, 1), specular=(1, 1, 1, 1))
    image = renderer.render(facing_scene(path, lights=(light,), color_space="display", local_viewer=False), float32=True)
    # f0 = min(0.04 · 10 · texel, 1): 0.4 red on the left, 0.4 blue on the right, R·V = 1.
    np.testing.assert_allclose(image[24, 12, :3], [0.4, 0, 0], atol=0.01)
    np.testing.assert_allclose(image[24, 36, :3], [0, 0, 0.4], atol=0.01)


def test_extension_textures_are_read_from_a_glb_binary_chunk(tmp_path):
    """A GLB keeps its images in bufferViews of the binary chunk (document_image reads them)."""
    import base64
    import json
    import struct

    pixels = np.full((4, 4, 3), (0, 255, 0), np.uint8)
    material = {"pbrMetallicRoughness": {"metallicFactor": 0.0},
                "extensions": {"KHR_materials_specular": {"specularColorTexture": {"index": 0}}}}
    document = json.loads(_write_textured(tmp_path, "s", material, pixels).read_text())
    blob = base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1])
    png = base64.b64decode(document["images"][0]["uri"].split(",", 1)[1])
    blob += b"\0" * (-len(blob) % 4)
    document["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(png)})
    blob += png + b"\0" * (-len(png) % 4)
    document["images"] = [{"bufferView": len(document["bufferViews"]) - 1, "mimeType": "image/png"}]
    document["buffers"] = [{"byteLength": len(blob)}]
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    glb = b"glTF" + struct.pack("<II", 2, 12 + 8 + len(text) + 8 + len(blob))
    glb += struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(blob)) + b"BIN\0" + blob
    (tmp_path / "s.glb").write_bytes(glb)
    loaded = load_mesh(str(tmp_path / "s.glb")).parts[0].material
    assert loaded.specular_map is not None
    assert loaded.specular[1] == pytest.approx(0.04) and loaded.specular[0] == pytest.approx(0.0, abs=1e-5)


def _as_glb(gltf_path, glb_path):
    """The same document as a GLB (JSON chunk only; the buffers stay data URIs)."""
    import struct

    text = gltf_path.read_bytes()
    text += b" " * (-len(text) % 4)
    glb_path.write_bytes(b"glTF" + struct.pack("<II", 2, 20 + len(text)) + struct.pack("<I", len(text)) + b"JSON" + text)
    return glb_path


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_gltf_specular_glossiness_shows_the_diffuse_texture(tmp_path, renderer, suffix):
    """KHR_materials_pbrSpecularGlossiness (older Sketchfab/3ds Max exports; assimp's
    BoxTextured-glTF-pbrSpecularGlossiness): trimesh bakes the specular color into a new base
    color texture, which rendered the box grey and washed out where f3d shows the diffuse
    texture. Under a white head-on light with no specular part, each texel shows as it is."""
    positions, indices = quad(-1.0, -0.5, 1.0)
    path = write_gltf(
        tmp_path / "sg.gltf",
        meshes=[[{"positions": positions * [2, 1, 1], "indices": indices, "normals": np.tile(np.float32([0, 0, 1]), (4, 1)),
                  "uvs": np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32), "material": 0}]],
        materials=[{"extensions": {"KHR_materials_pbrSpecularGlossiness": {
            "diffuseTexture": {"index": 0}, "specularFactor": [0.2, 0.3, 0.4], "glossinessFactor": 0.5}}}],
        images=[_checker()], samplers=[{"magFilter": 9728, "minFilter": 9728}], textures=[{"source": 0, "sampler": 0}],
        extra={"extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"]},
    )
    if suffix == ".glb":
        path = _as_glb(path, tmp_path / "sg.glb")
    material = load_mesh(path).parts[0].material
    assert material.specular[:3] == pytest.approx((0.2, 0.3, 0.4)) and material.diffuse[:3] == (1.0, 1.0, 1.0)
    assert material.shininess == pytest.approx((2 / 0.25**2 - 2) / 4)  # roughness 1 − 0.5, the metallic-roughness rule
    assert material.texture is not None and material.texture.nearest
    image = renderer.render(head_on([SceneObject(load_mesh(path))], size=(128, 64)))  # a light without specular
    # the checker's texels exactly (test_gltf_textured_and_untextured_parts_with_instanced_nodes's layout)
    assert tuple(pixel(image, -1.5, 0.25)[:3]) == (0, 0, 255) and tuple(pixel(image, -0.5, 0.25)[:3]) == (255, 255, 0)


def test_gltf_texture_transform_moves_the_uvs(tmp_path, renderer):
    """KHR_texture_transform (assimp's TextureTransformTest.gltf showed its own "not
    supported" tiles; f3d applies it). A 2×2 texture of four colors on two quads, nearest
    sampling: an offset of half the texture in u (left quad) or in glTF's v, which runs down
    the image (right quad), shows the neighbouring texel. Without a transform the quads'
    upper-left quarter shows the image's lower-left texel (blue)."""
    pixels = np.zeros((2, 2, 4), np.uint8)
    pixels[0, 0], pixels[0, 1], pixels[1, 0], pixels[1, 1] = (255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255), (255, 255, 255, 255)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    left, indices = quad(-1.75, -0.5)
    right, _ = quad(0.25, -0.5)

    def material(offset):
        return {"pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {
            "index": 0, "extensions": {"KHR_texture_transform": {"offset": offset}}}}}

    path = write_gltf(
        tmp_path / "tt.gltf",
        meshes=[[{"positions": left, "indices": indices, "normals": normals, "uvs": uvs, "material": 0}],
                [{"positions": right, "indices": indices, "normals": normals, "uvs": uvs, "material": 1}]],
        materials=[material([0.5, 0.0]), material([0.0, 0.5])],
        images=[pixels], samplers=[{"magFilter": 9728, "minFilter": 9728}], textures=[{"source": 0, "sampler": 0}],
        extra={"extensionsUsed": ["KHR_texture_transform"]},
    )
    image = renderer.render(head_on([SceneObject(load_mesh(path))], size=(128, 64)))
    assert tuple(pixel(image, -1.5, 0.25)[:3]) == (255, 255, 255)  # u + 0.5: the lower-right texel
    assert tuple(pixel(image, -1.5, -0.25)[:3]) == (0, 255, 0)  # the upper-right one
    assert tuple(pixel(image, 0.5, 0.25)[:3]) == (255, 0, 0)  # v + 0.5: the upper-left texel
    assert tuple(pixel(image, 0.5, -0.25)[:3]) == (0, 0, 255)  # the lower-left one
