"""Progress of long work (turntable, bench accuracy): a tqdm bar on a terminal, nothing when
stderr is not a terminal or with -q."""

from __future__ import annotations

import fcntl
import io
import os
import pty
import struct
import subprocess
import sys
import termios
from pathlib import Path

import pytest

from wgpu_shading.study.accuracy.progress import Progress

BIN = Path(sys.executable).parent


def _turntable_stderr(tmp_path, *extra: str, terminal: bool) -> str:
    command = [str(BIN / "wgpu-shading"), "turntable", "builtin:torus", "--size", "32", "--frames", "12",
               "-o", str(tmp_path / "spin.gif"), *extra]
    if not terminal:
        result = subprocess.run(command, capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stderr
        return result.stderr
    controller, terminal_end = pty.openpty()
    fcntl.ioctl(terminal_end, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))  # a 100-column terminal
    try:
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=terminal_end)
        os.close(terminal_end)
        chunks = []
        while True:
            try:
                chunk = os.read(controller, 4096)
            except OSError:  # the pty closes when the process exits
                break
            if not chunk:
                break
            chunks.append(chunk)
        assert process.wait(timeout=120) == 0
    finally:
        os.close(controller)
    return b"".join(chunks).decode(errors="replace")


def test_turntable_shows_a_bar_on_a_terminal(tmp_path):
    shown = _turntable_stderr(tmp_path, terminal=True)
    assert "12/12" in shown and "frame" in shown


@pytest.mark.parametrize("extra, terminal", [((), False), (("-q",), True)])
def test_turntable_is_quiet_without_a_terminal_or_with_q(tmp_path, extra, terminal):
    assert _turntable_stderr(tmp_path, *extra, terminal=terminal).strip() == ""


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_study_progress_bar_on_a_terminal_only():
    terminal = _Terminal()
    bar = Progress(4.0, stream=terminal)
    for step in ("128² 20 triangles", "128² 200 triangles"):
        bar.advance(2.0, step)
    assert "100%" in terminal.getvalue() and "200 triangles" in terminal.getvalue() and bar.done == 4.0
    log = io.StringIO()
    Progress(4.0, stream=log).advance(4.0, "done")
    assert log.getvalue() == ""
