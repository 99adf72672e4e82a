"""A glTF file's own cameras (`--camera-index N`, issue 27) against projections worked out by
hand: a small unlit red square at a known place lands on known pixels through a perspective
camera (yfov, znear, zfar or none) and an orthographic one (ymag), placed by a node that is
moved, turned and parented. Out-of-range indices name the count."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from gltf_builder import quad, write_gltf
from wgpu_shading import load_view
from wgpu_shading.scene.view.options import ViewOptions

SIZE = 100
RED = {"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}, "extensions": {"KHR_materials_unlit": {}}}


def _file(tmp_path, cameras, camera_nodes, square_at=(1.0, 0.0, 0.0), extra_nodes=(), width=0.2):
    """A square facing +Z centred at `square_at` (node 0), then `camera_nodes`."""
    positions, indices = quad(square_at[0] - width / 2, square_at[1] - width / 2, width, square_at[2])
    nodes = [{"mesh": 0}, *camera_nodes, *extra_nodes]
    path = write_gltf(tmp_path / "cameras.gltf", [[{"positions": positions, "indices": indices, "material": 0}]],
                      materials=[RED], nodes=nodes,
                      extra={"cameras": cameras, "extensionsUsed": ["KHR_materials_unlit"]})
    document = json.loads(path.read_text())
    document["scenes"] = [{"nodes": [0] + [1 + i for i in range(len(camera_nodes))]}]
    path.write_text(json.dumps(document))
    return path


def _red_centre(path, index, **options):
    scene = load_view(str(path), ViewOptions(size=SIZE, camera_index=index, **options))
    from wgpu_shading import Renderer

    image = Renderer().render_frame(scene).color
    red = (image[..., 0] > 200) & (image[..., 1] < 60)
    assert red.any(), "the square is not in view"
    rows, columns = np.nonzero(red)
    return (columns.mean() + 0.5, rows.mean() + 0.5), red.sum(), scene.camera


PERSPECTIVE = {"type": "perspective", "perspective": {"yfov": math.radians(90), "znear": 0.1, "zfar": 100.0}}


def test_a_perspective_camera_projects_as_its_yfov_says(tmp_path):
    # camera at (0, 0, 5) looking down −Z, 90° vertical field: x = 1 at depth 5 is at
    # NDC 1/5, column (0.2 + 1) / 2 · 100 = 60; the square is 0.2 / 5 · 50 = 2 pixels wide
    path = _file(tmp_path, [PERSPECTIVE], [{"camera": 0, "translation": [0, 0, 5]}])
    (x, y), area, camera = _red_centre(path, 0)
    assert (x, y) == pytest.approx((60.0, 50.0), abs=0.5)
    assert area == pytest.approx(4, abs=2)
    assert camera.fov_y == pytest.approx(90.0) and camera.near == pytest.approx(0.1) and camera.far == pytest.approx(100.0)


def test_an_infinite_perspective_camera_still_draws_what_is_in_front(tmp_path):
    camera = {"type": "perspective", "perspective": {"yfov": math.radians(90), "znear": 0.01}}  # no zfar: infinite
    path = _file(tmp_path, [camera], [{"camera": 0, "translation": [0, 0, 500]}], square_at=(100, 0, 0), width=20.0)
    (x, y), _, placed = _red_centre(path, 0)
    assert (x, y) == pytest.approx((60.0, 50.0), abs=0.5)
    assert placed.far > 500.0


def test_an_orthographic_camera_projects_as_its_ymag_says(tmp_path):
    # ymag 2: the view is 4 high (and 4 wide in a square image); x = 1 is at column 75
    camera = {"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 2.0, "znear": 0.0, "zfar": 10.0}}
    path = _file(tmp_path, [camera], [{"camera": 0, "translation": [0, 0, 5]}], square_at=(1.0, -1.0, 0.0))
    (x, y), area, placed = _red_centre(path, 0)
    assert (x, y) == pytest.approx((75.0, 75.0), abs=0.5)
    assert area == pytest.approx(25, abs=4)  # 0.2 of 4 is 5 pixels
    assert placed.projection == "orthographic" and placed.ortho_height == pytest.approx(4.0)


def test_a_turned_and_parented_camera_node_looks_along_its_minus_z(tmp_path):
    # the camera's node turned +90° about Y looks down −X; its parent puts it at (5, 0, 0).
    # The square, turned the same way, faces it from the origin, 0.5 up.
    half = math.sqrt(0.5)
    camera_nodes = [{"children": [2], "translation": [5, 0, 0]}, {"camera": 0, "rotation": [0, half, 0, half]}]
    path = _file(tmp_path, [PERSPECTIVE], camera_nodes[:1], square_at=(0.0, 0.0, 0.0), extra_nodes=camera_nodes[1:])
    document = json.loads(path.read_text())
    document["nodes"][0]["rotation"] = [0, half, 0, half]  # the square faces +X, towards the camera
    document["nodes"][0]["translation"] = [0, 0.5, 0]  # 0.5 up at distance 5: NDC 0.1, row 45
    path.write_text(json.dumps(document))
    (x, y), _, camera = _red_centre(path, 0)
    assert (x, y) == pytest.approx((50.0, 45.0), abs=0.5)
    np.testing.assert_allclose(camera.eye, [5, 0, 0], atol=1e-9)


def test_the_second_camera_and_an_index_out_of_range(tmp_path, capsys):
    near = {"type": "perspective", "perspective": {"yfov": math.radians(90), "znear": 0.1}}
    path = _file(tmp_path, [PERSPECTIVE, near], [{"camera": 0, "translation": [0, 0, 5]}, {"camera": 1, "translation": [0, 0, 2]}])
    (x, _), _, _ = _red_centre(path, 1)
    assert x == pytest.approx(75.0, abs=0.5)  # x = 1 at depth 2: NDC 1/2
    code, err = run_cli(capsys, "render", str(path), "--camera-index", "2", "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "cameras.gltf", "camera index 2 is out of range: the file has 2 cameras (0..1)")
    code, err = run_cli(capsys, "render", str(path), "--camera-index=-1", "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "--camera-index", "expected an index")


def test_a_camera_no_node_places_is_an_error_naming_it(tmp_path, capsys):
    path = _file(tmp_path, [PERSPECTIVE, PERSPECTIVE], [{"camera": 0, "translation": [0, 0, 5]}])
    code, err = run_cli(capsys, "render", str(path), "--camera-index", "1", "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "cameras[1]", "no node of the scene uses this camera")


def test_camera_options_move_the_files_camera(tmp_path):
    path = _file(tmp_path, [PERSPECTIVE], [{"camera": 0, "translation": [0, 0, 5]}], square_at=(0, 0, 0))
    camera = load_view(str(path), ViewOptions(size=SIZE, camera_index=0, camera_azimuth=90.0)).camera
    np.testing.assert_allclose(camera.eye, [5, 0, 0], atol=1e-9)  # turned about the target, the square's centre
