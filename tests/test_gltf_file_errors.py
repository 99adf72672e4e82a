"""glTF files that cannot be read as meant: one-line MeshErrors naming the file (exit 2 from the
command line), and a warning where a texture is lost (docs/real-world-files.md)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from gltf_builder import quad, write_gltf
from wgpu_shading import MeshError, load_mesh


@pytest.mark.parametrize("text", [b"[]", b"5", b"[" * 100_000 + b"]" * 100_000])
def test_a_gltf_that_is_json_but_not_an_object_is_a_mesh_error(tmp_path, capsys, text):
    path = tmp_path / "odd.gltf"
    path.write_bytes(text)
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "odd.gltf", "not a valid glTF file")


@pytest.mark.parametrize("uri", ["missing.png", "folder", "empty.png"])
def test_a_gltf_texture_that_cannot_be_read_is_a_warning_not_silence(tmp_path, uri):
    # trimesh drops the image without a word: the model came out untextured with exit 0 and
    # no hint, where an OBJ's missing map_Kd warns.
    (tmp_path / "folder").mkdir()
    (tmp_path / "empty.png").write_bytes(b"")
    positions, indices = quad(0, 0)
    uvs = positions[:, :2]
    path = write_gltf(tmp_path / "t.gltf", [[{"positions": positions, "indices": indices, "uvs": uvs, "material": 0}]],
                      materials=[{"name": "skin", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                      extra={"images": [{"uri": uri}], "textures": [{"source": 0}]})
    with pytest.warns(UserWarning, match="t.gltf: material 'skin': its base colour texture could not be read"):
        mesh = load_mesh(path)
    assert mesh.parts[0].material.texture is None


@pytest.mark.parametrize(
    "material, words",
    [
        ({"pbrMetallicRoughness": []}, ["AttributeError"]),
        ({"extensions": []}, ["AttributeError"]),
        ({"extensions": {"KHR_materials_specular": {"specularFactor": "x"}}}, ["ValueError"]),
        ({"emissiveFactor": [1e39, 0, 0]}, ["material.emission", "1e+39"]),
    ],
)
def test_a_hostile_gltf_material_is_a_mesh_error_naming_the_file(tmp_path, capsys, material, words):
    positions, indices = quad(0, 0)
    path = write_gltf(tmp_path / "m.gltf", [[{"positions": positions, "indices": indices, "material": 0}]], materials=[material])
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = one_line_error(code, err, "m.gltf", "material", *words)
    with pytest.raises(MeshError) as error:
        load_mesh(path)
    assert line == f"wgpu-shading: error: {error.value}"


@pytest.mark.parametrize("info, field", [
    ({"index": 0, "extensions": {"KHR_texture_transform": "Not an object"}}, "baseColorTexture.extensions.KHR_texture_transform: expected an object"),
    ({"index": 0, "extensions": ["KHR_texture_transform"]}, "baseColorTexture.extensions: expected an object"),
    ({"index": 0, "extensions": {"KHR_texture_transform": {"texCoord": "x"}}}, "baseColorTexture.extensions.KHR_texture_transform.texCoord must be"),
    ({"index": 0, "texCoord": -1}, "baseColorTexture.texCoord must be a non-negative integer, got -1"),
])
def test_a_bad_texture_info_names_its_field(tmp_path, info, field):
    # assimp's test file glTF2/wrongTypes/badExtension.gltf (a string where the extension's
    # object belongs) was refused with "'str' object has no attribute 'get'".
    from gltf_builder import quad, write_gltf

    positions, faces = quad(0, 0)
    path = write_gltf(tmp_path / "t.gltf", [[{"positions": positions, "indices": faces, "uvs": positions[:, :2], "material": 0}]],
                      materials=[{"pbrMetallicRoughness": {"baseColorTexture": info}}], images=[np.full((2, 2, 4), 255, np.uint8)])
    with pytest.raises(MeshError, match=re.escape(field)) as caught:
        load_mesh(path)
    assert "attribute" not in str(caught.value)
