"""Scene files (docs/scene-files.md): every key of the contract is read, and every mistake is an error
that names the file, the table and the key."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import DirectionalLight, PositionalLight, SceneError, SpotLight, load_scene
from wgpu_shading.scene import material

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

FULL = """
[output]
size = [320, 200]
background = [0.1, 0.2, 0.3]

[shading]
frequency = "gouraud"
reflection = "blinn-phong"
blinn_exponent_scale = 3.0
local_viewer = false
two_sided = true

[camera]
eye = [1.0, 2.0, 3.0]
target = [0.0, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov_y = 50.0
near = 0.5
far = 50.0

[ambient]
color = [0.6, 0.6, 0.6, 1.0]

[[lights]]
type = "directional"
direction = [0.0, 0.0, -1.0]
ambient = [0.1, 0.0, 0.0, 1.0]
diffuse = [1.0, 0.0, 0.0, 1.0]
specular = [1.0, 0.0, 0.0, 1.0]

[[lights]]
type = "positional"
position = [5.0, 2.0, -3.0]
attenuation = [1.0, 0.1, 0.01]

[[lights]]
type = "spot"
position = [5.0, 2.0, -3.0]
direction = [0.0, 0.0, -1.0]
cutoff = 20.0
exponent = 10.0

[[objects]]
mesh = "builtin:torus"
material = "pewter"
translate = [0.0, 0.0, -1.0]
rotate = [35.0, 0.0, 0.0]
scale = [1.0, 2.0, 1.0]

[[objects]]
mesh = "builtin:sphere?slices=12&stacks=6"
material = { base = "gold", emission = [0.3, 0.2, 0.2], shininess = 20.0 }
"""


def write(tmp_path: Path, text: str, name: str = "scene.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_every_contract_key_is_read(tmp_path):
    scene = load_scene(write(tmp_path, FULL))
    assert scene.size == (320, 200)
    assert scene.background == (0.1, 0.2, 0.3, 1.0)  # RGB accepted, alpha 1
    shading = scene.shading
    assert (shading.frequency, shading.reflection, shading.blinn_exponent_scale) == ("gouraud", "blinn-phong", 3.0)
    assert shading.local_viewer is False and shading.two_sided is True
    camera = scene.camera
    assert (camera.eye, camera.target, camera.fov_y, camera.near, camera.far) == ((1, 2, 3), (0, 0.5, 0), 50, 0.5, 50)
    assert scene.ambient == (0.6, 0.6, 0.6, 1.0)
    directional, positional, spot = scene.lights
    assert isinstance(directional, DirectionalLight) and directional.ambient == (0.1, 0, 0, 1)
    assert isinstance(positional, PositionalLight) and positional.attenuation == (1.0, 0.1, 0.01)
    assert isinstance(spot, SpotLight) and (spot.cutoff, spot.exponent) == (20.0, 10.0)
    torus, sphere = scene.objects
    assert torus.material == material("pewter")
    assert (torus.translate, torus.rotate, torus.scale) == ((0, 0, -1), (35, 0, 0), (1, 2, 1))
    assert sphere.mesh.triangle_count == 2 * 12 * 5
    assert sphere.material.diffuse == material("gold").diffuse
    assert sphere.material.emission == (0.3, 0.2, 0.2, 1.0) and sphere.material.shininess == 20.0


def test_defaults_follow_opengl(tmp_path):
    scene = load_scene(write(tmp_path, '[[objects]]\nmesh = "builtin:cube"\n'))
    assert scene.ambient == (0.2, 0.2, 0.2, 1.0)  # GL_LIGHT_MODEL_AMBIENT
    m = scene.objects[0].surface_material  # no material given: OpenGL's default
    assert (m.ambient, m.diffuse, m.specular, m.shininess) == ((0.2, 0.2, 0.2, 1), (0.8, 0.8, 0.8, 1), (0, 0, 0, 1), 0.0)
    assert scene.shading.frequency == "phong" and scene.shading.local_viewer is True
    assert scene.size == (512, 512)


def test_rotation_is_x_then_y_then_z(tmp_path):
    scene = load_scene(write(tmp_path, '[[objects]]\nmesh = "builtin:cube"\nrotate = [90.0, 90.0, 0.0]\n'))
    model = scene.objects[0].world_from_model()
    # X first takes +Y to +Z, then Y takes +Z to +X.
    np.testing.assert_allclose(model[:3, :3] @ [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize(
    "text, message",
    [
        ("[output]\nsize = [0, 10]\n", "output.size: width and height must be between 1 and 16384"),
        ("[output]\nsize = [100000, 100000]\n", "output.size"),
        ("[shading]\nfrequency = \"smooth\"\n", "shading.frequency: expected one of 'flat', 'gouraud', 'phong'"),
        ("[shading]\nfrequncy = \"flat\"\n", "[shading]: unknown key 'frequncy'; did you mean 'frequency'?"),
        ("[camera]\neye = [0.0, 0.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n", "eye [0.0, 0.0, 0.0] and target [0.0, 0.0, 0.0] coincide"),
        ("[camera]\nup = [0.0, 0.0, 1.0]\n", "camera.up [0.0, 0.0, 1.0] is parallel to the view direction"),
        ("[camera]\nnear = 10.0\nfar = 1.0\n", "camera.far (1) must be greater than camera.near (10)"),
        ("[[lights]]\ntype = \"spot\"\ncutoff = 120.0\n", "[[lights]] #1: light.cutoff: expected a number in [0, 90], got 120"),
        ("[[lights]]\ntype = \"laser\"\n", "[[lights]] #1.type: expected one of"),
        ("[[lights]]\ntype = \"directional\"\nposition = [1.0, 2.0, 3.0]\n", "unknown key 'position' for a directional light"),
        ("[[lights]]\nattenuation = [0.0, 0.0, 0.0]\n", "(0, 0, 0) divides by zero"),
        ("[[lights]]\ndifuse = [1.0, 1.0, 1.0]\n", "unknown key 'difuse'; did you mean 'diffuse'?"),
        ("[[lights]]\ndiffuse = [1.0, \"red\", 1.0]\n", "light.diffuse: expected numbers, got 'red'"),
        ("[[lights]]\ndiffuse = [1.0, -1.0, 1.0]\n", "light.diffuse: color components must be >= 0"),
        ("[[lights]]\nposition = [1.0, nan, 0.0]\n", "light.position: expected finite numbers"),
        ("[[objects]]\nmaterial = \"gold\"\n", "[[objects]] #1: missing key 'mesh'"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = \"unobtainium\"\n", "unknown material 'unobtainium'"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = \"gld\"\n", "did you mean 'gold'?"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nscale = [1.0, 0.0, 1.0]\n", "object.scale: components must be non-zero"),
        ("[[objects]]\nmesh = \"nothing.obj\"\n", "[[objects]] #1.mesh: mesh file"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = { shinyness = 3.0 }\n", "unknown key 'shinyness'; did you mean 'shininess'?"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = { texture = \"missing.png\" }\n", "texture"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = { texture_mode = \"multiply\" }\n", "texture_mode: expected one of"),
        ("[camra]\n", "scene: unknown key 'camra'; did you mean 'camera'?"),
        ("[output\n", "invalid TOML"),
    ],
)
def test_mistakes_name_the_file_and_key(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(SceneError) as error:
        load_scene(path)
    assert str(error.value).startswith(str(path)), error.value
    assert message in str(error.value)


def test_missing_scene_file():
    with pytest.raises(SceneError, match="scene file 'nowhere.toml' not found"):
        load_scene("nowhere.toml")


def test_paths_are_relative_to_the_scene_file(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = load_scene(write(tmp_path / "sub", '[[objects]]\nmesh = "tri.obj"\n'))
    assert scene.objects[0].mesh.triangle_count == 1


SHARED_MODELS = EXAMPLES.parent.parent / "shared" / "models"


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_load(path):
    if "shared/models" in path.read_text() and not SHARED_MODELS.is_dir():
        pytest.skip("needs the model collection in ../shared/models (not part of the repository)")
    scene = load_scene(path)
    assert scene.objects, f"{path.name} draws nothing"
    assert all(math.isfinite(v) for light in scene.lights for v in light.diffuse)
