"""Instruction counts of warm frames under callgrind: what no neighbour's load disturbs.

    python -m benchmarks --only callgrind     # ours, the seed's WGSL, the limit, moderngl (GL)

Each contender renders its warm frames (scripts/callgrind_frames.py) under
`valgrind --tool=callgrind` with instrumentation switched on only around them (a tiny
shared library toggles it: built here with the system's C compiler). The count is the whole
process's, every thread (callgrind runs the threads one at a time). Needs valgrind, its
header <valgrind/callgrind.h> and cc; without them the section says so and is skipped.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from .measure import progress

SCRIPT = Path(__file__).resolve().parent / "scripts" / "callgrind_frames.py"
CONTENDERS = ("ours", "depth", "seed", "limit", "gl")
TOGGLE_C = """#include <valgrind/callgrind.h>
void start(void) { CALLGRIND_ZERO_STATS; CALLGRIND_START_INSTRUMENTATION; }
void stop(void) { CALLGRIND_STOP_INSTRUMENTATION; CALLGRIND_DUMP_STATS; }
"""


def callgrind_unusable() -> str | None:
    for tool in ("valgrind", "cc"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed"
    return None


def run_callgrind(mesh: str = "torus", size: int = 512, frames: int = 3, moderngl: bool = True) -> dict[str, int]:
    """Instructions of `frames` warm frames per contender (the whole process)."""
    counts: dict[str, int] = {}
    with tempfile.TemporaryDirectory() as folder:
        toggle = Path(folder) / "toggle.so"
        subprocess.run(["cc", "-shared", "-fPIC", "-O2", "-o", str(toggle), "-x", "c", "-"], input=TOGGLE_C, text=True, check=True)
        for contender in CONTENDERS:
            if contender == "gl" and not moderngl:
                continue
            progress(f"callgrind: {contender}, {frames} frames of the {mesh} at {size}²")
            out = Path(folder) / f"{contender}.out"
            subprocess.run(
                ["valgrind", "--tool=callgrind", "--instr-atstart=no", f"--callgrind-out-file={out}",
                 sys.executable, str(SCRIPT), contender, "--mesh", mesh, "--size", str(size), "--frames", str(frames)],
                env={**os.environ, "CALLGRIND_TOGGLE": str(toggle)}, capture_output=True, text=True, check=True, timeout=1800,
            )
            counts[contender] = sum(_totals(path) for path in Path(folder).glob(f"{contender}.out*"))
    return counts


def _totals(path: Path) -> int:
    """The instruction total of one callgrind output file (its `totals:` or `summary:` line)."""
    summary = 0
    for line in path.read_text(errors="replace").splitlines():
        if line.startswith("totals:"):
            return int(line.split()[1])
        if line.startswith("summary:"):
            summary = int(line.split()[1])
    return summary


def callgrind_table(counts: dict[str, int], mesh: str = "torus", size: int = 512, frames: int = 3) -> str:
    labels = {
        "ours": "ours (`Renderer.render`)", "depth": "ours, colour + depth (`render_frame(depth=True)`)",
        "seed": "the seed's shader in WGSL, our device", "limit": "trivial-shader limit", "gl": "moderngl, the seed's GLSL",
    }
    lines = [
        f"## Instructions of {frames} warm frames of the {mesh} at {size}² (callgrind, whole process)",
        "",
        "| contender | instructions | ÷ moderngl |",
        "|---|---:|---:|",
    ]
    for name, count in counts.items():
        ratio = f"{count / counts['gl']:.2f}×" if "gl" in counts else "–"
        lines.append(f"| {labels[name]} | {count / 1e6:,.1f} M | {ratio} |")
    return "\n".join(lines) + "\n"
