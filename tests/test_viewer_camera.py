"""The camera a viewer's user expects (docs/conventions.md#projection-pixels-and-depth): orthographic projection, automatic framing
from the up axis (f3d's --up), f3d's camera flags and the scene-file keys behind them.

Orthographic images are checked against what parallel projection must give (exact sizes,
independence from distance), not against another path of the same code."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading import Camera, DirectionalLight, Scene, SceneObject, load_mesh, material
from wgpu_shading.assets import parse_scene
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.cli import main
from wgpu_shading.cli.main import build_parser
from wgpu_shading.cli.arguments import scene_from_args
from wgpu_shading.errors import SceneError
from wgpu_shading.scene.view.reading import parse_direction

SIZE = (160, 120)


def _sphere_scene(distance: float, camera_changes: dict) -> Scene:
    camera = Camera(eye=(0.0, 0.0, distance), near=distance - 2.0, far=distance + 2.0, **camera_changes)
    return Scene(
        objects=(SceneObject(load_mesh("builtin:sphere?slices=256&stacks=128"), material("white_plastic")),),
        lights=(DirectionalLight(direction=(0.0, 0.0, -1.0)),),
        camera=camera,
        size=SIZE,
    )


def test_orthographic_sphere_has_the_exact_size_at_any_distance(renderer):
    masks = []
    for distance in (3.0, 40.0):
        frame = renderer.render_frame(_sphere_scene(distance, dict(projection="orthographic", ortho_height=3.0)), depth=True)
        covered = np.isfinite(frame.depth)
        # A unit sphere under parallel projection is a disc of radius 1 world unit = 40 pixels.
        area = covered.sum()
        assert abs(area - math.pi * 40.0**2) < 2 * math.pi * 40.0, area  # within a one-pixel rim
        rows, columns = np.nonzero(covered)
        assert rows.min() == 20 and rows.max() == 99 and columns.min() == 40 and columns.max() == 119
        # Depth is the eye-space distance along the view axis: near the sphere's front point,
        # distance − 1 (the pixel centre is half a pixel, 1/80 unit, off the axis: +1.6e-4).
        assert frame.depth[60, 80] == pytest.approx(distance - 1.0 + 1.6e-4, abs=2e-4)
        masks.append(covered)
    assert np.array_equal(masks[0], masks[1])  # parallel projection: distance changes nothing


def test_perspective_sphere_grows_when_near_but_orthographic_does_not(renderer):
    near = renderer.render_frame(_sphere_scene(3.0, {}), depth=True)
    far = renderer.render_frame(_sphere_scene(40.0, {}), depth=True)
    assert np.isfinite(near.depth).sum() > 10 * np.isfinite(far.depth).sum()


def test_switching_to_orthographic_keeps_the_framing_at_the_target(renderer):
    # A square at the target's distance, facing the camera, covers the same pixels in both
    # projections: the default ortho_height is the perspective view's height there.
    square = SceneObject(load_mesh("builtin:plane?size=1.6"), material("white_plastic"))  # faces +Z
    scene = Scene(objects=(square,), lights=(DirectionalLight(),), camera=Camera(eye=(0.0, 0.0, 4.0)), size=SIZE)
    ortho = replace(scene, camera=replace(scene.camera, projection="orthographic"))
    assert ortho.camera.view_height() == pytest.approx(2 * 4.0 * math.tan(math.radians(22.5)))
    perspective_mask = np.isfinite(renderer.render_frame(scene, depth=True).depth)
    ortho_mask = np.isfinite(renderer.render_frame(ortho, depth=True).depth)
    assert perspective_mask.sum() > 1000
    assert np.sum(perspective_mask != ortho_mask) <= 4  # rounding at the edges only


def _eye_in_file_space(scene):
    """The camera's eye and up in the mesh file's own coordinates (before --up turned it)."""
    model = scene.objects[0].world_from_model()
    origin = np.asarray(scene.objects[0].mesh.origin)
    inverse = np.linalg.inv(model)
    eye = inverse @ np.append(scene.camera.eye, 1.0)
    up = inverse[:3, :3] @ np.asarray(scene.camera.up)
    centre = (inverse @ np.append(scene.camera.target, 1.0))[:3]
    return eye[:3] + origin - (centre + origin), up


def test_bare_mesh_framing_follows_the_up_axis_as_f3d():
    # f3d: +Y up (default) views from +Z looking along -Z; --up +Z views from -Y with +Z up.
    # Here the mesh is turned instead of the camera: in the file's coordinates, the same view.
    y_offset, y_up = _eye_in_file_space(mesh_scene("example:gear.ply", (64, 64), None))
    z_offset, z_up = _eye_in_file_space(mesh_scene("example:gear.ply", (64, 64), None, up="+Z"))
    assert y_up == pytest.approx((0, 1, 0)) and y_offset[2] > 2 * abs(y_offset[1]) > 0
    assert z_up == pytest.approx((0, 0, 1)) and -z_offset[1] > 2 * abs(z_offset[2]) > 0
    assert abs(y_offset[0]) < 1e-9 and abs(z_offset[0]) < 1e-9


@pytest.mark.parametrize("text, expected", [("+Z", (0, 0, 1)), ("-x", (-1, 0, 0)), ("Y", (0, 1, 0)), ("0,0,2", (0, 0, 2))])
def test_direction_spellings(text, expected):
    assert parse_direction(text) == pytest.approx(expected)


def test_azimuth_and_elevation_turn_as_vtk():
    camera = Camera(eye=(0.0, 0.0, 3.0))
    assert camera.orbited(azimuth=90).eye == pytest.approx((3.0, 0.0, 0.0))  # to the camera's right
    raised = camera.orbited(elevation=90)
    assert raised.eye == pytest.approx((0.0, 3.0, 0.0)) and raised.up == pytest.approx((0.0, 0.0, -1.0))


def _args(*argv: str):
    return build_parser().parse_args(["render", *argv])


def test_camera_flags_set_the_camera_and_match_the_scene_file_keys(tmp_path):
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('[[objects]]\nmesh = "builtin:torus"\n')
    flagged = scene_from_args(_args(
        str(scene_file), "--camera-position", "1,2,5", "--camera-focal-point", "0,0.5,0", "--camera-view-up", "+Y",
        "--camera-view-angle", "30", "--camera-azimuth-angle", "20", "--camera-elevation-angle", "10",
        "--camera-orthographic",
    )).camera
    keyed = parse_scene({
        "camera": {"eye": [1, 2, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y": 30, "azimuth": 20,
                   "elevation": 10, "projection": "orthographic"},
        "objects": [{"mesh": "builtin:torus"}],
    }).camera
    assert flagged == keyed
    assert flagged.projection == "orthographic" and flagged.fov_y == 30
    height = scene_from_args(_args(str(scene_file), "--camera-ortho-height", "2.5")).camera
    assert height.projection == "orthographic" and height.view_height() == 2.5


def test_moving_a_bare_mesh_camera_keeps_the_mesh_inside_the_depth_range():
    scene = scene_from_args(_args("builtin:torus", "--camera-position", "0,0,40"))
    assert scene.camera.near < 40 - 1 and scene.camera.far > 40 + 1
    # The default lights follow the camera: the headlight travels along the view direction.
    assert scene.lights[1].direction == pytest.approx((0.0, 0.0, -1.0))


@pytest.mark.parametrize(
    "argv, message",
    [
        (["builtin:torus", "--camera-view-up", "+W"], "expected +X, -X"),
        (["builtin:torus", "--camera-position", "0,0"], "expected 3 numbers"),
        (["builtin:torus", "--camera-position", "0,0,0", "--camera-focal-point", "0,0,0"], "coincide"),
        (["builtin:torus", "--camera-view-angle", "0"], "camera.fov_y"),
        (["builtin:torus", "--camera-ortho-height", "-1"], "camera.ortho_height"),
    ],
)
def test_bad_camera_flags_are_one_line_errors(argv, message, tmp_path, capsys):
    try:
        status = main(["render", *argv, "-o", str(tmp_path / "x.png")])
    except SystemExit as exit_:  # argparse's own type errors
        status = exit_.code
    assert status == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_the_float64_reference_draws_orthographic_cameras_as_the_gpu_does(renderer, frequency):
    """The reference derives glOrtho itself (window = NDC of x / half width, depth affine on
    screen): the same coverage, colour and depth as the GPU, off-axis and tilted."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from support import EDGE_BAND, compare
    from wgpu_shading.scene import Shading
    from wgpu_shading.study.reference import render_reference

    scene = replace(
        _sphere_scene(3.0, dict(projection="orthographic", ortho_height=2.6)),
        camera=Camera(eye=(0.7, 1.1, 3.0), target=(0.2, 0.1, 0.0), up=(0.2, 1.0, 0.0), near=0.5, far=8.0,
                      projection="orthographic", ortho_height=2.6),
        objects=(SceneObject(load_mesh("builtin:sphere?slices=24&stacks=12"), material("gold"), rotate=(20, 30, 0)),),
        lights=(DirectionalLight(direction=(-0.3, -0.5, -1.0)),),
        shading=Shading(frequency=frequency),
    )
    compare(renderer.render_frame(scene, float32=True, depth=True), render_reference(scene), EDGE_BAND, f"orthographic {frequency}")


