"""Hostile and out-of-range input (issue 14): each is exit 2 with one line that names the
file, the key and the value; the library raises SceneError/MeshError with the same text;
nothing reaches the GPU that would give inf, NaN or a blank image."""

from __future__ import annotations

import gc
import math
import os
import warnings
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpu_shading import MeshError, Renderer, SceneError, load_mesh, load_scene
from wgpu_shading.cli.main import main
from wgpu_shading.scene import Camera, Material, PositionalLight, Scene, SceneObject, Texture, builtin

SPHERE = '[[objects]]\nmesh = "builtin:sphere?slices=12&stacks=8"\n'

# (file name, contents, the words the one-line message must contain)
SCENE_CASES = [
    ("light_type_list.toml", '[[lights]]\ntype = ["spot"]\n' + SPHERE, ["[[lights]] #1.type", "['spot']"]),
    ("camera_number.toml", "camera = 5\n" + SPHERE, ["[camera]", "expected a table", "5"]),
    ("background_table.toml", "[output]\nbackground = { r = 1 }\n" + SPHERE, ["output.background", "{'r': 1}"]),
    ("nested.toml", SPHERE + "translate = " + "[" * 3000 + "]" * 3000 + "\n", ["nested too deeply"]),
    ("huge_builtin.toml", '[[objects]]\nmesh = "builtin:sphere?slices=100000&stacks=100000"\n', ["builtin:sphere", "19999800000 triangles", "4000000"]),
    ("huge_torus.toml", '[[objects]]\nmesh = "builtin:torus?segments=20000&rings=20000"\n', ["builtin:torus", "at most 4000000"]),
    ("many_lights.toml", SPHERE + '[[lights]]\ntype = "spot"\n' * 700, ["lights", "700 lights", "at most 256"]),
    ("base_number.toml", '[[objects]]\nmesh = "builtin:cube"\nmaterial = { base = 1 }\n', ["[[objects]] #1.material.base", "got 1"]),
    ("near.toml", "[camera]\nnear = 1e-39\n" + SPHERE, ["camera.near", "1e-39"]),
    ("fov.toml", "[camera]\nfov_y = 1e-40\n" + SPHERE, ["camera.fov_y", "1e-40"]),
    ("far_over_near.toml", "[camera]\nnear = 1e-10\nfar = 1e25\n" + SPHERE, ["camera.far / camera.near", "1e+35"]),
    ("up.toml", "[camera]\nup = [1e-300, 0, 0]\n" + SPHERE, ["camera.up", "1e-300"]),
    ("radius.toml", '[[objects]]\nmesh = "builtin:sphere?radius=1e39"\n', ["builtin:sphere", "radius", "1e+39"]),
    ("radius_nan.toml", '[[objects]]\nmesh = "builtin:sphere?radius=nan"\n', ["builtin:sphere", "radius", "nan"]),
    ("cube_negative.toml", '[[objects]]\nmesh = "builtin:cube?size=-1"\n', ["builtin:cube", "size", "-1"]),
    ("light_diffuse.toml", "[[lights]]\ndiffuse = [1e39, 1e39, 1e39]\n" + SPHERE, ["[[lights]] #1", "light.diffuse", "1e+39"]),
    ("light_specular.toml", "[[lights]]\nspecular = [0, 1e39, 0]\n" + SPHERE, ["light.specular", "1e+39"]),
    ("background_huge.toml", "[output]\nbackground = [1e39, 0, 0]\n" + SPHERE, ["output.background", "1e+39"]),
    ("background_two.toml", "[output]\nbackground = [2, 2, 2]\n" + SPHERE, ["output.background", "between 0 and 1", "2.0"]),
    ("scale_tiny.toml", SPHERE + "scale = [1e-30, 1, 1]\n", ["object.scale", "1e-30"]),
    ("attenuation.toml", "[[lights]]\nattenuation = [1, 0, 1e300]\n" + SPHERE, ["light.attenuation", "1e+300"]),
    ("long_number.toml", SPHERE + "translate = [" + "1" * 100_000 + ", 0, 0]\n", ["invalid TOML"]),
    ("long_key.toml", SPHERE + "k" * 1_000_000 + " = 1\n", ["[[objects]] #1: unknown key", "..."]),
    (
        "eye_space.toml",
        '[camera]\neye = [0, 0, 1e15]\n[[objects]]\nmesh = "builtin:sphere?radius=1e6"\nscale = [1e12, 1e12, 1e12]\n',
        ["objects[0]", "1e+18", "float32"],
    ),
]


