"""Command-line flags and arguments refused with one line naming the flag and the value (exit 2,
no traceback; docs/reliability.md)."""

from __future__ import annotations

import pytest

from cli_errors import one_line_error, run_cli


def test_a_nul_character_in_an_argument_is_a_clear_error(tmp_path, capsys):
    code, err = run_cli(capsys, "render", "scene\x00.toml", "-o", str(tmp_path / "o.png"))
    assert code == 2 and err.strip() == "wgpu-shading: error: input 'scene\\x00.toml' contains a NUL character"
    code, err = run_cli(capsys, "render", "builtin:cube", "-o", "o\x00.png")
    assert code == 2 and "--output 'o\\x00.png' contains a NUL character" in err


@pytest.mark.parametrize("spec", ["directional:dir=1,1,1:dir=0,0,1", "positional:pos=1,1,1:position=2,2,2"])
def test_a_light_key_given_twice_is_an_error(tmp_path, capsys, spec):
    code, err = run_cli(capsys, "render", "builtin:cube", "--light", spec, "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "--light", "given twice")


def test_turntable_degrees_must_be_finite(tmp_path, capsys):
    code, err = run_cli(capsys, "turntable", "builtin:sphere", "--degrees", "inf", "--frames", "2", "-o", str(tmp_path / "t.gif"))
    assert code == 2 and "--degrees" in err and "inf" in err


@pytest.mark.parametrize("fps", ["1e-300", "0", "nan", "1e300"])
def test_turntable_fps_out_of_range_is_a_clear_error(tmp_path, capsys, fps):
    code, err = run_cli(capsys, "turntable", "builtin:cube", "--fps", fps, "--frames", "1", "-o", str(tmp_path / "t.gif"))
    assert code == 2 and "--fps must be between 0.01 and 1000 frames per second" in err


def test_a_text_command_whose_reader_goes_away_stops_quietly():
    """`wgpu-shading shader … | head`: a reader that has gone away (here: closed before the
    first write) stops the command without an error message, as text tools stop, and with
    the status a shell reports for SIGPIPE (128 + 13)."""
    import os
    import subprocess
    import sys

    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        writer = subprocess.run(
            [sys.executable, "-c", "import sys; from wgpu_shading.cli import main; sys.exit(main())",
             "shader", "example:two_lights.toml"],
            stdout=write_end, stderr=subprocess.PIPE, text=True, timeout=120,
        )
    finally:
        os.close(write_end)
    assert (writer.returncode, writer.stderr) == (141, "")