def test_analytic_shapes_refuse_orthographic_cameras():
    from wgpu_shading.study.reference import render_analytic_sphere

    with pytest.raises(SceneError, match="orthographic"):
        render_analytic_sphere(_sphere_scene(3.0, dict(projection="orthographic")), (0, 0, 0), 1.0, material("gold"))


def test_resolution_is_f3ds_name_for_size():
    assert scene_from_args(_args("builtin:torus", "--resolution", "300,200")).size == (300, 200)
    assert scene_from_args(_args("builtin:torus", "--size", "300x200")).size == (300, 200)


def test_camera_direction_keeps_the_distance_and_yields_to_position(tmp_path):
    base = scene_from_args(_args("builtin:torus")).camera
    distance = np.linalg.norm(np.subtract(base.eye, base.target))
    looking_down = scene_from_args(_args("builtin:torus", "--camera-direction=-Y", "--camera-view-up=-Z")).camera
    assert np.subtract(looking_down.eye, looking_down.target) == pytest.approx((0.0, distance, 0.0))
    placed = scene_from_args(_args("builtin:torus", "--camera-direction=-Y", "--camera-position", "0,0,7")).camera
    assert placed.eye == (0.0, 0.0, 7.0)


def test_azimuth_and_elevation_without_the_angle_suffix():
    short = scene_from_args(_args("builtin:torus", "--camera-azimuth", "30", "--camera-elevation", "10")).camera
    long = scene_from_args(_args("builtin:torus", "--camera-azimuth-angle", "30", "--camera-elevation-angle", "10")).camera
    assert short == long and short != scene_from_args(_args("builtin:torus")).camera


def test_ortho_height_without_orthographic_projection_is_an_error():
    with pytest.raises(SceneError, match='camera.ortho_height .* needs projection = "orthographic"'):
        parse_scene({"camera": {"ortho_height": 2.0}})
    assert parse_scene({"camera": {"ortho_height": 2.0, "projection": "orthographic"}}).camera.view_height() == 2.0