def _run(capsys, *args: str) -> tuple[int, str]:
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.err


@pytest.mark.parametrize("name, text, words", SCENE_CASES, ids=[case[0] for case in SCENE_CASES])
def test_bad_scene_files_are_one_line_errors_naming_file_key_and_value(tmp_path, capsys, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning may leak either
        code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"), "--size", "16")
        with pytest.raises(SceneError) as error:
            load_scene(path)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and len(lines[0]) < 700, err[:2000]
    assert lines[0] == f"wgpu-shading: error: {error.value}"  # the library's text, verbatim
    assert str(path) in lines[0]
    for word in words:
        assert word in lines[0], lines[0]
    assert not (tmp_path / "out.png").exists()


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


MESH_CASES = [
    ("garbage.stl", lambda: np.random.default_rng(1).bytes(3000), ["garbage.stl", "not a valid STL file"]),
    ("garbage.obj", lambda: np.random.default_rng(2).bytes(3000), ["garbage.obj"]),
    ("garbage.ply", lambda: np.random.default_rng(3).bytes(3000), ["garbage.ply", "not a PLY file"]),
    ("garbage.off", lambda: np.random.default_rng(4).bytes(3000), ["garbage.off"]),
    ("empty.obj", lambda: b"", ["empty.obj", "empty"]),
    (
        "truncated.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 200000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        ["truncated.ply", "200000000 faces"],
    ),
    (
        "short.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 2000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        ["short.ply", "2000 faces", "truncated or damaged"],
    ),
    (
        "missing_face.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        ["missing_face.ply", "truncated", "2 faces"],
    ),
    (  # found by the fuzz test: trimesh reads PLY faces unchecked, normals then failed with IndexError
        "face_out_of_range.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 1\n",
        ["face_out_of_range.ply", "a face refers to vertex 1", "1 vertices"],
    ),
    ("face_out_of_range.stl", lambda: b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid\n", ["face_out_of_range.stl", "NaN or infinite"]),
    ("tiny.obj", lambda: b"v 0 0 0\nv 1e-20 0 0\nv 0 1e-20 0\nf 1 2 3\n", ["tiny.obj", "1.41e-20 units across"]),
    ("huge.obj", lambda: b"v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", ["huge.obj"]),
    ("far.obj", lambda: b"v 1e15 0 0\nv 1e15 1 0\nv 1e15 0 1\nf 1 2 3\n", ["mesh", "far.obj", "automatic camera and lights"]),
]


@pytest.mark.parametrize("name, data, words", MESH_CASES, ids=[case[0] for case in MESH_CASES])
def test_bad_mesh_files_are_one_line_errors(tmp_path, capsys, name, data, words):
    path = _write(tmp_path / name, data())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"), "--size", "16")
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for word in words:
        assert word in lines[0], lines[0]
    if name != "far.obj":
        with pytest.raises(MeshError) as error:
            load_mesh(path)
        assert lines[0] == f"wgpu-shading: error: {error.value}"


def test_a_two_gigabyte_ply_of_zeros_is_refused_from_its_header(tmp_path, capsys):
    path = tmp_path / "zeros.ply"
    with open(path, "wb") as file:
        file.truncate(2_000_000_000)  # sparse: no disk used
    code, err = _run(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    assert code == 2 and "not a PLY file" in err


def test_a_latin1_comment_in_an_obj_loads(tmp_path):
    path = _write(tmp_path / "latin.obj", "# café, naïve\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".encode("latin-1"))
    mesh = load_mesh(path)
    assert mesh.triangle_count == 1 and mesh.vertex_count == 3


def test_a_one_bit_png_texture_is_white_not_black(tmp_path, renderer):
    Image.new("1", (8, 8), 1).save(tmp_path / "white.png")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(
        '[output]\nsize = [32, 32]\n[ambient]\ncolor = [1, 1, 1]\n'
        '[[objects]]\nmesh = "builtin:plane"\nmaterial = { texture = "white.png" }\n'
    )
    scene = load_scene(scene_file)
    assert scene.objects[0].material.texture.pixels.min() == 255
    image = renderer.render(scene)
    assert image[16, 16, :3].tolist() == [255, 255, 255]  # ambient 1 × material 1 × texel 1


def test_a_texture_wider_than_the_limit_is_refused_before_decoding(tmp_path, capsys):
    Image.new("RGB", (16385, 1)).save(tmp_path / "wide.png")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('[[objects]]\nmesh = "builtin:plane"\nmaterial = { texture = "wide.png" }\n')
    code, err = _run(capsys, "render", str(scene_file), "-o", str(tmp_path / "o.png"))
    assert code == 2 and "wide.png" in err and "16385×1 pixels; at most 16384" in err


def test_a_texture_beyond_the_adapters_limit_is_a_scene_error(renderer):
    limit = renderer.device.limits["max-texture-dimension-2d"]
    texture = Texture(np.zeros((1, 8, 3), np.uint8), name="wide")
    object.__setattr__(texture, "pixels", np.zeros((1, limit + 1, 4), np.uint8))  # past the scene's own check
    scene = Scene(objects=(SceneObject(builtin("builtin:plane"), Material(texture=texture)),), size=(8, 8))
    with pytest.raises(SceneError, match=f"texture 'wide': {limit + 1}×1 pixels exceeds this adapter's limit of {limit}"):
        Renderer(device=renderer.device).render(scene)


def test_a_failed_texture_read_leaves_no_open_file(tmp_path):
    """imageio's plugin search left files open (in reference cycles) when none could read one."""
    bad = _write(tmp_path / "bad.png", b"not an image at all")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('[[objects]]\nmesh = "builtin:plane"\nmaterial = { texture = "bad.png" }\n')
    def open_on_bad_file() -> int:
        count = 0
        for fd in os.listdir("/proc/self/fd"):
            try:
                count += os.readlink(f"/proc/self/fd/{fd}") == str(bad)
            except OSError:  # closed meanwhile (another thread's file)
                pass
        return count

    gc.collect()
    gc.disable()  # cycles are not collected: what is open now stays open
    try:
        for _ in range(10):
            with pytest.raises(SceneError, match="bad.png"):
                load_scene(scene_file)
        still_open = open_on_bad_file()
    finally:
        gc.enable()
    assert still_open == 0
    assert bad.exists()


def test_turntable_degrees_must_be_finite(tmp_path, capsys):
    code, err = _run(capsys, "turntable", "builtin:sphere", "--degrees", "inf", "--frames", "2", "-o", str(tmp_path / "t.gif"))
    assert code == 2 and "--degrees" in err and "inf" in err


def test_library_constructors_raise_the_same_checks():
    with pytest.raises(SceneError, match=r"camera.near: expected at least 1e-20"):
        Camera(near=1e-39)
    with pytest.raises(SceneError, match=r"light.diffuse: color components must be at most"):
        PositionalLight(diffuse=(1e39, 0, 0))
    with pytest.raises(SceneError, match=r"lights: expected a list"):
        Scene(lights=5)
    with pytest.raises(SceneError, match=r"object.mesh: expected a Mesh, got str"):
        SceneObject("builtin:cube")
    with pytest.raises(MeshError, match=r"builtin:cube needs size"):
        builtin("builtin:cube?size=-1")
    with pytest.raises(SceneError, match="material: expected a material name"):
        from wgpu_shading import material

        material(1)
    from wgpu_shading import DeviceError, Mesh

    with pytest.raises(DeviceError, match="device: expected a wgpu.GPUDevice, got int"):
        Renderer(device=5)
    with pytest.raises(DeviceError, match="adapter: expected a selector"):
        Renderer(adapter=5)
    with pytest.raises(SceneError, match="load_scene: expected a path to a scene file, got NoneType"):
        load_scene(None)
    with pytest.raises(MeshError, match="positions must be numbers"):
        Mesh.from_arrays("abc", [[0, 1, 2]])


def test_a_huge_but_accepted_light_is_not_darker_than_a_normal_one(renderer):
    """Before: diffuse 1e39 became inf in float32, and inf × 0 darkened hundreds of pixels.
    At the limit (1e6) every lit pixel saturates and none goes dark."""
    mesh = builtin("builtin:sphere?slices=24&stacks=12")
    def image(diffuse):
        scene = Scene(
            objects=(SceneObject(mesh, Material(specular=(1, 1, 1, 1), shininess=20)),),
            lights=(PositionalLight(diffuse=diffuse, specular=diffuse),),
            size=(48, 48),
        )
        return renderer.render(scene, float32=True)
    normal, huge = image((1, 1, 1, 1)), image((1e6, 1e6, 1e6, 1))
    assert np.isfinite(huge).all()
    assert (huge[..., :3] >= normal[..., :3] - 1e-6).all()


@pytest.mark.parametrize("fps", ["1e-300", "0", "nan", "1e300"])
def test_turntable_fps_out_of_range_is_a_clear_error(tmp_path, capsys, fps):
    code, err = _run(capsys, "turntable", "builtin:cube", "--fps", fps, "--frames", "1", "-o", str(tmp_path / "t.gif"))
    assert code == 2 and "--fps must be between 0.01 and 1000 frames per second" in err


def test_inf_that_slips_past_validation_never_reaches_a_shader(renderer):
    """The net under validation: a value forced in afterwards (frozen dataclasses can be
    bypassed) is refused at upload, naming the object."""
    material = Material()
    object.__setattr__(material, "diffuse", (math.inf, 0.0, 0.0, 1.0))
    scene = Scene(objects=(SceneObject(builtin("builtin:cube"), material),), lights=(PositionalLight(),), size=(8, 8))
    with pytest.raises(SceneError, match=r"objects\[0\]: a value derived from it .* is not finite in float32"):
        Renderer(device=renderer.device).render(scene)


def test_a_nul_character_in_an_argument_is_a_clear_error(tmp_path, capsys):
    code, err = _run(capsys, "render", "scene\x00.toml", "-o", str(tmp_path / "o.png"))
    assert code == 2 and err.strip() == "wgpu-shading: error: input 'scene\\x00.toml' contains a NUL character"
    code, err = _run(capsys, "render", "builtin:cube", "-o", "o\x00.png")
    assert code == 2 and "--output 'o\\x00.png' contains a NUL character" in err


def test_batch_views_beyond_the_limit_fail_before_anything_is_listed(tmp_path, capsys):
    code, err = _run(capsys, "batch", "-o", str(tmp_path / "ds"), "--meshes", "builtin:cube", "--views", "100000000000")
    assert code == 2 and "views: expected 1 to 100000 views per mesh, got 100000000000" in err


def test_a_texture_header_claiming_a_huge_image_is_refused_before_decoding(tmp_path):
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", 30000, 30000, 8, 2, 0, 0, 0)  # 30000² RGB, and no pixel data at all
    path = _write(tmp_path / "bomb.png", b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IEND", b""))
    from wgpu_shading.assets.textures import load_texture

    with pytest.raises(SceneError, match=r"bomb.png': too large .*at most 16384 pixels per side"):
        load_texture(path)
