"""Run every performance benchmark of issue #7 and print a table of medians and ratios.

    pip install -e '.[bench]'          # the peers (moderngl, pygfx) and matplotlib
    python -m benchmarks               # everything, ~25 min on 2 cores (docs/performance.md)
    python -m benchmarks --quick       # smaller and fewer, ~19 min (the 10M-triangle memory table ~6, the A/B scripts ~10)
    python -m benchmarks --only warm,cold
    python -m benchmarks --smoke       # does every benchmark still run? ~20 s; numbers mean nothing

Results: markdown tables on stdout, and in --out (default benchmarks/results/):
results.md, results.json, scaling_triangles.png, scaling_pixels.png.
Absolute times are specific to this machine and its load; the ratios, measured side by
side in one run, are what carries over.

--smoke runs every phase above and the standalone benchmarks (bench_specialization.py,
bench_reference.py, golden_noise.py) once each, on tiny inputs (meshes of at most 2K
triangles, 32-64 px images, one round), with the peers that are installed (moderngl and
pygfx come with the [bench] extra; without it they are left out and named), and ends with
one line saying what ran. It writes into a temporary folder (or --out), never into docs/.
tests/test_benchmarks.py runs it, so that a benchmark the code moved away from fails a test
instead of rotting until the next real run.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

SECTIONS = ("warm", "depth", "breakdown", "cold", "batch", "memory", "scaling", "dataset", "shadows")
REAL_ONLY = ("callgrind",)  # sections of a real run only (the smoke run has a script of that name instead)
HERE = Path(__file__).resolve().parent
# --smoke only: the standalone benchmarks, each with its own smallest arguments. None of
# them is given an output file (bench_specialization.py --output would rewrite docs/).
SMOKE_SCRIPTS = {
    "specialization": ("bench_specialization.py", "--size", "64", "--frames", "1"),
    "reference": ("bench_reference.py", "--size", "32", "--triangles", "20", "200", "--repeat", "1"),
    "golden_noise": ("golden_noise.py", "--smoke"),
    "gif_palette": ("gif_palette.py", "--smoke"),
    "loading": ("bench_loading.py", "--smoke"),
    "antialiasing": ("bench_antialiasing.py", "--smoke"),
    "live": ("bench_live.py", "--smoke"),
    "callgrind": ("scripts/callgrind_frames.py", "ours", "--smoke"),
    "ab_issue21": ("scripts/ab_issue21.py", "both", "--smoke"),
    "ab_issue29": ("scripts/ab_issue29.py", "frame-memory", "--smoke"),
    "ab_issue29_start_up": ("scripts/ab_issue29.py", "start-up", "--smoke"),
    "ab_issue29_frame_plans": ("scripts/ab_issue29.py", "frame-plans", "--smoke"),
    "ab_issue29_turned_away": ("scripts/ab_issue29.py", "turned-away", "--smoke"),
    "ab_issue29_chunks": ("scripts/ab_issue29.py", "chunks", "--smoke"),
    "ab_issue29_batch_parts": ("scripts/ab_issue29.py", "batch-parts", "--smoke"),
    "ab_issue29_kept_frames": ("scripts/ab_issue29.py", "kept-frames", "--smoke"),
    "ab_issue29_fresh_meshes": ("scripts/ab_issue29.py", "fresh-meshes", "--smoke"),
    "ab_issue29_frames_in_flight": ("scripts/ab_issue29.py", "frames-in-flight", "--smoke"),
    "ab_issue29_chunk_order": ("scripts/ab_issue29.py", "chunk-order", "--smoke"),
    "ab_issue29_thread_cpu": ("scripts/ab_issue29.py", "thread-cpu", "--smoke"),
    "ab_issue29_output_folders": ("scripts/ab_issue29.py", "output-folders", "--smoke"),
    "ab_issue29_crease_split": ("scripts/ab_issue29.py", "crease-split", "--smoke"),
    "ab_issue29_encoder_threads": ("scripts/ab_issue29.py", "encoder-threads", "--smoke"),
    "ab_issue29_dask_saturation": ("scripts/ab_issue29.py", "dask-saturation", "--smoke"),
    "ab_issue29_dask_client": ("scripts/ab_issue29.py", "dask-client", "--smoke"),
    "ab_issue29_per_mesh": ("scripts/ab_issue29.py", "per-mesh", "--smoke"),
    "ab_issue29_files_beside": ("scripts/ab_issue29.py", "files-beside", "--smoke"),
    "ab_issue29_spread_folders": ("scripts/ab_issue29.py", "spread-folders", "--smoke"),
    "ab_issue29_poll_gap": ("scripts/ab_issue29.py", "poll-gap", "--smoke"),
    "ab_issue29_vertex_cache": ("scripts/ab_issue29.py", "vertex-cache", "--smoke"),
    "ab_issue29_mesh_cache": ("scripts/ab_issue29.py", "mesh-cache", "--smoke"),
    "ab_issue29_mesh_cache_many": ("scripts/ab_issue29.py", "mesh-cache-many", "--smoke"),
    "frame_timeline": ("scripts/frame_timeline.py", "run", "--smoke"),
    "hostile_files": ("scripts/hostile_files.py", "--smoke"),  # (its full run feeds docs/reliability.md: by hand)
}
# A real run also runs the standalone benchmarks whose figures docs/performance.md quotes,
# with their own default sizes, so that one command gives every figure of that page
# (specialization, reference and golden_noise feed other pages: run them by hand).
# "callgrind" is a section of its own in a real run (valgrind around the frames: callgrind.py).
# frame_timeline.py runs under `perf record -a` (root or perf_event_paranoid <= -1): by hand.
REAL_SCRIPTS = {
    "loading": ("bench_loading.py",),
    "antialiasing": ("bench_antialiasing.py",),
    "live": ("bench_live.py",),
    "ab_issue21": ("scripts/ab_issue21.py", "both"),
    "ab_issue29": ("scripts/ab_issue29.py", "frame-memory"),
    "ab_issue29_start_up": ("scripts/ab_issue29.py", "start-up"),
    "ab_issue29_frame_plans": ("scripts/ab_issue29.py", "frame-plans"),
    "ab_issue29_turned_away": ("scripts/ab_issue29.py", "turned-away"),
    "ab_issue29_chunks": ("scripts/ab_issue29.py", "chunks", "--rounds", "5"),
    "ab_issue29_batch_parts": ("scripts/ab_issue29.py", "batch-parts", "--rounds", "5"),
    "ab_issue29_kept_frames": ("scripts/ab_issue29.py", "kept-frames", "--rounds", "6"),
    "ab_issue29_fresh_meshes": ("scripts/ab_issue29.py", "fresh-meshes", "--size", "256", "--rounds", "10"),
    "ab_issue29_frames_in_flight": ("scripts/ab_issue29.py", "frames-in-flight", "--size", "256", "--rounds", "8"),
    "ab_issue29_chunk_order": ("scripts/ab_issue29.py", "chunk-order", "--size", "256", "--rounds", "10"),
    "ab_issue29_thread_cpu": ("scripts/ab_issue29.py", "thread-cpu", "--size", "256", "--rounds", "3"),
    "ab_issue29_crease_split": ("scripts/ab_issue29.py", "crease-split", "--rounds", "12"),
    "ab_issue29_encoder_threads": ("scripts/ab_issue29.py", "encoder-threads", "--size", "256", "--rounds", "16"),
    "ab_issue29_dask_saturation": ("scripts/ab_issue29.py", "dask-saturation", "--size", "256", "--rounds", "8"),
    "ab_issue29_dask_client": ("scripts/ab_issue29.py", "dask-client", "--size", "256", "--rounds", "12"),
    "ab_issue29_per_mesh": ("scripts/ab_issue29.py", "per-mesh", "--size", "256", "--rounds", "6"),
    "ab_issue29_files_beside": ("scripts/ab_issue29.py", "files-beside", "--size", "256", "--rounds", "6"),
    "ab_issue29_spread_folders": ("scripts/ab_issue29.py", "spread-folders", "--size", "256", "--rounds", "8"),
    "ab_issue29_poll_gap": ("scripts/ab_issue29.py", "poll-gap", "--size", "256", "--rounds", "8"),
    "ab_issue29_vertex_cache": ("scripts/ab_issue29.py", "vertex-cache", "--size", "512", "--rounds", "16"),
    "ab_issue29_mesh_cache": ("scripts/ab_issue29.py", "mesh-cache", "--size", "256", "--rounds", "12", "--views", "12"),
    "ab_issue29_mesh_cache_many": ("scripts/ab_issue29.py", "mesh-cache-many", "--size", "256", "--rounds", "5", "--views", "12"),
}


@dataclasses.dataclass(frozen=True)
class Settings:
    """Sizes and repetitions of one kind of run."""

    warm_sizes: tuple[int, ...]
    warm_rounds: int
    warm_frames: int
    breakdown_size: int
    breakdown_rounds: int
    breakdown_frames: int
    cold_rounds: int
    batch_frames: int
    batch_size: int
    memory_triangles: int
    memory_size: int
    memory_runs: int
    scaling_counts: tuple[int, ...]
    scaling_sides: tuple[int, ...]
    scaling_rounds: int
    scaling_frames: int
    # What only the smoke run changes (the defaults are the real runs').
    tiny: bool = False  # scenes.py's tiny meshes instead of the 10K torus, bunny and 1.3M sphere
    scaling_size: int = 512  # image side of the triangle curve
    thread_frames: int = 5  # per-thread CPU: at least this many frames ...
    thread_seconds: float = 1.0  # ... and this long (the kernel counts CPU time in 10 ms ticks)
    cold_size: int | None = None  # image side of the cold CLI renders (None: the CLI's 512)
    cold_fill_caches: bool = True  # an untimed first run of each cold variant
    cold_phase_rounds: int | None = None  # rounds of the phases without prebuilt FFI (None: max(2, rounds // 2))
    # benchmarks/dataset.py: meshes × views to PNG files (4 meshes; the tiny run: 2 builtins)
    dataset_views: int = 48
    dataset_sizes: tuple[int, ...] = (256, 512)
    dataset_passes: int = 3
    file_triangles: int = 10_000_000  # memory: the binary STL and PLY, the OBJ and the GLB loaded and rendered (issue #29: < 3x their arrays)
    shadow_sizes: tuple[int, ...] = (512,)  # benchmarks/shadows.py: a shadowed frame against pyrender and pygfx


FULL = Settings(
    warm_sizes=(512, 1024), warm_rounds=7, warm_frames=3,
    breakdown_size=512, breakdown_rounds=8, breakdown_frames=3,
    cold_rounds=10,
    batch_frames=360, batch_size=512,
    memory_triangles=1_300_000, memory_size=512, memory_runs=6,
    scaling_counts=(10_000, 30_000, 100_000, 300_000, 1_000_000, 3_000_000),
    scaling_sides=(128, 256, 512, 1024, 2048), scaling_rounds=4, scaling_frames=2,
)
QUICK = dataclasses.replace(
    FULL,
    warm_sizes=(512,), warm_rounds=2, warm_frames=2,
    breakdown_rounds=2, breakdown_frames=2,
    cold_rounds=4,
    batch_frames=60,
    memory_runs=1,
    scaling_counts=(10_000, 100_000, 1_000_000), scaling_sides=(256, 512, 1024), scaling_rounds=2, scaling_frames=1,
    dataset_views=12, dataset_sizes=(256,), dataset_passes=3,  # a median: one 48-frame pass swings ±0.1 in its ratios (docs/performance.md)
)
# Every step once, on tiny inputs.
SMOKE = Settings(
    warm_sizes=(64,), warm_rounds=1, warm_frames=1,
    breakdown_size=64, breakdown_rounds=1, breakdown_frames=1,
    cold_rounds=1,
    batch_frames=5, batch_size=64,  # 5 turns of 72°: 90° ones would show the cube the same each time
    memory_triangles=2_000, memory_size=64, memory_runs=1,
    scaling_counts=(200, 2_000), scaling_sides=(32, 64), scaling_rounds=1, scaling_frames=1,
    tiny=True, scaling_size=64, thread_frames=1, thread_seconds=0.1,
    cold_size=64, cold_fill_caches=False, cold_phase_rounds=1,
    dataset_views=3, dataset_sizes=(32,), dataset_passes=1, file_triangles=2_000, shadow_sizes=(64,),
)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n\n")[0])
    modes = parser.add_mutually_exclusive_group()
    modes.add_argument("--quick", action="store_true", help="smaller sizes, fewer rounds (~19 min on 2 cores)")
    modes.add_argument(
        "--smoke", action="store_true",
        help="every benchmark (these sections and the standalone scripts) once on tiny inputs, in seconds; "
        "checks that they run, the numbers mean nothing",
    )
    parser.add_argument(
        "--only", help=f"comma-separated sections: {', '.join(SECTIONS + REAL_ONLY + tuple(REAL_SCRIPTS))} "
        f"(with --smoke: {', '.join(SECTIONS + tuple(SMOKE_SCRIPTS))})"
    )
    parser.add_argument("--no-pygfx", action="store_true", help="leave pygfx out of the warm table")
    parser.add_argument(
        "--out", type=Path, default=None,
        help="output folder (default: benchmarks/results/; with --smoke a temporary folder, removed afterwards)",
    )
    parser.add_argument(
        "--scratch", type=Path, default=None,
        help="folder the dataset section writes its datasets in (a new folder there, removed at the end; "
        "default: the system's temporary folder). Its table states how long a new file took there",
    )
    args = parser.parse_args(argv)
    begun = time.perf_counter()
    smoke = args.smoke
    known = SECTIONS + (tuple(SMOKE_SCRIPTS) if smoke else REAL_ONLY + tuple(REAL_SCRIPTS))
    chosen = known if not args.only else tuple(s.strip() for s in args.only.split(","))
    unknown = set(chosen) - set(known)
    if unknown:
        parser.error(f"unknown sections: {', '.join(sorted(unknown))}")
    os.environ.setdefault("NODEVICE_SELECT", "1")
    # Every file is parsed and every order made where a benchmark times them (loading, memory,
    # hostile files), and nothing is written into the user's cache folder; the dataset section
    # keeps a mesh cache of its own, in its scratch folder (dataset.py, mesh_cache_in).
    from wgpu_shading.assets.disk_cache import CACHE_VARIABLE

    os.environ[CACHE_VARIABLE] = "off"

    from wgpu_shading import Renderer

    from . import report
    from .measure import machine_description

    s = SMOKE if smoke else QUICK if args.quick else FULL
    # A real run needs the peers (the [bench] extra); a smoke run leaves out those it cannot run.
    skipped: list[str] = []
    moderngl = not smoke or _peer_usable("moderngl", skipped)
    pygfx = not args.no_pygfx and (not smoke or _peer_usable("pygfx", skipped))
    pyrender = _pyrender_usable(skipped) if {"depth", "dataset", "shadows"} & set(chosen) else False
    out = args.out or (Path(tempfile.mkdtemp(prefix="wgpu-shading-bench-smoke-")) if smoke else HERE / "results")
    ran: list[str] = []
    failed: list[str] = []

    renderer = Renderer()
    started = time.perf_counter()
    mode = " --smoke" if smoke else " --quick" if args.quick else ""
    results: dict[str, object] = {
        "command": "python -m benchmarks" + mode + (f" --only {args.only}" if args.only else ""),
        "machine": machine_description(),
        "load_average_at_start": os.getloadavg(),
    }
    title = " (smoke run: tiny inputs, one round; the numbers mean nothing)" if smoke else ""
    print(f"# wgpu-shading performance{title}\n\nmachine: {results['machine']}\n", flush=True)
    labels: dict[str, dict] = {"memory": {}, "scaling": {}}  # table titles: the defaults name the real runs' inputs
    if smoke:
        from .scenes import TINY_TORUS_SEGMENTS

        labels = {"memory": {"size": s.memory_size}, "scaling": {"sphere_size": s.scaling_size, "torus": str(2 * TINY_TORUS_SEGMENTS**2)}}
        results["table_labels"] = labels

    results["section_loads"] = {}

    def step(name: str):
        return _step(name, smoke, ran, failed, results["section_loads"])

    if "warm" in chosen:
        with step("warm"):
            from .warm import run_warm

            rows = run_warm(
                renderer, s.warm_sizes, rounds=s.warm_rounds, frames=s.warm_frames, pygfx=pygfx, moderngl=moderngl, tiny=s.tiny
            )
            print(report.warm_table(rows), flush=True)
            results["warm"] = rows
    if "depth" in chosen:
        with step("depth"):
            from .depth import depth_table, run_depth

            rows = run_depth(renderer, s.warm_sizes, rounds=s.warm_rounds, frames=s.warm_frames, tiny=s.tiny, pyrender=pyrender)
            print(depth_table(rows), flush=True)
            results["depth"] = rows
    if "breakdown" in chosen:
        with step("breakdown"):
            from .warm import run_breakdown

            rows = run_breakdown(
                renderer, s.breakdown_size, rounds=s.breakdown_rounds, frames=s.breakdown_frames, moderngl=moderngl,
                tiny=s.tiny, thread_frames=s.thread_frames, thread_seconds=s.thread_seconds,
            )
            print(report.breakdown_table(rows), flush=True)
            results["breakdown"] = rows
    if "cold" in chosen:
        with step("cold"):
            from .cold import run_cold

            cold = run_cold(
                rounds=s.cold_rounds, size=s.cold_size, moderngl=moderngl, fill_caches=s.cold_fill_caches,
                phase_rounds=s.cold_phase_rounds,
            )
            print(report.cold_table(cold), flush=True)
            results["cold"] = cold
    if "batch" in chosen:
        with step("batch"):
            from .batch import run_batch

            batch = run_batch(
                renderer, frames=s.batch_frames, size=s.batch_size, passes=2, tiny=s.tiny,
                thread_frames=s.thread_frames, thread_seconds=s.thread_seconds,
            )
            print(report.batch_table(batch), flush=True)
            results["batch"] = batch
    if "memory" in chosen:
        with step("memory"):
            from .memory import FILE_FORMATS, run_file_memory, run_memory

            memory = run_memory(s.memory_triangles, s.memory_size, runs=s.memory_runs)
            print(report.memory_table(memory, **labels["memory"]), flush=True)
            results["memory"] = memory
            file_memory = [run_file_memory(s.file_triangles, s.memory_size, file_format) for file_format in FILE_FORMATS]
            print(report.file_memory_table(file_memory), flush=True)
            results["file_memory"] = file_memory
    if "scaling" in chosen:
        with step("scaling"):
            from .scaling import pixel_curve, triangle_curve
            from .scenes import TINY_TORUS_SEGMENTS

            curve = {"rounds": s.scaling_rounds, "frames": s.scaling_frames, "moderngl": moderngl}
            scaling = {
                "triangles": triangle_curve(renderer, s.scaling_counts, size=s.scaling_size, **curve),
                "pixels": pixel_curve(renderer, s.scaling_sides, segments=TINY_TORUS_SEGMENTS if s.tiny else 72, **curve),
            }
            print(report.scaling_table(scaling, **labels["scaling"]), flush=True)
            results["scaling"] = scaling
    if "dataset" in chosen:
        with step("dataset"):
            from .dataset import SMOKE_MESHES, default_meshes, run_dataset_benchmark, table

            meshes = list(SMOKE_MESHES) if s.tiny else default_meshes()
            dataset = run_dataset_benchmark(
                renderer, meshes, s.dataset_views, s.dataset_sizes, s.dataset_passes, chunk=2 if s.tiny else 16,
                pyrender=pyrender, scratch_parent=args.scratch,
            )
            print("## Dataset rendering (benchmarks/dataset.py)\n\n" + table(dataset) + "\n", flush=True)
            results["dataset"] = dataset
    if "shadows" in chosen:
        with step("shadows"):
            from .shadows import run_shadows, shadows_table

            shadows = run_shadows(renderer, s.shadow_sizes, rounds=s.warm_rounds, frames=s.warm_frames, tiny=s.tiny,
                                  pyrender=pyrender, pygfx=pygfx)
            print(shadows_table(shadows), flush=True)
            results["shadows"] = shadows
    if "callgrind" in chosen and not smoke:
        from .callgrind import callgrind_table, callgrind_unusable, run_callgrind

        reason = callgrind_unusable()
        if reason is not None:
            skipped.append(f"the instruction counts ({reason})")
        else:
            with step("callgrind"):
                counts = run_callgrind(moderngl=moderngl)
                print(callgrind_table(counts), flush=True)
                results["callgrind"] = counts
    for name, (script, *script_args) in (SMOKE_SCRIPTS if smoke else REAL_SCRIPTS).items():
        if name in chosen:
            with step(name):
                results.setdefault("scripts", {})[name] = _run_script(script, script_args)

    elapsed = time.perf_counter() - started
    results["seconds"] = elapsed
    results["load_average_at_end"] = os.getloadavg()
    with step("report"):  # results.md, results.json, the scaling plots
        out.mkdir(parents=True, exist_ok=True)
        markdown = report.everything(results)
        (out / "results.md").write_text(markdown)
        (out / "results.json").write_text(json.dumps(_plain(results), indent=1))
        if "scaling" in results:
            report.plot_scaling(results["scaling"], out)
    if not smoke:
        if skipped:
            print(f"skipped: {'; '.join(skipped)}", file=sys.stderr)
        print(f"\n{elapsed / 60:.1f} min; load average {results['load_average_at_start']} → "
              f"{results['load_average_at_end']}; written to {out}", file=sys.stderr)
        return 0
    if "scaling" in results and not _importable("matplotlib"):
        skipped.append("the scaling plots (matplotlib not installed)")
    if args.out is None:
        shutil.rmtree(out, ignore_errors=True)
        where = "results.md and results.json written to a temporary folder, removed"
    else:
        where = f"results written to {out}"
    print(f"smoke: ran {len(ran)} steps in {time.perf_counter() - begun:.1f} s: {', '.join(ran) or 'none'}")
    print(f"smoke: skipped: {'; '.join(skipped) if skipped else 'nothing'}")
    print(f"smoke: {'FAILED: ' + ', '.join(failed) if failed else 'all ran'}; {where}", flush=True)
    return 1 if failed else 0


@contextlib.contextmanager
def _step(name: str, smoke: bool, ran: list[str], failed: list[str], loads: dict | None = None):
    """One benchmark. In a smoke run a failure is printed and counted, and the others still
    run (so one run shows everything that rotted); in a real run it stops the run. Every
    section ends with the machine's load average over it (its figures are read with it)."""
    start, cpu = time.perf_counter(), time.process_time()
    load_before = os.getloadavg()
    if smoke:
        print(f"<!-- smoke: {name} -->", flush=True)
    try:
        yield
    except Exception:
        if not smoke:
            raise
        traceback.print_exc()
        print(f"smoke: {name} FAILED (traceback on stderr)\n", flush=True)
        failed.append(name)
    else:
        ran.append(f"{name} ({time.perf_counter() - start:.1f} s)")
        load_after = os.getloadavg()
        line = (
            f"_{name}: {time.perf_counter() - start:.0f} s; load average (1 min) {load_before[0]:.1f} at the start, "
            f"{load_after[0]:.1f} at the end, on {os.cpu_count()} cores._\n"
        )
        print(line, flush=True)
        if loads is not None:
            loads[name] = (load_before[0], load_after[0], time.perf_counter() - start, time.process_time() - cpu)


