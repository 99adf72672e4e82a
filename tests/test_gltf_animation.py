"""glTF animations at a chosen time (issue 27): each interpolation against its closed form
(glTF 2.0 Appendix C), then real files posed at a few times against vertex positions
computed by hand from their keyframes: the glTF Asset Generator's node animations (one per
interpolation and path), a skin whose joint turns, and morph weights animated."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from wgpu_shading import MeshError, load_mesh
from wgpu_shading.assets.gltf.animations import interpolate

DATA = Path(__file__).parent / "data" / "real"
GENERATOR = DATA / "asset_generator"
pytestmark = pytest.mark.filterwarnings("ignore:.*texture could not be read")


def _quaternion(axis, degrees):
    half = math.radians(degrees) / 2
    return np.array([*(np.asarray(axis, float) * math.sin(half)), math.cos(half)])


def _rotation(axis, degrees):
    x, y, z = np.asarray(axis, float)
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array([
        [c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
        [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
        [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)],
    ])


# --------------------------------------------------------------------------- closed forms

TIMES = np.array([0.0, 1.0, 3.0])
VALUES = np.array([[0.0], [2.0], [6.0]])


@pytest.mark.parametrize("time, step, linear", [
    (-5.0, 0.0, 0.0),  # before the first keyframe: the first value (clamp)
    (0.0, 0.0, 0.0), (0.5, 0.0, 1.0), (1.0, 2.0, 2.0), (2.5, 2.0, 5.0),
    (3.0, 6.0, 6.0), (99.0, 6.0, 6.0),  # after the last: the last value
])
def test_step_and_linear_against_their_closed_forms(time, step, linear):
    assert interpolate(TIMES, VALUES, time, "STEP")[0] == step
    assert interpolate(TIMES, VALUES, time, "LINEAR")[0] == pytest.approx(linear)


@pytest.mark.parametrize("s", [0.0, 0.1, 0.25, 0.5, 0.8, 1.0])
def test_cubic_spline_is_the_hermite_polynomial_with_tangents_scaled_by_the_interval(s):
    # keyframes at 2 s and 4 s (interval 2): values 1 and 3, out-tangent 0.5, in-tangent -1
    times = np.array([2.0, 4.0])
    values = np.array([[[9.0], [1.0], [0.5]], [[-1.0], [3.0], [9.0]]])  # (in, value, out); 9s are unused
    t = 2.0 + 2.0 * s
    expected = ((2 * s**3 - 3 * s**2 + 1) * 1.0 + (s**3 - 2 * s**2 + s) * 2.0 * 0.5
                + (-2 * s**3 + 3 * s**2) * 3.0 + (s**3 - s**2) * 2.0 * -1.0)
    assert interpolate(times, values, t, "CUBICSPLINE")[0] == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("s", [0.25, 0.5, 0.9])
def test_linear_rotation_is_slerp_the_short_way_round(s):
    start, end = _quaternion((0, 1, 0), 0), _quaternion((0, 1, 0), 120)
    expected = _quaternion((0, 1, 0), 120 * s)
    got = interpolate(np.array([0.0, 1.0]), np.stack([start, end]), s, "LINEAR", rotation=True)
    np.testing.assert_allclose(got, expected, atol=1e-12)
    # −q is the same rotation: still the short way, not the 240° one
    got = interpolate(np.array([0.0, 1.0]), np.stack([start, -end]), s, "LINEAR", rotation=True)
    np.testing.assert_allclose(abs(np.dot(got, expected)), 1.0, atol=1e-12)


def test_a_single_keyframe_holds_its_value_at_every_time():
    for time in (-1.0, 0.0, 7.0):
        assert interpolate(np.array([0.5]), np.array([[4.0, 5.0, 6.0]]), time, "LINEAR").tolist() == [4.0, 5.0, 6.0]


# --------------------------------------------------------------------------- real files posed


def _at(name: str, time: float | None, **options):
    mesh = load_mesh(GENERATOR / name, animation_time=time, **options)
    return mesh.world_positions()


@pytest.mark.parametrize("time, x", [(0.0, -0.1), (0.25, -0.05), (0.5, 0.0), (1.0, 0.1), (1.5, 0.0), (5.0, -0.1)])
def test_linear_translation_moves_the_cube(time, x):
    rest = _at("Animation_Node_00.gltf", None)
    np.testing.assert_allclose(_at("Animation_Node_00.gltf", time), rest + [x, 0, 0], atol=1e-6)


@pytest.mark.parametrize("time, degrees", [(0.0, 90), (0.5, 45), (1.0, 0), (1.5, -45), (2.25, -67.5), (4.0, 90)])
def test_linear_rotation_turns_the_cube(time, degrees):
    rest = _at("Animation_Node_01.gltf", None)
    np.testing.assert_allclose(_at("Animation_Node_01.gltf", time), rest @ _rotation((0, 1, 0), degrees).T, atol=1e-5)


@pytest.mark.parametrize("time, scale", [(0.0, 0.8), (0.5, 1.0), (1.0, 1.2), (1.75, 0.9)])
def test_linear_scale_grows_the_cube(time, scale):
    rest = _at("Animation_Node_02.gltf", None)
    np.testing.assert_allclose(_at("Animation_Node_02.gltf", time), rest * scale, atol=1e-6)


@pytest.mark.parametrize("time, x", [(0.0, -0.1), (0.99, -0.1), (1.0, 0.0), (2.5, 0.1), (3.999, 0.0), (4.0, -0.1)])
def test_step_translation_jumps_at_each_keyframe(time, x):
    rest = _at("Animation_Node_03.gltf", None)
    np.testing.assert_allclose(_at("Animation_Node_03.gltf", time), rest + [x, 0, 0], atol=1e-6)


@pytest.mark.parametrize("time", [0.0, 0.25, 0.5, 1.3, 2.0])
def test_cubic_spline_translation_follows_the_hermite_curve(time):
    # keyframes −0.1, 0.1, −0.1 at 0, 1, 2 s with zero tangents: smoothstep between them
    s = time % 1.0 if time < 2.0 else 1.0
    start, end = (-0.1, 0.1) if time < 1.0 else (0.1, -0.1)
    x = start + (end - start) * (3 * s**2 - 2 * s**3)
    rest = _at("Animation_Node_04.gltf", None)
    np.testing.assert_allclose(_at("Animation_Node_04.gltf", time), rest + [x, 0, 0], atol=1e-6)


def test_cubic_spline_rotation_is_normalized():
    # keyframes 90°, 0°, −90° about +Y with zero tangents: at 0.5 s the Hermite blend of the two
    # quaternions, normalized, is a rotation about +Y by the angle its components give
    q = 0.5 * _quaternion((0, 1, 0), 90) + 0.5 * _quaternion((0, 1, 0), 0)
    degrees = math.degrees(2 * math.atan2(q[1], q[3]))
    rest = _at("Animation_Node_05.gltf", None)
    np.testing.assert_allclose(_at("Animation_Node_05.gltf", 0.5), rest @ _rotation((0, 1, 0), degrees).T, atol=1e-5)


def test_a_channel_starting_late_holds_its_first_keyframe_before_it():
    rest = _at("Animation_NodeMisc_01.gltf", None)  # rotation keyframes from 1 s to 5 s, the first 90° about +Y
    np.testing.assert_allclose(_at("Animation_NodeMisc_01.gltf", 0.0), rest @ _rotation((0, 1, 0), 90).T, atol=1e-5)
    np.testing.assert_allclose(_at("Animation_NodeMisc_01.gltf", 1.5), rest @ _rotation((0, 1, 0), 45).T, atol=1e-5)


def test_animation_index_chooses_the_animation_and_all_plays_every_one():
    # NodeMisc_07: animation 0 turns the cube, animation 1 moves it
    rest = _at("Animation_NodeMisc_07.gltf", None)
    turned = _at("Animation_NodeMisc_07.gltf", 0.5, animation_index=0)
    moved = _at("Animation_NodeMisc_07.gltf", 0.5, animation_index=1)
    both = _at("Animation_NodeMisc_07.gltf", 0.5, animation_index="all")
    assert np.ptp(turned - rest, axis=0).max() > 1e-3 and np.ptp(moved - rest, axis=0).max() < 1e-9
    np.testing.assert_allclose(both, turned + (moved - rest), atol=1e-6)  # the move is a pure translation


def test_an_animation_index_out_of_range_names_the_count():
    with pytest.raises(MeshError, match=r"animation index 2 is out of range: the file has 2 animations \(0\.\.1, or all\)"):
        _at("Animation_NodeMisc_07.gltf", 0.0, animation_index=2)


FILE_45 = 2 * math.degrees(math.atan2(0.383, 0.924))  # SimpleSkin writes 45° as (0, 0, 0.383, 0.924): 45.03°


@pytest.mark.parametrize("time, degrees", [(0.0, 0), (0.25, FILE_45 / 2), (1.0, 90), (1.25, 90), (2.25, FILE_45 / 2),
                                           (3.75, -(FILE_45 + 90) / 2), (99.0, 0)])
def test_a_skin_follows_its_animated_joint(time, degrees):
    # SimpleSkin (the glTF tutorial's): a strip from y = 0 to 2; joint 0 at (0, 1, 0), joint 1
    # its child, turning about Z: 0°, 45°, 90°, 90°, 45°, 0°, 0°, −45°, −90°, −90°, −45°, 0° every
    # 0.5 s. Both inverse bind matrices undo the (0, 1, 0) offset, so a vertex with weights
    # (w0, w1) goes to w0·v + w1·(v turned about (0, 1, 0)).
    rest = load_mesh(DATA / "khronos" / "SimpleSkin.gltf").world_positions()
    posed = load_mesh(DATA / "khronos" / "SimpleSkin.gltf", animation_time=time).world_positions()
    pivot = np.array([0.0, 1.0, 0.0])
    for vertex, got in zip(rest, posed):
        w1 = vertex[1] / 2.0  # the file's weights: 0, 0.25, 0.5, 0.75, 1 up the strip
        turned = (vertex - pivot) @ _rotation((0, 0, 1), degrees).T + pivot
        np.testing.assert_allclose(got, (1 - w1) * vertex + w1 * turned, atol=2e-6)


@pytest.mark.parametrize("time, elbow", [(1.0, 70), (2.5, -35)])
def test_the_shipped_arm_bends_its_elbow_and_turns_as_documented(time, elbow):
    # example:arm.glb: the bar's top ring (y = 2.2, all weight on the elbow at (0, 1.2, 0))
    # turns about Z with the elbow: 0°, 70°, 0°, −70°, 0° at 0..4 s ("wave", animation 0)
    posed = load_mesh("example:arm.glb", animation_time=time).world_positions()
    rest = load_mesh("example:arm.glb").world_positions()
    top = np.isclose(rest[:, 1], 2.2)
    pivot = np.array([0.0, 1.2, 0.0])
    np.testing.assert_allclose(posed[top], (rest[top] - pivot) @ _rotation((0, 0, 1), elbow).T + pivot, atol=1e-5)
    # "turn" (animation 1) turns the whole arm about Y by 90° a second
    turned = load_mesh("example:arm.glb", animation_time=1.5, animation_index=1).world_positions()
    np.testing.assert_allclose(turned, rest @ _rotation((0, 1, 0), 135).T, atol=1e-5)


@pytest.mark.parametrize("matrix, shown", [
    (["a"] * 16, "'a'"),
    ([1e300] * 15 + [1.0], "1e+300"),  # beyond the ±1e15 nodes.py allows (JSON has no inf; 1e400 reads as inf)
])
def test_a_bad_matrix_on_an_animated_node_is_refused_as_without_the_animation(tmp_path, matrix, shown):
    # The animated node's matrix was dropped silently when it did not convert, and decomposed
    # into NaNs with numpy warnings on stderr when it was not finite: only the unanimated
    # file was refused. Now the same one-line error, whatever the time.
    from gltf_builder import add_animation, quad, write_gltf

    positions, faces = quad(0, 0)
    path = write_gltf(tmp_path / "m.gltf", [[{"positions": positions, "indices": faces}]], nodes=[{"mesh": 0, "matrix": matrix}])
    add_animation(path, [(0, "translation", [0.0, 1.0], [[0, 0, 0], [1, 0, 0]])])
    for time in (None, 0.5):
        with pytest.raises(MeshError, match=r"m.gltf.*nodes\[0\]\.matrix: expected 16 finite numbers") as caught:
            load_mesh(path, animation_time=time)
        assert shown in str(caught.value)


def _hostile(tmp_path, change) -> Path:
    """A square animated along x (times 0, 1, 2), then `change`d (its document, as JSON)."""
    import json

    from gltf_builder import add_animation, quad, write_gltf

    positions, faces = quad(0, 0)
    path = write_gltf(tmp_path / "h.gltf", [[{"positions": positions, "indices": faces}]])
    add_animation(path, [(0, "translation", [0.0, 1.0, 2.0], [[0, 0, 0], [1, 0, 0], [0, 0, 0]])])
    document = json.loads(path.read_text())
    change(document)
    path.write_text(json.dumps(document))
    return path


def _times(document) -> dict:
    return document["accessors"][document["animations"][0]["samplers"][0]["input"]]


def _sampler(document) -> dict:
    return document["animations"][0]["samplers"][0]


@pytest.mark.parametrize("change, words", [
    (lambda d: _times(d).update(count=10**7), ["accessors[", "10000000 elements need"]),  # far more keyframes than the buffer holds
    (lambda d: _times(d).update(count=2**31), ["accessors[", ".count", "2147483648"]),
    (lambda d: _sampler(d).update(interpolation="CUBICSPLINE"), ["samplers[0].output", "expected 9 elements for 3 CUBICSPLINE keyframes, got 3"]),
    (lambda d: _sampler(d).update(interpolation="QUADRATIC"), ["samplers[0].interpolation", "'QUADRATIC'"]),
    (lambda d: _sampler(d).update(output=_sampler(d)["input"]), ["samplers[0].output", "translation needs elements of width 3, got 1"]),
    (lambda d: d["animations"][0]["channels"][0].update(sampler=7), ["channels[0].sampler", "7 is not an index"]),
    (lambda d: d["animations"][0]["channels"][0]["target"].update(node=-1), ["channels[0].target.node", "-1 is not an index into nodes"]),
    (lambda d: d.update(animations={"a": 1}), ["animations: expected a list"]),
])
def test_a_hostile_animation_is_one_line_naming_its_field(tmp_path, capsys, change, words):
    path = _hostile(tmp_path, change)
    for command in (["render", str(path), "--animation-time", "0.5"], ["animate", str(path), "--fps", "2"]):
        code, err = run_cli(capsys, *command, "--size", "16", "-o", str(tmp_path / ("x.gif" if command[0] == "animate" else "x.png")))
        one_line_error(code, err, "h.gltf", *words)


@pytest.mark.parametrize("times, words", [
    ([0.0, 2.0, 1.0], ["samplers[0].input", "finite and increasing"]),  # not monotonic
    ([0.0, float("nan"), 2.0], ["samplers[0].input", "finite and increasing"]),
    ([0.0, 1.0, float("inf")], ["samplers[0].input", "finite and increasing"]),
])
def test_keyframe_times_must_be_finite_and_increasing(tmp_path, capsys, times, words):
    import base64
    import json

    from gltf_builder import add_animation, quad, write_gltf

    positions, faces = quad(0, 0)
    path = add_animation(write_gltf(tmp_path / "h.gltf", [[{"positions": positions, "indices": faces}]]),
                         [(0, "translation", [0.0, 1.0, 2.0], [[0, 0, 0], [1, 0, 0], [0, 0, 0]])])
    document = json.loads(path.read_text())
    view = document["bufferViews"][_times(document)["bufferView"]]
    blob = bytearray(base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1]))
    blob[view["byteOffset"] : view["byteOffset"] + 12] = np.array(times, "<f4").tobytes()
    document["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()
    _times(document).pop("min"), _times(document).pop("max")
    path.write_text(json.dumps(document))
    code, err = run_cli(capsys, "render", str(path), "--animation-time", "0.5", "--size", "16", "-o", str(tmp_path / "x.png"))
    one_line_error(code, err, "h.gltf", *words)


@pytest.mark.parametrize("camera, words", [
    ({"type": "perspective", "perspective": {"yfov": 0, "znear": 0.1}}, ["cameras[0].perspective.yfov", "greater than 0"]),
    ({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0}}, ["cameras[0].perspective.znear", "greater than 0"]),
    ({"type": "perspective", "perspective": {"yfov": 0.8, "znear": -1}}, ["cameras[0].perspective.znear", "got -1"]),
    ({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 1, "zfar": 0.5}}, ["cameras[0].perspective.zfar", "greater than 1"]),
    ({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": -1, "znear": 0, "zfar": 10}}, ["cameras[0].orthographic.ymag"]),
    ({"type": "fisheye"}, ["cameras[0]", "'fisheye'"]),
])
def test_a_hostile_camera_is_one_line_naming_its_field(tmp_path, capsys, camera, words):
    path = _hostile(tmp_path, lambda d: (d.update(cameras=[camera]), d["nodes"].append({"camera": 0, "translation": [0, 0, 5]}),
                                         d["scenes"][0]["nodes"].append(len(d["nodes"]) - 1)))
    code, err = run_cli(capsys, "render", str(path), "--camera-index", "0", "--size", "16", "-o", str(tmp_path / "x.png"))
    one_line_error(code, err, "h.gltf", *words)
