"""The Python blocks of docs/*.md name what exists: every block compiles, and every name it
imports from wgpu_shading can be imported (a moved module, such as the old
`wgpu_shading.batch`, fails here). Blocks that are whole programs and quick also run."""

from __future__ import annotations

import ast
import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"
# Whole programs, quick to run, in an empty folder.
RUN = {"view-options.md"}


def _blocks() -> list[tuple[str, int, str]]:
    blocks = []
    for path in sorted(DOCS.glob("*.md")):
        text = path.read_text(encoding="utf-8")
        for match in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M):
            blocks.append((path.name, text.count("\n", 0, match.start()) + 1, match.group(1)))
    return blocks


BLOCKS = _blocks()


def test_the_docs_have_python_blocks():
    assert len(BLOCKS) >= 5 and any(name == "performance.md" for name, _, _ in BLOCKS)


@pytest.mark.parametrize("name, line, code", BLOCKS, ids=[f"{name}@{line}" for name, line, _ in BLOCKS])
def test_doc_block_imports_exist(name, line, code, tmp_path):
    tree = ast.parse(code, filename=f"docs/{name}:{line}")
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("wgpu_shading"):
            module = importlib.import_module(node.module)
            for alias in node.names:
                assert hasattr(module, alias.name) or importlib.util.find_spec(f"{node.module}.{alias.name}"), (
                    f"docs/{name} line {line}: {node.module} has no {alias.name}"
                )
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("wgpu_shading"):
                    importlib.import_module(alias.name)
    if name in RUN:
        script = tmp_path / "block.py"
        script.write_text(code)
        result = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, f"docs/{name} line {line}:\n{result.stderr}"


def test_help_names_no_docs_path():
    """An installed package has no docs/ folder: --help explains instead of pointing there."""
    from wgpu_shading.cli.main import build_parser

    parser = build_parser()
    commands = next(action for action in parser._actions if action.dest == "command")  # argparse keeps them here
    for name, command in commands.choices.items():
        assert "docs/" not in command.format_help(), name