def _run_script(script: str, script_args: list[str]) -> str:
    """A standalone benchmark in its own process, as a person runs it; its tables to stdout
    (and returned, for results.md)."""
    command = [sys.executable, str(HERE / script), *script_args]
    heading = f"## {script} {' '.join(script_args)}".rstrip()
    print(heading + "\n", flush=True)
    result = subprocess.run(command, cwd=HERE.parent, capture_output=True, text=True, timeout=1800)
    print(result.stdout.rstrip() + "\n", flush=True)
    if result.returncode != 0:
        raise RuntimeError(f"{script} exited with {result.returncode}:\n{result.stderr.strip()[-2000:]}")
    return heading + "\n\n" + result.stdout.rstrip() + "\n"


def _importable(module: str) -> bool:
    return importlib.util.find_spec(module) is not None


def _peer_usable(name: str, skipped: list[str]) -> bool:
    """Can the smoke run use this peer? If not, say why in `skipped`."""
    if not _importable(name):
        skipped.append(f"the {name} peer (not installed: pip install -e '.[bench]')")
        return False
    if name == "moderngl":
        from .peers import moderngl_context

        try:
            moderngl_context()  # the one context every moderngl peer of this process uses
        except Exception as error:  # no EGL / no OpenGL 4.3 on this machine
            skipped.append(f"the moderngl peer (no headless OpenGL: {str(error).splitlines()[0]})")
            return False
    return True


def _pyrender_usable(skipped: list[str]) -> bool:
    """pyrender (the [bench] extra) with OSMesa (apt: libosmesa6)? If not, say why in `skipped`
    (a real run too: the colour + depth table needs it, the rest does not)."""
    if not _importable("pyrender"):
        skipped.append("the pyrender peer (not installed: pip install -e '.[bench]')")
        return False
    from .pyrender_peer import pyrender_unusable

    reason = pyrender_unusable()
    if reason is not None:
        skipped.append(f"the pyrender peer (no offscreen OpenGL through OSMesa: apt install libosmesa6; {reason})")
        return False
    return True


def _plain(value: object) -> object:
    """Dataclasses and tuples to JSON-friendly values."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


if __name__ == "__main__":
    sys.exit(main())
