"""`wgpu-shading animate FILE -o anim.gif --fps N` (issue 27): a glTF file's animation played
into a GIF or MP4, each frame what `render --animation-time T` draws at T = k / fps, under
one camera that frames every pose."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from wgpu_shading import MeshError, UsageError, load_mesh
from wgpu_shading.assets.animation_frames import MAX_FRAMES, AnimationFrames, frame_times
from wgpu_shading.scene.view.options import ViewOptions

DATA = Path(__file__).parent / "data" / "real"
MOVING = DATA / "asset_generator" / "Animation_Node_00.gltf"  # x from −0.1 to 0.1 and back over 0..2 s
pytestmark = pytest.mark.filterwarnings("ignore:.*texture could not be read")


@pytest.mark.parametrize("start, end, fps, expected", [
    (0.0, 1.0, 4.0, [0.0, 0.25, 0.5, 0.75, 1.0]),  # the end falls on a frame: included
    (0.0, 0.7083333, 15.0, [k / 15 for k in range(11)]),  # Fox's walk: 11/15 s is past its end
    (0.5, 0.5, 30.0, [0.5]),  # a single keyframe: one frame
    (2.0, 1.0, 30.0, [2.0]),
    (0.0, 0.3, 10.0, [0.0, 0.1, 0.2, 0.3]),  # 0.3 · 10 is 2.9999999999999996 in floats: still 4 frames
])
def test_frame_times(start, end, fps, expected):
    assert frame_times(start, end, fps) == pytest.approx(expected, abs=1e-12)


def test_too_many_frames_is_a_usage_error():
    with pytest.raises(UsageError, match=f"at most {MAX_FRAMES}"):
        frame_times(0.0, 1e6, 60.0)


def test_every_frame_is_the_pose_at_its_time_under_one_camera():
    frames = AnimationFrames(str(MOVING), ViewOptions(size=(32, 32)), fps=2.0)
    assert frames.times == [0.0, 0.5, 1.0, 1.5, 2.0]
    scenes = list(frames)
    assert len({scene.camera for scene in scenes}) == 1 and len({scene.lights for scene in scenes}) == 1
    for time, scene in zip(frames.times, scenes):
        expected = load_mesh(MOVING, animation_time=time).world_positions()
        np.testing.assert_allclose(scene.objects[0].mesh.world_positions(), expected, atol=1e-6)
    # the one camera frames every pose: the cube's box widened by the ±0.1 it moves along x
    lower, upper = frames.framing.bounds()
    rest_lower, rest_upper = load_mesh(MOVING).bounds()
    np.testing.assert_allclose(lower, rest_lower - [0.1, 0, 0], atol=1e-6)
    np.testing.assert_allclose(upper, rest_upper + [0.1, 0, 0], atol=1e-6)


def test_animate_writes_a_gif_of_the_frames(tmp_path, capsys):
    from wgpu_shading.cli.main import main

    output = tmp_path / "moving.gif"
    assert main(["animate", str(MOVING), "-o", str(output), "--fps", "2", "--size", "32"]) == 0
    assert "(5 frames, 0 s to 2 s of animation 0, 2 fps)" in capsys.readouterr().out
    import imageio.v3 as iio

    frames = iio.imread(output, index=None)
    assert frames.shape[:3] == (5, 32, 32)
    assert not np.array_equal(frames[0], frames[1])  # it moves
    np.testing.assert_array_equal(frames[0], frames[4])  # and comes back: the same pose at 0 s and 2 s
    assert sorted(p.name for p in tmp_path.iterdir()) == ["moving.gif"]  # no temporary file left behind


def test_start_end_and_the_animation_index(tmp_path):
    two = DATA / "asset_generator" / "Animation_NodeMisc_07.gltf"  # two animations
    frames = AnimationFrames(str(two), ViewOptions(animation_index=1), fps=4.0, start=0.5, end=1.0)
    assert frames.times == [0.5, 0.75, 1.0] and frames.animation == 1
    every = AnimationFrames(str(two), ViewOptions(animation_index="all"), fps=1.0)
    assert every.animation == "all" and every.times[0] == 0.0


@pytest.mark.parametrize("args, words", [
    (["example:knot.obj"], ["only glTF files", "animations"]),
    ([str(DATA / "khronos" / "MorphPrimitivesTest.gltf")], ["MorphPrimitivesTest.gltf", "has no animations"]),
    ([str(MOVING), "--animation-time", "1"], ["--animation-time", "animate"]),
    ([str(MOVING), "--animation-index", "3"], ["animation index 3 is out of range: the file has 1 animation"]),
    ([str(MOVING), "--fps", "0"], ["--fps"]),
    ([str(MOVING), "--end", "inf"], ["--end"]),
])
def test_what_cannot_be_played_is_one_line(tmp_path, capsys, args, words):
    code, err = run_cli(capsys, "animate", *args, "-o", str(tmp_path / "out.gif"), "--size", "16")
    one_line_error(code, err, *words)
    assert not (tmp_path / "out.gif").exists()


def test_a_wrong_suffix_is_refused_before_any_frame(tmp_path, capsys):
    code, err = run_cli(capsys, "animate", str(MOVING), "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "out.png")


# --------------------------------------------------------------------------- found by trying real and hostile files

KHRONOS = DATA / "khronos"


@pytest.mark.parametrize("name", ["SimpleSkin.gltf", "SimpleMorph.gltf"])
def test_a_flat_model_is_played(tmp_path, capsys, name):
    # Both lie in the z = 0 plane: the box around every pose is flat, and the framing mesh
    # made of two of its sides had no area ("the animation's reach: none of its 2 triangles
    # has any area"), so neither Khronos tutorial file could be played.
    frames = AnimationFrames(str(KHRONOS / name), ViewOptions(size=(32, 32)), fps=1.0)
    lower, upper = frames.framing.bounds()
    assert lower[2] == upper[2] == 0.0 and (upper[:2] > lower[:2]).all()
    output = tmp_path / "flat.gif"
    code, err = run_cli(capsys, "animate", str(KHRONOS / name), "-o", str(output), "--size", "32", "--fps", "1", "-q")
    assert code == 0 and err == "" and output.exists()


def test_a_start_after_the_end_plays_the_one_frame_at_the_start(tmp_path, capsys):
    output = tmp_path / "one.gif"
    code, err = run_cli(capsys, "animate", str(KHRONOS / "SimpleSkin.gltf"), "-o", str(output), "--size", "16",
                        "--start", "5", "--end", "1")
    assert code == 0, err
    import imageio.v3 as iio

    assert iio.imread(output, index=None).shape[0] == 1


def _reads_of(path: Path, monkeypatch) -> list[str]:
    """Every open() of `path` from now on (the file read by our reader or anyone else)."""
    import builtins

    opened, real_open = [], builtins.open

    def counting_open(file, *args, **kwargs):
        if isinstance(file, (str, Path)) and Path(file).resolve() == path.resolve():
            opened.append(str(file))
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", counting_open)
    return opened


@pytest.mark.parametrize("source", [KHRONOS / "SimpleSkin.gltf", KHRONOS / "AnimatedMorphCube.gltf", MOVING])
def test_the_file_is_parsed_once_and_every_frame_is_the_moment_drawn_alone(source, monkeypatch):
    # Before, the file was parsed for the framing and again for every frame (N + 1 reads; the
    # textures decoded each time). Now once; the pixels must not change: each frame against
    # the view `render --animation-time T` loads on its own (the file read again, under the
    # same framing).
    from wgpu_shading.assets.view_loader import load_view
    from wgpu_shading.render.renderer import Renderer

    opened = _reads_of(source, monkeypatch)
    options = ViewOptions(size=(48, 40))
    frames = AnimationFrames(str(source), options, fps=3.0)
    scenes = list(frames)
    assert len(opened) == 1 and len(scenes) >= 4
    monkeypatch.undo()
    renderer = Renderer()
    for time, image in zip(frames.times, renderer.render_many(scenes)):
        alone = load_view(str(source), ViewOptions(size=(48, 40), animation_time=time, animation_index=0), framing=frames.framing)
        np.testing.assert_array_equal(image.color, renderer.render(alone), err_msg=f"{source.name} at {time} s")


def _square_growing_from_nothing(tmp_path) -> Path:
    """A square whose node scales from 0 (hidden, as exporters make an object appear) to 1."""
    from gltf_builder import add_animation, quad, write_gltf

    positions, faces = quad(-0.5, -0.5)
    path = write_gltf(tmp_path / "appears.gltf", [[{"positions": positions, "indices": faces}]])
    return add_animation(path, [(0, "scale", [0.0, 1.0, 2.0], [[0, 0, 0], [0, 0, 0], [1, 1, 1]])])


def test_a_moment_when_nothing_shows_is_a_frame_of_background(tmp_path, capsys):
    # Before, the whole animation was refused: "contains no triangles" (frame 0 is empty).
    from wgpu_shading.render.renderer import Renderer

    frames = AnimationFrames(str(_square_growing_from_nothing(tmp_path)), ViewOptions(size=(24, 24)), fps=1.0)
    assert frames.times == [0.0, 1.0, 2.0]
    empty, still_empty, shown = [image.color for image in Renderer().render_many(frames)]
    background = np.array([0, 0, 0, 255], np.uint8)  # the bare-mesh default
    assert (empty == background).all() and (still_empty == background).all()
    assert (shown != background).any(axis=-1).sum() > 24 * 24 // 4  # the square fills the framing
    output = tmp_path / "appears.gif"
    code, err = run_cli(capsys, "animate", str(tmp_path / "appears.gltf"), "-o", str(output), "--size", "24", "--fps", "1", "-q")
    assert code == 0 and err == ""


def test_an_animation_that_never_shows_anything_is_one_line(tmp_path, capsys):
    from gltf_builder import add_animation, quad, write_gltf

    positions, faces = quad(0, 0)
    path = add_animation(write_gltf(tmp_path / "never.gltf", [[{"positions": positions, "indices": faces}]]),
                         [(0, "scale", [0.0, 1.0], [[0, 0, 0], [0, 0, 0]])])
    code, err = run_cli(capsys, "animate", str(path), "-o", str(tmp_path / "never.gif"), "--size", "16")
    one_line_error(code, err, "never.gltf", "no frame of the animation", "shows anything")
    assert not (tmp_path / "never.gif").exists()


def test_what_the_file_says_is_said_once_for_the_whole_animation(tmp_path):
    # Two weights for one morph target: a note each time the file is posed (every frame).
    import json
    import warnings

    from gltf_builder import add_animation, quad, write_gltf

    positions, faces = quad(0, 0)
    path = write_gltf(tmp_path / "weights.gltf", [[{"positions": positions, "indices": faces}]])
    document = json.loads(path.read_text())
    document["meshes"][0]["primitives"][0]["targets"] = [{"POSITION": 0}]
    path.write_text(json.dumps(document))
    add_animation(path, [(0, "weights", [0.0, 1.0], [[0.0, 0.5], [0.2, 0.5]])])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        list(AnimationFrames(str(path), ViewOptions(size=(16, 16)), fps=4.0))
    said = [str(w.message) for w in caught]
    assert len(said) == 1 and "2 morph weights for 1 targets" in said[0], said


def test_render_at_a_moment_when_nothing_shows_draws_the_background_as_animate_does(tmp_path, capsys):
    # `animate`'s frame at T is what `render --animation-time T` draws: before, render
    # refused the moment ("contains no triangles"); load_mesh, which must return a Mesh,
    # still says why there is none.
    import imageio.v3 as iio

    path = _square_growing_from_nothing(tmp_path)
    for time, shown in ((0.5, False), (2.0, True)):
        output = tmp_path / f"at_{time}.png"
        code, err = run_cli(capsys, "render", str(path), "--animation-time", str(time), "--size", "24", "-o", str(output), "-q")
        assert code == 0 and err == "", err
        image = iio.imread(output)
        assert (image != [0, 0, 0, 255]).any(axis=-1).any() == shown
    with pytest.raises(MeshError, match=r"appears.gltf.*nothing shows at 0.5 s of animation 0"):
        load_mesh(path, animation_time=0.5)
    never = _square_growing_from_nothing(tmp_path)
    import json

    document = json.loads(never.read_text())
    document["nodes"][0]["scale"] = [0, 0, 0]  # hidden unanimated too: nothing to place a view around
    never.write_text(json.dumps(document))
    code, err = run_cli(capsys, "render", str(never), "--animation-time", "0.5", "--size", "24", "-o", str(tmp_path / "n.png"))
    one_line_error(code, err, "appears.gltf", "contains no triangles")


def test_a_warning_about_the_file_is_said_even_when_the_first_frames_show_nothing(tmp_path):
    # The lost texture's note is made once (materials are made once per file); the first
    # frame, empty, must not swallow it before a frame that shows something says it.
    import json
    import warnings

    path = _square_growing_from_nothing(tmp_path)
    document = json.loads(path.read_text())
    document["images"] = [{"uri": "missing.png"}]
    document["textures"] = [{"source": 0}]
    document["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    document["meshes"][0]["primitives"][0]["material"] = 0
    path.write_text(json.dumps(document))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        list(AnimationFrames(str(path), ViewOptions(size=(16, 16)), fps=1.0))
    said = [str(w.message) for w in caught]
    assert len(said) == 1 and "could not be read" in said[0], said
