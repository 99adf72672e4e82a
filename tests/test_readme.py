"""The README runs: every shell command and every Python block of it, as a user would run
them, in an empty folder (so nothing depends on the clone's files), with the environment's
`wgpu-shading` and `python`. A README that names a missing file or a moved import fails here.

Not run: `./run ...` lines, the set-up itself (the suite is already running under it).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"
BIN = Path(sys.executable).parent  # the environment's bin/: wgpu-shading and python


def _blocks(language: str) -> list[tuple[int, str]]:
    """(line number, text) of every fenced block of `language`."""
    text = README.read_text(encoding="utf-8")
    blocks = []
    for match in re.finditer(rf"^```{language}\n(.*?)^```", text, re.S | re.M):
        blocks.append((text.count("\n", 0, match.start()) + 1, match.group(1)))
    return blocks


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    return env


def _commands(block: str) -> list[str]:
    commands = []
    for line in block.splitlines():
        if line.strip() and not line.lstrip().startswith(("#", "./run")):
            commands.append(line)
    return commands


SHELL_BLOCKS = _blocks("sh")
PYTHON_BLOCKS = _blocks("python")


def test_the_readme_has_commands_and_code():
    assert sum(len(_commands(block)) for _, block in SHELL_BLOCKS) >= 10
    assert len(PYTHON_BLOCKS) >= 2


@pytest.mark.parametrize("line, block", SHELL_BLOCKS, ids=[f"sh@line{n}" for n, _ in SHELL_BLOCKS])
def test_readme_shell_block_runs(line, block, tmp_path):
    # A block's commands run in order in one folder: `check --update` writes what the next line reads.
    for command in _commands(block):
        result = subprocess.run(
            ["bash", "-c", command], cwd=tmp_path, env=_environment(), capture_output=True, text=True, timeout=300
        )
        assert result.returncode == 0, f"README line {line}ff: {command!r} exited {result.returncode}:\n{result.stderr}"
    _assert_outputs_named(tmp_path, block, f"README line {line}ff")


def _assert_outputs_named(folder: Path, text: str, where: str, ignore: tuple[str, ...] = ()) -> None:
    """A command a reader copies names what it writes (-o, --out, a redirect): nothing lands in
    their current folder under a name the README does not show."""
    unnamed = sorted(p.name for p in folder.iterdir() if p.name not in ignore and p.name not in text)
    assert not unnamed, f"{where} wrote files it does not name: {unnamed}"


@pytest.mark.parametrize("line, block", PYTHON_BLOCKS, ids=[f"python@line{n}" for n, _ in PYTHON_BLOCKS])
def test_readme_python_block_runs(line, block, tmp_path):
    script = tmp_path / "readme_block.py"
    script.write_text(block)
    result = subprocess.run(
        [str(BIN / "python"), str(script)], cwd=tmp_path, env=_environment(), capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, f"README Python block at line {line} failed:\n{result.stderr}"
    _assert_outputs_named(tmp_path, block, f"README Python block at line {line}", ignore=(script.name,))
