"""Scene values are validated wherever they come from (scene files, the library's
constructors): a bad one is exit 2 with one line naming the file, the key and the value, and
the library raises SceneError with the same text; what passes stays finite on the GPU (no
inf, NaN or blank image)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from wgpu_shading import MeshError, Renderer, SceneError, load_scene
from wgpu_shading.scene import Camera, Material, PositionalLight, Scene, SceneObject, builtin


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


@pytest.mark.parametrize("name, text, words", SCENE_CASES, ids=[case[0] for case in SCENE_CASES])
def test_bad_scene_files_are_one_line_errors_naming_file_key_and_value(tmp_path, capsys, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning may leak either
        code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"), "--size", "16")
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


@pytest.mark.parametrize("text", ["", "objects = []\n", "[camera]\nfov_y = 40\n"])
def test_a_scene_file_without_objects_is_an_error_not_a_black_image(tmp_path, capsys, text):
    # An empty (or truncated) scene file rendered the background alone with exit 0.
    path = tmp_path / "nothing.toml"
    path.write_text(text)
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = one_line_error(code, err, "nothing.toml", "[[objects]]")
    with pytest.raises(SceneError) as error:
        load_scene(path)
    assert line == f"wgpu-shading: error: {error.value}"
    assert not (tmp_path / "out.png").exists()


def test_samples_written_as_a_float_is_the_whole_number(tmp_path, capsys):
    # `samples = 4.0` passed validation (4.0 in (1, 4)) and then reached wgpu as a float:
    # "TypeError: an integer is required", exit 3.
    assert Scene(samples=4.0).samples == 4 and type(Scene(samples=4.0).samples) is int
    assert type(Scene(samples=np.int64(1)).samples) is int
    with pytest.raises(SceneError, match="output.samples"):
        Scene(samples=4.5)
    path = tmp_path / "s.toml"
    path.write_text('[output]\nsamples = 4.0\nsize = [16, 16]\n[[objects]]\nmesh = "builtin:cube"\n')
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"), "-q")
    assert code == 0, err


def test_a_tiny_ortho_height_is_refused_by_the_camera_not_the_uniform_net(tmp_path, capsys):
    # 1e-300 passed (0, 1e15]: the projection overflowed float32, a numpy warning leaked
    # and the error blamed "camera and lights" without the key.
    path = tmp_path / "ortho.toml"
    path.write_text('[camera]\nprojection = "orthographic"\northo_height = 1e-300\n[[objects]]\nmesh = "builtin:cube"\n')
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = one_line_error(code, err, str(path), "camera.ortho_height", "1e-300")
    with pytest.raises(SceneError) as error:
        load_scene(path)
    assert line == f"wgpu-shading: error: {error.value}"


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


def test_inf_that_slips_past_validation_never_reaches_a_shader(renderer):
    """The net under validation: a value forced in afterwards (frozen dataclasses can be
    bypassed) is refused at upload, naming the object."""
    material = Material()
    object.__setattr__(material, "diffuse", (math.inf, 0.0, 0.0, 1.0))
    scene = Scene(objects=(SceneObject(builtin("builtin:cube"), material),), lights=(PositionalLight(),), size=(8, 8))
    with pytest.raises(SceneError, match=r"objects\[0\]: a value derived from it .* is not finite in float32"):
        Renderer(device=renderer.device).render(scene)
