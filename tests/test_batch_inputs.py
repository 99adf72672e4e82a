"""A second round of hostile input, found by trying what tests/test_hostile_inputs.py and
tests/test_fuzz.py do not: each was a traceback (exit 3), a silent wrong result or a
blank image with exit 0. Every one must be exit 2 with one line naming the file or key
(or, where the input is legitimate, the right result)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, SceneError, load_mesh, load_scene
from wgpu_shading.errors import UsageError
from wgpu_shading.cli.main import main
from wgpu_shading.dataset import read_manifest
from wgpu_shading.scene import Scene


def _run(capsys, *args: str) -> tuple[int, str]:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning may leak onto stderr
        code = main(list(args))
    return code, capsys.readouterr().err


def _one_line(code: int, err: str, *words: str) -> str:
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


def test_samples_written_as_a_float_is_the_whole_number(tmp_path, capsys):
    # `samples = 4.0` passed validation (4.0 in (1, 4)) and then reached wgpu as a float:
    # "TypeError: an integer is required", exit 3.
    assert Scene(samples=4.0).samples == 4 and type(Scene(samples=4.0).samples) is int
    assert type(Scene(samples=np.int64(1)).samples) is int
    with pytest.raises(SceneError, match="output.samples"):
        Scene(samples=4.5)
    path = tmp_path / "s.toml"
    path.write_text('[output]\nsamples = 4.0\nsize = [16, 16]\n[[objects]]\nmesh = "builtin:cube"\n')
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"), "-q")
    assert code == 0, err


def test_a_tiny_ortho_height_is_refused_by_the_camera_not_the_uniform_net(tmp_path, capsys):
    # 1e-300 passed (0, 1e15]: the projection overflowed float32, a numpy warning leaked
    # and the error blamed "camera and lights" without the key.
    path = tmp_path / "ortho.toml"
    path.write_text('[camera]\nprojection = "orthographic"\northo_height = 1e-300\n[[objects]]\nmesh = "builtin:cube"\n')
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = _one_line(code, err, str(path), "camera.ortho_height", "1e-300")
    with pytest.raises(SceneError) as error:
        load_scene(path)
    assert line == f"wgpu-shading: error: {error.value}"


def test_a_mesh_whose_triangles_have_no_area_is_an_error_not_a_blank_image(tmp_path, capsys):
    path = tmp_path / "collinear.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = _one_line(code, err, "collinear.obj", "area")
    with pytest.raises(MeshError) as error:
        load_mesh(path)
    assert line == f"wgpu-shading: error: {error.value}"


@pytest.mark.parametrize("text", [b"[]", b"5", b"[" * 100_000 + b"]" * 100_000])
def test_a_gltf_that_is_json_but_not_an_object_is_a_mesh_error(tmp_path, capsys, text):
    path = tmp_path / "odd.gltf"
    path.write_bytes(text)
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    _one_line(code, err, "odd.gltf", "not a valid glTF file")


def test_depth_and_colour_to_the_same_file_is_refused(tmp_path, capsys):
    # Before, the depth PNG silently replaced the colour image (exit 0).
    out = str(tmp_path / "same.png")
    code, err = _run(capsys, "render", "builtin:cube", "--size", "16", "-o", out, "--depth", out)
    _one_line(code, err, "--depth", "same.png", "same file")
    assert not Path(out).exists()


@pytest.mark.parametrize(
    "name, data, words",
    [
        ("latin1.csv", b"mesh,name\nbuiltin:cube,caf\xe9\n", ["latin1.csv", "UTF-8"]),
        ("utf16.csv", "mesh,azimuth\nbuiltin:cube,0\n".encode("utf-16"), ["utf16.csv", "UTF-8"]),
        ("deep.jsonl", b'{"mesh": "builtin:cube", "eye": ' + b"[" * 100_000 + b"]" * 100_000 + b"}\n", ["deep.jsonl", "line 1", "nested too deeply"]),
        ("twice.csv", b"mesh,azimuth,mesh\nbuiltin:cube,0,builtin:sphere\n", ["twice.csv", "column 'mesh'", "twice"]),
        ("cells.csv", b"mesh,azimuth\nbuiltin:cube,0,5,6\n", ["cells.csv", "line 2", "4 cells", "2 columns"]),
    ],
)
def test_bad_manifests_are_one_line_errors(tmp_path, capsys, name, data, words):
    path = tmp_path / name
    path.write_bytes(data)
    code, err = _run(capsys, "batch", str(path), "-o", str(tmp_path / "ds"), "-q")
    line = _one_line(code, err, *words)
    with pytest.raises(UsageError) as error:  # a manifest is how the work is asked for, not a scene
        read_manifest(path)
    assert line == f"wgpu-shading: error: {error.value}"


def test_a_csv_manifest_with_a_byte_order_mark_reads_its_first_column(tmp_path):
    # Spreadsheets save "CSV UTF-8" with a BOM: the first column was '\ufeffmesh', unknown.
    path = tmp_path / "excel.csv"
    path.write_bytes("\ufeffmesh,azimuth\nbuiltin:cube,30\n".encode("utf-8"))
    (job,) = read_manifest(path)
    assert job.source == "builtin:cube"


@pytest.mark.parametrize(
    "row, words",
    [
        ("material\nbuiltin:cube,unobtainium", ["line 2", "unknown material 'unobtainium'"]),
        ("frequency\nbuiltin:cube,foo", ["line 2", "frequency", "'foo'"]),
        ("reflection\nbuiltin:cube,lambert", ["line 2", "reflection", "'lambert'"]),
        ("projection\nbuiltin:cube,fisheye", ["line 2", "projection", "'fisheye'"]),
        ("distance\nbuiltin:cube,-1", ["line 2", "distance", "-1"]),
        ("distance\nbuiltin:cube,0", ["line 2", "distance", "0"]),
    ],
)
def test_a_bad_manifest_value_is_bad_input_before_anything_renders(tmp_path, capsys, row, words):
    # These were found only when the job ran: exit 1 ("1 job(s) failed") after the rest of
    # the dataset had rendered, though the documented status for bad input is 2.
    path = tmp_path / "jobs.csv"
    path.write_text("mesh," + row + "\n")
    code, err = _run(capsys, "batch", str(path), "-o", str(tmp_path / "ds"), "-q", "--size", "8")
    _one_line(code, err, "jobs.csv", *words)
    assert not (tmp_path / "ds" / "cube").exists()


def test_a_json_boolean_is_not_an_angle(tmp_path):
    path = tmp_path / "jobs.jsonl"
    path.write_text('{"mesh": "builtin:cube", "azimuth": true}\n')
    with pytest.raises(UsageError, match="azimuth: expected a number, got True"):
        read_manifest(path)


@pytest.mark.parametrize("text", ["", "objects = []\n", "[camera]\nfov_y = 40\n"])
def test_a_scene_file_without_objects_is_an_error_not_a_black_image(tmp_path, capsys, text):
    # An empty (or truncated) scene file rendered the background alone with exit 0.
    path = tmp_path / "nothing.toml"
    path.write_text(text)
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = _one_line(code, err, "nothing.toml", "[[objects]]")
    with pytest.raises(SceneError) as error:
        load_scene(path)
    assert line == f"wgpu-shading: error: {error.value}"
    assert not (tmp_path / "out.png").exists()


def test_an_mtllib_that_is_a_folder_is_skipped_like_a_missing_one(tmp_path, capsys):
    # It raised IsADirectoryError's "[Errno 21] Is a directory: '...'", naming neither the
    # OBJ nor the material library.
    (tmp_path / "sub").mkdir()
    path = tmp_path / "m.obj"
    path.write_bytes(b"mtllib sub\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.warns(UserWarning, match="material library 'sub'"):
        mesh = load_mesh(path)
    assert len(mesh.indices) == 1


def test_an_unreadable_texture_message_has_no_memory_address(tmp_path, capsys):
    (tmp_path / "zero.png").write_bytes(b"")
    path = tmp_path / "t.toml"
    path.write_text('[[objects]]\nmesh = "builtin:cube"\nmaterial = { texture = "zero.png" }\n')
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = _one_line(code, err, "zero.png", "not an image Pillow can read")
    assert "0x" not in line and "BytesIO" not in line, line


@pytest.mark.parametrize("spec", ["directional:dir=1,1,1:dir=0,0,1", "positional:pos=1,1,1:position=2,2,2"])
def test_a_light_key_given_twice_is_an_error(tmp_path, capsys, spec):
    code, err = _run(capsys, "render", "builtin:cube", "--light", spec, "-o", str(tmp_path / "out.png"))
    _one_line(code, err, "--light", "given twice")


def test_a_malformed_scheduler_address_is_bad_input(tmp_path, capsys):
    pytest.importorskip("distributed")
    # Dask's ValueError ("missing port number in address") ended as exit 3.
    code, err = _run(capsys, "batch", "--meshes", "builtin:cube", "--views", "1", "--size", "8",
                     "-o", str(tmp_path / "ds"), "-q", "--scheduler", "garbage")
    _one_line(code, err, "--scheduler 'garbage'", "cannot connect")


@pytest.mark.parametrize("uri", ["missing.png", "folder", "empty.png"])
def test_a_gltf_texture_that_cannot_be_read_is_a_warning_not_silence(tmp_path, uri):
    # trimesh drops the image without a word: the model came out untextured with exit 0 and
    # no hint, where an OBJ's missing map_Kd warns.
    from gltf_builder import quad, write_gltf

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
    from gltf_builder import quad, write_gltf

    positions, indices = quad(0, 0)
    path = write_gltf(tmp_path / "m.gltf", [[{"positions": positions, "indices": indices, "material": 0}]], materials=[material])
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = _one_line(code, err, "m.gltf", "material", *words)
    with pytest.raises(MeshError) as error:
        load_mesh(path)
    assert line == f"wgpu-shading: error: {error.value}"


def test_an_obj_with_classic_mac_line_endings_loads(tmp_path):
    path = tmp_path / "cr.obj"
    path.write_bytes(b"v 0 0 0\rv 1 0 0\rv 0 1 0\rv 1 1 0\rf 1 2 3\rf 2 4 3\r")
    mesh = load_mesh(path)
    assert len(mesh.indices) == 2 and len(mesh.positions) >= 4


def test_an_unknown_builtin_in_batch_is_bad_input(tmp_path, capsys):
    # It was a failed job (exit 1) after the other meshes had rendered.
    code, err = _run(capsys, "batch", "--meshes", "builtin:cube", "--meshes", "builtin:sphre", "--views", "1",
                     "--size", "8", "-o", str(tmp_path / "ds"), "-q")
    _one_line(code, err, "unknown built-in mesh 'builtin:sphre'", "builtin:sphere")
    assert not (tmp_path / "ds" / "cube").exists()
