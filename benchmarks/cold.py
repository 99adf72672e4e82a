"""Cold start: process start to PNG on disk, for the CLI and its peers, in fresh processes.

Variants, interleaved round by round:
    wgpu-shading CLI            `wgpu-shading render builtin:torus -o OUT.png`
    CLI, prebuilt FFI off       the same with WGPU_SHADING_PREBUILT_FFI=0: wgpu-py's own
                                cffi start-up, i.e. the cold start before this work
    moderngl script             scripts/moderngl_torus.py: the same image with moderngl
    wgpu floor (+ prebuilt FFI) scripts/wgpu_floor.py: device + trivial pipeline + one
                                triangle + readback, the least any wgpu-py program does
    python + numpy              the interpreter starting and importing numpy

Disk caches (Mesa's shader cache, our FFI table) are warm, as for anyone who has run the
command once; `fresh caches` runs the CLI with an empty XDG_CACHE_HOME for comparison.
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from .measure import progress

SCRIPTS = Path(__file__).resolve().parent / "scripts"


def _cli() -> str:
    return shutil.which("wgpu-shading", path=str(Path(sys.executable).parent)) or "wgpu-shading"


@dataclass
class ColdResult:
    runs: dict[str, list[float]]  # variant -> seconds per run
    phases: dict[str, float]  # phase -> median seconds (prebuilt FFI on)
    phases_without_ffi: dict[str, float]

    def median(self, variant: str) -> float:
        return statistics.median(self.runs[variant])


def _timed(command: list[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed: {result.stderr.strip()[-400:]}")
    return elapsed


def run_cold(
    rounds: int, *, size: int | None = None, moderngl: bool = True, fill_caches: bool = True, phase_rounds: int | None = None
) -> ColdResult:
    """size: the image side for the CLI and cold_phases.py (default: the CLI's 512);
    moderngl False leaves the moderngl script out; fill_caches False skips the untimed
    first run of each variant; phase_rounds: rounds of the phases without the prebuilt FFI
    (default max(2, rounds // 2)). The smoke run uses all four to run each step once."""
    folder = Path(tempfile.mkdtemp(prefix="wgpu-shading-cold-"))
    out = str(folder / "t.png")
    env = {**os.environ}
    no_ffi = {**env, "WGPU_SHADING_PREBUILT_FFI": "0"}
    render = [_cli(), "render", "builtin:torus", "-o", out, "-q"] + (["--size", str(size)] if size else [])
    variants = {
        "wgpu-shading CLI": (render, env),
        "CLI, prebuilt FFI off (before)": (render, no_ffi),
        "moderngl script": ([sys.executable, str(SCRIPTS / "moderngl_torus.py"), out] + ([str(size)] if size else []), env),
        "wgpu floor + prebuilt FFI": ([sys.executable, str(SCRIPTS / "wgpu_floor.py"), "--prebuilt-ffi"], env),
        "wgpu floor (plain wgpu-py)": ([sys.executable, str(SCRIPTS / "wgpu_floor.py")], env),
        "python + import numpy": ([sys.executable, "-c", "import numpy"], env),
    }
    if not moderngl:
        del variants["moderngl script"]
    if fill_caches:
        for command, variant_env in variants.values():  # fill disk caches; not timed
            _timed(command, variant_env)
    runs: dict[str, list[float]] = {name: [] for name in variants}
    names = list(variants)
    for round_index in range(rounds):
        progress(f"cold start: round {round_index + 1}/{rounds}")
        shift = round_index % len(names)
        for name in names[shift:] + names[:shift]:
            command, variant_env = variants[name]
            runs[name].append(_timed(command, variant_env))
    # First run ever: Mesa's shader cache and our FFI table both live under XDG_CACHE_HOME.
    runs["CLI, fresh caches (first run ever)"] = []
    for _ in range(max(1, rounds // 4)):
        with tempfile.TemporaryDirectory() as cache:
            runs["CLI, fresh caches (first run ever)"].append(_timed(render, {**env, "XDG_CACHE_HOME": cache}))
    phases = _phases(out, env, rounds, size)
    phases_without_ffi = _phases(out, no_ffi, phase_rounds or max(2, rounds // 2), size)
    shutil.rmtree(folder, ignore_errors=True)
    return ColdResult(runs, phases, phases_without_ffi)


def _phases(out: str, env: dict[str, str], rounds: int, size: int | None = None) -> dict[str, float]:
    samples: dict[str, list[float]] = {}
    start_samples = []
    for _ in range(rounds):
        # The interpreter's own start-up, before the script's first line.
        start_samples.append(_timed([sys.executable, "-c", "pass"], env))
        command = [sys.executable, str(SCRIPTS / "cold_phases.py"), out] + ([str(size)] if size else [])
        result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
        if result.returncode != 0:
            raise RuntimeError(f"cold_phases.py failed: {result.stderr.strip()[-400:]}")
        for name, seconds in json.loads(result.stdout.strip().splitlines()[-1]).items():
            samples.setdefault(name, []).append(seconds)
    phases = {"Python interpreter start": statistics.median(start_samples)}
    phases.update({name: statistics.median(values) for name, values in samples.items()})
    return phases
