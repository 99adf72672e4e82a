"""Cold start: process start to PNG on disk, for the CLI and its peers, in fresh processes.

Variants, interleaved round by round:
    wgpu-shading CLI            `wgpu-shading render builtin:torus -o OUT.png`
    CLI with Python's own exit  the same command through start_process() and cli.main() in
                                `python -c`, which ends with Python's teardown (the program
                                skips it once its files are closed: cli/process_end.py)
    CLI, prebuilt FFI off       the same with WGPU_SHADING_PREBUILT_FFI=0: wgpu-py's own
                                cffi start-up, i.e. the cold start before this work
    moderngl script             scripts/moderngl_torus.py: the same image with moderngl
    ..., one BLAS thread        the script with OPENBLAS_NUM_THREADS=1, which the CLI sets
                                for itself before numpy loads
    wgpu floor (+ prebuilt FFI) scripts/wgpu_floor.py: device + trivial pipeline + one
                                triangle + readback, the least any wgpu-py program does
    python + numpy              the interpreter starting and importing numpy

Disk caches (Mesa's shader cache, our FFI table, Python's bytecode) are warm, as for anyone
who has run the command once; `fresh caches` runs the CLI with an empty XDG_CACHE_HOME for
comparison. Python's bytecode: an installed package has its modules compiled (pip does it
at install), but a clone run from its source tree with PYTHONDONTWRITEBYTECODE set (as this
project's machines have it) compiles ~90 modules from source at every start, which the
peers in site-packages never do. So every variant runs with bytecode caching on, all in one
cache folder (PYTHONPYCACHEPREFIX; filled by the untimed first run), and `CLI, no bytecode
cache` shows what compiling from source costs.

Every run's CPU time (user + system of the child, from wait4's rusage) is kept beside its
wall time: on a shared machine it is far less disturbed by the neighbours.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from .measure import progress

SCRIPTS = Path(__file__).resolve().parent / "scripts"


# The same command through main(), ending with Python's usual exit (the program ends its
# process at once: cli/process_end.py).
IN_PROCESS_MAIN = (
    "import sys; from wgpu_shading.cli.process_start import start_process; start_process(); "
    "from wgpu_shading.cli.main import main; sys.exit(main(owns_process=True))"
)


def _cli() -> str:
    return shutil.which("wgpu-shading", path=str(Path(sys.executable).parent)) or "wgpu-shading"


@dataclass
class ColdResult:
    runs: dict[str, list[float]]  # variant -> seconds per run
    phases: dict[str, float]  # phase -> median seconds (prebuilt FFI on)
    phases_without_ffi: dict[str, float]
    cpu: dict[str, list[float]] = field(default_factory=dict)  # variant -> CPU seconds (user + system) per run
    phases_cpu: dict[str, float] = field(default_factory=dict)  # phase -> median CPU seconds (prebuilt FFI on)

    def median(self, variant: str) -> float:
        return statistics.median(self.runs[variant])

    def cpu_median(self, variant: str) -> float:
        return statistics.median(self.cpu[variant]) if self.cpu.get(variant) else float("nan")


def _timed(command: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(wall, CPU) seconds of one run: CPU is the child's user + system time."""
    start = time.perf_counter()
    process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _, err = process.communicate(timeout=300)
    finally:
        if process.poll() is None:
            process.kill()
    elapsed = time.perf_counter() - start
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)  # cumulative over waited-for children: take the difference
    cpu = usage.ru_utime + usage.ru_stime - _timed.children_cpu
    _timed.children_cpu = usage.ru_utime + usage.ru_stime
    if process.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed: {err.strip()[-400:]}")
    return elapsed, cpu


_timed.children_cpu = 0.0


