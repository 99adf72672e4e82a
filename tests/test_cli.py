"""The command line, as a user types it."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest

from wgpu_shading.cli import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def run_cli(*args: str) -> subprocess.CompletedProcess:
    """The installed console script, in a fresh process (what a user's shell runs)."""
    executable = shutil.which("wgpu-shading", path=str(Path(sys.executable).parent)) or "wgpu-shading"
    return subprocess.run([executable, *args], capture_output=True, text=True, timeout=120)


def test_render_builtin_torus_from_a_new_process(tmp_path):
    out = tmp_path / "t.png"
    result = run_cli("render", "builtin:torus", "-o", str(out))
    assert result.returncode == 0, result.stderr
    image = iio.imread(out)
    assert image.shape == (512, 512, 4) and image.dtype == np.uint8
    covered = (image[:, :, :3] != 0).any(axis=2)
    assert 0.1 < covered.mean() < 0.6  # the torus fills a good part of the frame
    # gold: red > green > blue wherever lit
    lit = image[covered].astype(int)
    assert (lit[:, 0] >= lit[:, 1]).mean() > 0.99 and (lit[:, 1] >= lit[:, 2]).mean() > 0.99


@pytest.mark.parametrize(
    "args, message",
    [
        (["render", "missing.toml"], "scene file 'missing.toml' not found"),
        (["render", "builtin:teapot"], "unknown built-in mesh 'builtin:teapot'"),
        (["render", "builtin:torus", "--material", "goldd"], "did you mean 'gold'"),
        (["render", "builtin:torus", "-o", "/nonexistent/dir/x.png"], "folder '/nonexistent/dir' does not exist"),
        (["render", "builtin:torus", "-o", "x.gif"], "unsupported format"),
    ],
)
def test_errors_are_one_line_without_traceback(args, message):
    result = run_cli(*args)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert result.stderr.startswith("wgpu-shading: error: ") and message in result.stderr


def test_bad_scene_key_names_file_and_key(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text("[shading]\nfrequency = \"smooth\"\n")
    assert main(["render", str(scene)]) == 2
    err = capsys.readouterr().err
    assert str(scene) in err and "shading.frequency" in err and "'smooth'" in err


def test_render_scene_file_with_overrides(tmp_path, capsys, renderer):
    out = tmp_path / "flat.png"
    assert main(["render", str(EXAMPLES / "gold_torus_phong.toml"), "--frequency", "flat", "--size", "96x64", "-o", str(out)]) == 0
    assert "flat shading" in capsys.readouterr().out
    image = iio.imread(out)
    assert image.shape == (64, 96, 4)


def test_float_output_and_depth(tmp_path, renderer):
    out, depth = tmp_path / "t.npy", tmp_path / "d.npy"
    assert main(["render", "builtin:sphere", "--size", "64", "-o", str(out), "--depth", str(depth), "-q"]) == 0
    color, distance = np.load(out), np.load(depth)
    assert color.dtype == np.float32 and color.shape == (64, 64, 4)
    assert np.isinf(distance[0, 0]) and np.isfinite(distance[32, 32])
    covered = np.isfinite(distance)
    assert (color[covered][:, 3] == 1.0).all()


def test_materials_lists_the_table(capsys):
    assert main(["materials"]) == 0
    out = capsys.readouterr().out
    assert "gold" in out and "0.7516" in out and "51.200" in out and "pewter" in out
    from wgpu_shading import MATERIALS

    listed = [line.split()[0] for line in out.splitlines() if line.split() and line.split()[0] in MATERIALS]
    assert listed == list(MATERIALS) and len(listed) == 29


def test_shader_prints_the_generated_wgsl(capsys):
    assert main(["shader", str(EXAMPLES / "gold_torus_gouraud.toml")]) == 0
    out = capsys.readouterr().out
    assert "frequency=gouraud" in out and "@vertex" in out and "@fragment" in out
    assert "SpotLight" not in out


def test_info_names_the_adapter(capsys, renderer):
    assert main(["info"]) == 0
    out = capsys.readouterr().out
    assert "llvmpipe" in out and "using:" in out
    assert "mesh cache: off (set WGPU_SHADING_MESH_CACHE to a folder" in out  # (the tests run without it: conftest.py)


def test_info_says_where_the_mesh_cache_is_and_how_full(capsys, renderer, tmp_path, monkeypatch):
    monkeypatch.setenv("WGPU_SHADING_MESH_CACHE", str(tmp_path))
    monkeypatch.setenv("WGPU_SHADING_MESH_CACHE_MB", "64")
    (tmp_path / "a.entry").write_bytes(bytes(3 << 20))
    assert main(["info"]) == 0
    assert f"mesh cache: {tmp_path} (1 entry, 3.0 of 64 MiB; WGPU_SHADING_MESH_CACHE=off turns it off)" in capsys.readouterr().out


def test_unknown_adapter_explains_how_to_get_one():
    result = run_cli("render", "builtin:cube", "--adapter", "no-such-gpu", "-o", "/tmp/never.png")
    assert result.returncode == 2
    # lavapipe is installed here: the error lists the adapters and must not suggest installing it.
    assert "no adapter matches 'no-such-gpu'" in result.stderr and "llvmpipe" in result.stderr
    assert "apt-get" not in result.stderr and "leave --adapter" in result.stderr


def test_help_for_every_command():
    for command in ("render", "shader", "materials", "info"):
        with pytest.raises(SystemExit) as exit_:
            main([command, "--help"])
        assert exit_.value.code == 0


INVALID_OBJ = {
    "nan.obj": ("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "nan.obj:1: 'v' line has a NaN or infinite coordinate"),
    "inf.obj": ("v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n", "inf.obj:2: 'v' line has a NaN or infinite coordinate"),
    "zero.obj": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "zero.obj:4: face index 0 in 'f 0 1 2' (OBJ indices start at 1)"),
    "outside.obj": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "outside.obj:4: face 'f 1 2 9' refers to a vertex that does not exist"),
    "empty.obj": ("# nothing\n", "contains no triangles"),
}


@pytest.mark.parametrize("name", sorted(INVALID_OBJ))
def test_invalid_mesh_files_are_one_line_errors(tmp_path, capsys, name):
    text, message = INVALID_OBJ[name]
    path = tmp_path / name
    path.write_text(text)
    assert main(["render", str(path), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and name in err and message in err, err
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["builtin:cube", "--size", "0x0"], "--size: width and height must be between 1 and 16384, got 0×0"),
        (["builtin:cube", "--size", "100000x100000"], "got 100000×100000"),
        (["builtin:cube", "--material", "kryptonite"], "unknown material 'kryptonite'"),
    ],
)
def test_invalid_arguments_are_one_line_errors(tmp_path, capsys, args, message):
    assert main(["render", *args, "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


@pytest.mark.parametrize(
    "camera, message",
    [
        ("eye = [1.0, 1.0, 1.0]\ntarget = [1.0, 1.0, 1.0]", "coincide"),
        ("eye = [0.0, 5.0, 0.0]\nup = [0.0, 1.0, 0.0]", "parallel to the view direction"),
    ],
)
def test_degenerate_cameras_are_one_line_errors(tmp_path, capsys, camera, message):
    scene = tmp_path / "camera.toml"
    scene.write_text(f'[camera]\n{camera}\n[[objects]]\nmesh = "builtin:cube"\n')
    assert main(["render", str(scene), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(scene) in err and message in err, err


def test_image_too_big_for_the_adapter_is_a_clear_error(tmp_path, capsys, renderer):
    # 16384² float32 needs a 4 GiB readback buffer; lavapipe allows 2 GiB per buffer.
    assert main(["render", "builtin:cube", "--size", "16384", "--float", "-o", str(tmp_path / "x.npy")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "4.0 GiB readback buffer" in err and "8-bit target" in err, err


def test_internal_errors_are_one_line_unless_debugging(monkeypatch, capsys):
    import wgpu_shading.cli as cli

    def broken(args):
        raise RuntimeError("something the package did wrong")

    monkeypatch.setattr(cli.info, "command_materials", broken)
    assert cli.main(["materials"]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "internal error: RuntimeError: something the package did wrong" in err
    monkeypatch.setenv("WGPU_SHADING_DEBUG", "1")
    with pytest.raises(RuntimeError):
        cli.main(["materials"])


@pytest.mark.parametrize("suffix", [".jpg", ".bmp", ".tif"])
def test_other_image_formats(tmp_path, suffix, renderer):
    out = tmp_path / f"torus{suffix}"
    assert main(["render", "builtin:torus", "--size", "64", "-o", str(out), "-q"]) == 0
    from PIL import Image

    image = np.asarray(Image.open(out))
    assert image.shape[:2] == (64, 64) and image[..., :3].max() > 100  # the torus is there


def test_float_output_needs_a_format_that_keeps_it(tmp_path, capsys):
    for name in ("x.jpg", "x.png"):
        assert main(["render", "builtin:cube", "--float", "-o", str(tmp_path / name)]) == 2
        assert "--float writes exact float32 values to .npy" in capsys.readouterr().err
        assert not (tmp_path / name).exists()


# --------------------------------------------------------------------------- what a newcomer types


def _help(capsys, *command: str) -> str:
    with pytest.raises(SystemExit) as exited:
        main([*command, "--help"])
    assert exited.value.code == 0
    return capsys.readouterr().out


def _option_help(text: str, option: str) -> str:
    """The help paragraph of one option (argparse wraps it over several lines)."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.lstrip().startswith(option))
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("  -")), len(lines))
    return " ".join(line.strip() for line in lines[start:end])


def _suffixes(text: str) -> set[str]:
    """The file suffixes a help text names (".png", not the "..far" of "near..far")."""
    import re

    return set(re.findall(r"(?<![\w.])(\.[a-z][a-z0-9]{2,3})\b", text))


CANDIDATE_SUFFIXES = (".png", ".npy", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".gif", ".webp", ".ppm", ".exr", ".mp4", ".txt")


def test_render_writes_exactly_the_formats_its_help_lists(tmp_path, capsys):
    """`-o` takes what --help lists and refuses the rest with the list (one table, image_writers.py)."""
    from PIL import Image

    listed = set(_suffixes(_option_help(_help(capsys, "render"), "-o OUTPUT")))
    accepted = set()
    for suffix in CANDIDATE_SUFFIXES:
        out = tmp_path / f"t{suffix}"
        status = main(["render", "builtin:cube", "--size", "8", "-o", str(out), "-q"])
        error = capsys.readouterr().err
        if status == 0:
            accepted.add(suffix)
            if suffix == ".npy":
                assert np.load(out).dtype == np.float32
            else:
                with Image.open(out) as image:
                    assert image.size == (8, 8) and image.mode in ("RGB", "RGBA")
        else:
            assert status == 2 and "unsupported format; use one of .png, .npy, .jpg" in error and not out.exists(), error
    assert accepted == listed == {".png", ".npy", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"}


def test_depth_and_animation_outputs_accept_what_their_help_lists(capsys):
    from wgpu_shading.assets.animation import ANIMATION_SUFFIXES
    from wgpu_shading.assets.image_writers import DEPTH_SUFFIXES

    assert _suffixes(_option_help(_help(capsys, "render"), "--depth DEPTH")) == set(DEPTH_SUFFIXES)
    assert _suffixes(_option_help(_help(capsys, "turntable"), "-o OUTPUT")) == set(ANIMATION_SUFFIXES)


@pytest.mark.parametrize(
    "argv, line",
    [
        (["render", "builtin:torus", "--sise", "64"], "unknown option --sise: did you mean --size? (see `wgpu-shading render --help`)"),
        (["render", "builtin:torus", "--sise=64"], "unknown option --sise: did you mean --size? (see `wgpu-shading render --help`)"),
        (["check", "x.toml", "--ref", "r.png", "--treshold", "3"], "unknown option --treshold: did you mean --threshold? (see `wgpu-shading check --help`)"),
        (["turntable", "builtin:torus", "--frame", "3", "-o", "never.gif"], "unknown option --frame: did you mean --frames? (see `wgpu-shading turntable --help`)"),
        (["bench", "accuracy", "--quik"], "unknown option --quik: did you mean --quick? (see `wgpu-shading bench accuracy --help`)"),
        (["render", "builtin:torus", "--zzzz"], "unknown option --zzzz (see `wgpu-shading render --help`)"),
        (["render", "a.obj", "b.obj"], "unexpected argument 'b.obj' (see `wgpu-shading render --help`)"),
        (["rendr", "builtin:torus"], ": did you mean render? (see `wgpu-shading --help`)"),
    ],
)
def test_a_mistyped_flag_gets_the_closest_spelling_and_the_commands_help(capsys, argv, line):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("wgpu-shading: error: ") and err.rstrip("\n").endswith(line) and err.count("\n") == 1, err


@pytest.mark.parametrize("flag, value, field", [
    ("--up", "-Z", "up"),
    ("--camera-direction", "-Y", "camera_direction"),
    ("--camera-position", "-1,2,3", "camera_position"),
    ("--camera-position", "-1e1,0,0", "camera_position"),
    ("--camera-elevation-angle", "-1.5e1", "camera_elevation"),
    ("--animation-time", "-2.5e-1", "animation_time"),
])
def test_a_value_starting_with_a_minus_sign_follows_its_flag(flag, value, field):
    # argparse took `--up -Z` (as the help writes the axis) and -1e1 for unknown options:
    # "--up: expected one argument". Now the value, as with `=`.
    from wgpu_shading.cli.arguments import view_options_from_args
    from wgpu_shading.cli.main import build_parser

    def parsed(*argv):
        return getattr(view_options_from_args(build_parser().parse_args(["render", "builtin:torus", *argv])), field)

    assert parsed(flag, value) == parsed(f"{flag}={value}") is not None


@pytest.mark.parametrize("argv, line", [
    (["render", "builtin:torus", "--size", "-q"], "--size: expected one argument"),  # a flag is still a flag
    (["render", "builtin:torus", "--up", "-Q"], "--up: expected one argument"),
    (["render", "builtin:torus", "--camera-index", "-1"], "--camera-index: expected an index from 0"),
])
def test_a_flag_after_a_flag_is_not_taken_for_its_value(capsys, argv, line):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert line in err and err.count("\n") == 1, err


def test_the_installed_command_answers_a_typo_in_one_line_with_status_2():
    result = run_cli("render", "builtin:torus", "--sise", "64")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr == "wgpu-shading: error: unknown option --sise: did you mean --size? (see `wgpu-shading render --help`)\n"


def test_help_shows_one_spelling_per_meaning_and_older_spellings_still_work(capsys, tmp_path):
    from wgpu_shading.cli.arguments import scene_from_args
    from wgpu_shading.cli.main import build_parser

    text = _help(capsys, "render")
    for shown in ("--transparent", "--no-transparent", "--size SIZE", "--camera-azimuth-angle DEG"):
        assert shown in text, shown
    for hidden in ("--no-background", "--resolution", "--camera-azimuth ", "--camera-elevation "):
        assert hidden not in text, hidden
    parse = lambda *flags: scene_from_args(build_parser().parse_args(["render", "builtin:torus", *flags]))  # noqa: E731
    assert parse("--no-background").background == parse("--transparent").background
    assert parse("--no-background").background[3] == 0.0
    assert parse("--resolution", "30,20").size == parse("--size", "30x20").size == (30, 20)
    assert parse("--camera-azimuth", "30").camera == parse("--camera-azimuth-angle", "30").camera
    # A prefix is not another spelling (it would silently change meaning when a flag is added).
    assert main(["render", "builtin:torus", "--transp", "-o", str(tmp_path / "t.png")]) == 2
    assert "unknown option --transp: did you mean --transparent?" in capsys.readouterr().err
