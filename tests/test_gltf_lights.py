"""KHR_lights_punctual → classic lights (assets/gltf/punctual_lights.py; docs/real-world-files.md,
"File lights"): values computed by hand from the extension's definitions."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gltf_builder import quad, write_gltf
from wgpu_shading import MeshError
from wgpu_shading.assets.gltf.punctual_lights import gltf_lights, spot_exponent
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.scene import DirectionalLight, PositionalLight, SpotLight

_QUARTER_TURN_X = [math.sin(-math.pi / 4), 0.0, 0.0, math.cos(-math.pi / 4)]  # −90° about X: −Z → −Y


def _file(tmp_path, lights, light_nodes, name="l.gltf", roots=None):
    positions, indices = quad(-1, -1, 2)
    nodes = [{"mesh": 0}] + light_nodes
    roots = list(range(len(nodes))) if roots is None else roots
    return write_gltf(tmp_path / name, [[{"positions": positions, "indices": indices, "normals": np.tile([0, 0, 1], (4, 1))}]],
                      nodes=nodes, extra={"extensionsUsed": ["KHR_lights_punctual"], "scenes": [{"nodes": roots}],
                                          "extensions": {"KHR_lights_punctual": {"lights": lights}}})


def test_each_kind_maps_to_its_classic_light_placed_by_its_node(tmp_path):
    lights = [
        {"type": "directional", "color": [1, 0.5, 0.25], "intensity": 2},
        {"type": "point", "intensity": 3, "range": 10},
        {"type": "spot", "intensity": 4, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
    ]
    nodes = [
        {"rotation": _QUARTER_TURN_X, "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"translation": [0, 0, 5], "children": [4]},
        {"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 2}}},
    ]
    placed = [light for light, _ in gltf_lights(_file(tmp_path, lights, nodes, roots=[0, 1, 2, 3]))]
    sun, point, spot = placed
    assert isinstance(sun, DirectionalLight) and np.allclose(sun.direction, [0, -1, 0], atol=1e-9)
    assert np.allclose(sun.diffuse, [2, 1, 0.5, 1]) and sun.specular == sun.diffuse and sun.ambient[:3] == (0, 0, 0)
    assert isinstance(point, PositionalLight) and np.allclose(point.position, [1, 2, 3])
    assert tuple(point.attenuation) == (0.0, 0.0, 1.0) and np.allclose(point.diffuse, [3, 3, 3, 1]) and point.range == 10.0
    assert isinstance(spot, SpotLight) and np.allclose(spot.position, [0, 1, 5]) and np.allclose(spot.direction, [0, 0, -1])
    assert math.isclose(spot.cutoff, math.degrees(0.6))
    assert math.isclose(math.cos(0.4) ** spot.exponent, 0.5)  # half intensity midway between the cones


def test_spot_exponent_of_a_hard_cone_is_zero():
    assert spot_exponent(0.5, 0.5) == 0.0


def test_a_file_with_lights_is_lit_by_them_and_viewer_lights_keeps_ours(tmp_path):
    # A narrow spot light straight down onto the middle of the quad: the middle is lit, a
    # corner (outside the cone) is not; with --viewer-lights the corner is lit too.
    from wgpu_shading.cli.main import main
    from PIL import Image

    lights = [{"type": "spot", "intensity": 1, "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.2}}]
    path = _file(tmp_path, lights, [{"translation": [0, 0, 1], "extensions": {"KHR_lights_punctual": {"light": 0}}}])
    scene = mesh_scene(str(path), (64, 64))
    assert len(scene.lights) == 1 and isinstance(scene.lights[0], SpotLight)
    assert len(mesh_scene(str(path), (64, 64), file_lights=False).lights) == 2
    from wgpu_shading.assets.view_loader import load_view
    from wgpu_shading.scene.view.options import ViewOptions

    assert len(load_view(str(path), ViewOptions(viewer_lights=True)).lights) == 2
    moved = load_view(str(path), ViewOptions(camera_azimuth=30.0))  # the file's lights stay when the camera moves
    assert moved.lights == scene.lights
    for flags, name in (([], "file.png"), (["--viewer-lights"], "viewer.png")):
        assert main(["render", str(path), "-o", str(tmp_path / name), "--size", "64", *flags]) == 0
    file_image = np.asarray(Image.open(tmp_path / "file.png"), dtype=int)
    viewer_image = np.asarray(Image.open(tmp_path / "viewer.png"), dtype=int)
    middle, corner = file_image[32, 32, :3].sum(), file_image[12, 12, :3].sum()
    assert middle > corner + 60
    assert viewer_image[12, 12, :3].sum() > corner + 60


@pytest.mark.parametrize("light, words", [
    ({"type": "laser"}, "lights[0].type"),
    ({"type": "point", "intensity": "bright"}, "lights[0].intensity"),
    ({"type": "point", "color": [1, 1]}, "lights[0].color"),
    ({"type": "spot", "spot": {"outerConeAngle": 3}}, "outerConeAngle"),
    ({"type": "point", "range": -1}, "lights[0].range"),
])
def test_hostile_light_fields_are_one_line_errors(tmp_path, light, words):
    path = _file(tmp_path, [light], [{"extensions": {"KHR_lights_punctual": {"light": 0}}}])
    with pytest.raises(MeshError, match=r"l\.gltf.*" + words.replace("[", r"\[").replace("]", r"\]")):
        gltf_lights(path)


def test_a_light_index_out_of_range_is_an_error(tmp_path):
    path = _file(tmp_path, [{"type": "point"}], [{"extensions": {"KHR_lights_punctual": {"light": 4}}}])
    with pytest.raises(MeshError, match="light"):
        gltf_lights(path)
    document = json.loads(path.read_text())
    document["extensions"]["KHR_lights_punctual"] = {"lights": "many"}
    path.write_text(json.dumps(document))
    with pytest.raises(MeshError, match="KHR_lights_punctual"):
        gltf_lights(path)


@pytest.mark.parametrize("frequency", ["gouraud", "phong"])
def test_range_fades_a_point_light_to_zero_on_the_gpu_as_in_the_reference(renderer, frequency):
    # A point light 1 above the middle of a 4×4 floor with range 1.5: the window
    # clamp(1 − (d/1.5)⁴, 0, 1)² / d² (KHR_lights_punctual) against the float64 reference,
    # and by hand: dark beyond the range, (1 − (1/1.5)⁴)² = 0.6243 straight below.
    from support import EDGE_BAND, compare

    from wgpu_shading.scene import Camera, Material, Scene, SceneObject, Shading, plane
    from wgpu_shading.study import reference as ref

    light = PositionalLight(position=(0.0, 0.0, 1.0), attenuation=(0.0, 0.0, 1.0), range=1.5, specular=(0, 0, 0, 1))
    scene = Scene(
        objects=(SceneObject(plane(4.0, 24), Material(ambient=(0, 0, 0, 1), diffuse=(1, 1, 1, 1))),),
        lights=(light,), ambient=(0.0, 0.0, 0.0, 1.0),
        camera=Camera(eye=(0.0, 0.0, 6.0), target=(0.0, 0.0, 0.0), fov_y=40.0), size=(64, 64),
        shading=Shading(frequency=frequency),
    )
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    compare(gpu, ref.render_reference(scene), EDGE_BAND, f"range / {frequency}")
    if frequency == "phong":
        assert abs(gpu.color[32, 32, 0] - (1 - (1 / 1.5) ** 4) ** 2) < 0.01
        assert gpu.color[32, 4, 0] < 1e-6  # 1.9 from the middle: beyond the range


def test_a_bare_gltf_with_lights_is_parsed_once(tmp_path, monkeypatch):
    """Its meshes and its lights come from one reading of the file (MeshFile.lights); a
    caller who does not want the lights never reads them (a broken light table then fails
    no one)."""
    from wgpu_shading.assets.gltf import document

    lights = [{"type": "point", "intensity": 1}]
    path = _file(tmp_path, lights, [{"translation": [0, 0, 1], "extensions": {"KHR_lights_punctual": {"light": 0}}}])
    reads = []
    original = document.GltfData.__init__
    monkeypatch.setattr(document.GltfData, "__init__", lambda self, *a, **k: (reads.append(a), original(self, *a, **k))[1])
    assert len(mesh_scene(str(path), (32, 32)).lights) == 1
    assert len(reads) == 1
    broken = _file(tmp_path, [{"type": "point", "intensity": "bright"}], [{"extensions": {"KHR_lights_punctual": {"light": 0}}}], "broken.gltf")
    with pytest.raises(MeshError):
        mesh_scene(str(broken), (32, 32))
    assert len(mesh_scene(str(broken), (32, 32), file_lights=False).lights) == 2