def run_cold(
    rounds: int, *, size: int | None = None, moderngl: bool = True, fill_caches: bool = True, phase_rounds: int | None = None
) -> ColdResult:
    """size: the image side for the CLI and cold_phases.py (default: the CLI's 512);
    moderngl False leaves the moderngl script out; fill_caches False skips the untimed
    first run of each variant; phase_rounds: rounds of the phases without the prebuilt FFI
    (default max(2, rounds // 2)). The smoke run uses all four to run each step once."""
    folder = Path(tempfile.mkdtemp(prefix="wgpu-shading-cold-"))
    out = str(folder / "t.png")
    _timed.children_cpu = _children_cpu()
    env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPYCACHEPREFIX"] = str(folder / "pycache")  # bytecode for every variant, as installed packages have it
    no_bytecode = {**env, "PYTHONDONTWRITEBYTECODE": "1", "PYTHONPYCACHEPREFIX": str(folder / "no-pycache")}
    no_ffi = {**env, "WGPU_SHADING_PREBUILT_FFI": "0"}
    # What the program sets for itself before numpy loads (cli/main.py console_main), given
    # to a peer and to the in-process variant, so that each difference is shown on its own.
    one_blas_thread = {**env, "OPENBLAS_NUM_THREADS": "1"}
    arguments = ["render", "builtin:torus", "-o", out, "-q"] + (["--size", str(size)] if size else [])
    render = [_cli(), *arguments]
    moderngl_script = [sys.executable, str(SCRIPTS / "moderngl_torus.py"), out] + ([str(size)] if size else [])
    variants = {
        "wgpu-shading CLI": (render, env),
        "CLI with Python's own exit (main() after start_process())": ([sys.executable, "-c", IN_PROCESS_MAIN, *arguments], env),
        "CLI, no bytecode cache (a source tree with PYTHONDONTWRITEBYTECODE)": (render, no_bytecode),
        "CLI, prebuilt FFI off (wgpu-py's own cffi start-up)": (render, no_ffi),
        "moderngl script": (moderngl_script, env),
        "moderngl script, one BLAS thread (OPENBLAS_NUM_THREADS=1, as the CLI)": (moderngl_script, one_blas_thread),
        "wgpu floor + prebuilt FFI": ([sys.executable, str(SCRIPTS / "wgpu_floor.py"), "--prebuilt-ffi"], env),
        "wgpu floor (plain wgpu-py)": ([sys.executable, str(SCRIPTS / "wgpu_floor.py")], env),
        "python + import numpy": ([sys.executable, "-c", "import numpy"], env),
    }
    if not moderngl:
        variants = {name: variant for name, variant in variants.items() if not name.startswith("moderngl")}
    if fill_caches:
        for command, variant_env in variants.values():  # fill disk caches (and the bytecode); not timed
            _timed(command, variant_env)
    else:  # at least the bytecode, or the first timed run of each variant would compile it
        _timed(render, env)
    runs: dict[str, list[float]] = {name: [] for name in variants}
    cpu: dict[str, list[float]] = {name: [] for name in variants}
    names = list(variants)
    for round_index in range(rounds):
        progress(f"cold start: round {round_index + 1}/{rounds}")
        shift = round_index % len(names)
        for name in names[shift:] + names[:shift]:
            command, variant_env = variants[name]
            wall, seconds = _timed(command, variant_env)
            runs[name].append(wall)
            cpu[name].append(seconds)
    # First run ever: Mesa's shader cache and our FFI table both live under XDG_CACHE_HOME.
    fresh = "CLI, fresh caches (first run ever)"
    runs[fresh], cpu[fresh] = [], []
    for _ in range(max(1, rounds // 4)):
        with tempfile.TemporaryDirectory() as cache:
            wall, seconds = _timed(render, {**env, "XDG_CACHE_HOME": cache, "PYTHONPYCACHEPREFIX": str(Path(cache) / "pycache")})
            runs[fresh].append(wall)
            cpu[fresh].append(seconds)
    phases, phases_cpu = _phases(out, one_blas_thread, rounds, size)
    phases_without_ffi, _ = _phases(out, {**no_ffi, "OPENBLAS_NUM_THREADS": "1"}, phase_rounds or max(2, rounds // 2), size)
    shutil.rmtree(folder, ignore_errors=True)
    return ColdResult(runs, phases, phases_without_ffi, cpu, phases_cpu)


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _phases(out: str, env: dict[str, str], rounds: int, size: int | None = None) -> tuple[dict[str, float], dict[str, float]]:
    """Median wall and CPU seconds of each phase (scripts/cold_phases.py measures both)."""
    samples: dict[str, list[float]] = {}
    cpu_samples: dict[str, list[float]] = {}
    start_samples, start_cpu = [], []
    for _ in range(rounds):
        # The interpreter's own start-up, before the script's first line.
        wall, seconds = _timed([sys.executable, "-c", "pass"], env)
        start_samples.append(wall)
        start_cpu.append(seconds)
        command = [sys.executable, str(SCRIPTS / "cold_phases.py"), out] + ([str(size)] if size else [])
        result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
        if result.returncode != 0:
            raise RuntimeError(f"cold_phases.py failed: {result.stderr.strip()[-400:]}")
        _timed.children_cpu = _children_cpu()
        measured = json.loads(result.stdout.strip().splitlines()[-1])
        for name, seconds in measured["wall"].items():
            samples.setdefault(name, []).append(seconds)
        for name, seconds in measured["cpu"].items():
            cpu_samples.setdefault(name, []).append(seconds)
    phases = {"Python interpreter start": statistics.median(start_samples)}
    phases.update({name: statistics.median(values) for name, values in samples.items()})
    phases_cpu = {"Python interpreter start": statistics.median(start_cpu)}
    phases_cpu.update({name: statistics.median(values) for name, values in cpu_samples.items()})
    return phases, phases_cpu
