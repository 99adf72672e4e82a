"""Dataset rendering: frames per second for meshes × views written to PNG files.

    python -m benchmarks.dataset            # 4 meshes × 48 views, 256² and 512², 3 passes (~4 min)
    python -m benchmarks.dataset --smoke    # 2 tiny meshes × 4 views, 1 pass (what the tests run)

Modes, every one writing the same colour PNGs (zlib level 1) of the same 192 jobs:
    naive            for each mesh: build its scene; for each view: render, wait, write the PNG
    in-process       render_dataset(workers=1): chunks, pipelined frames on 2 lavapipe devices,
                     PNG encoding on 2 threads
    in-process, 1 device   the same with render_many(parallel=1): what one Dask worker runs
    dask 1 worker    render_dataset on a warm LocalCluster of 1 process (LP_NUM_THREADS = cores),
                     through a Client held across the runs (client=), as a notebook or service
                     holds one; `batch --scheduler` connects and closes a client a run, ~17 ms
                     more a run here (scripts/ab_issue29.py dask-client)
    dask 2 workers   a warm LocalCluster of 2 processes (LP_NUM_THREADS = cores / 2 each), the same
    naive, colour + depth     the naive loop with render_frame(depth=True), also writing the depth
                     as float32 .npy (np.save)
    batch, colour + depth     render_dataset(workers=1) with Outputs(depth="npy"): `wgpu-shading batch
                     --depth npy`, the same PNG and .npy files (and its records and cameras.json)
    batch, colour + depth, first run   the same with an empty mesh cache (below), as the first
                     run over these meshes on a machine: every file parsed, every order made
    pyrender, colour + depth  the naive colour + depth loop with pyrender (OSMesa) instead
                     (benchmarks/pyrender_peer.py); only when pyrender can run here

Besides the modes, every pass times the stages of the colour + depth batch alone
(benchmarks/dataset_stages.py: loading, scenes, render + readback, encoding, writing).

The mesh cache (assets/disk_cache.py: each file's Mesh and each mesh's vertex-cache order,
kept from one process to the next) is a folder of the scratch folder, filled before the
timing starts, as anyone's is after a first run over the same meshes (as Mesa's shader
cache and Python's bytecode are in the cold-start benchmark); every mode uses it but the
first run's, which starts from an empty folder each time. The user's own cache folder is
neither read nor written.

Dask's clusters are started (and warmed by one small batch: worker start, plugin, pipeline
compilation) before timing; their start-up is reported separately.

Dask's per-frame overhead is measured within each run, so the load other processes put on the
machine cancels out: wall time minus the time the worker spent inside its chunks (loading,
rendering, writing), per frame, for 1 worker, less the same quantity of the in-process run
(skip checks, cameras.json, report), as a share of the worker's time per frame. What is
left is Dask's: submitting the chunks, the scheduler's round trip between them, the
records' way back (the client's connection is held across runs, as above). The time
inside chunks is the union of each worker's spans of work (run.busy_time): a Dask worker
renders its next chunk while the last one waits for its writes, and until issue #29's
tenth pass those overlaps were counted twice, which made Dask's overhead read low.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import sys
import tempfile
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Iterator

import numpy as np
from PIL import Image

from wgpu_shading import Renderer
from wgpu_shading.assets.disk_cache import CACHE_VARIABLE
from wgpu_shading.dataset import Outputs, mesh_jobs, render_dataset, turntable_views
from wgpu_shading.dataset.output_folder import make_output_folder
from wgpu_shading.dataset.views import base_scene, job_scene

from .dataset_stages import STAGES, StageTimes, time_stages

# The model collection beside the repository (../shared/models), also from a worktree deeper down.
MODELS = next(
    (parent / "shared" / "models" for parent in Path(__file__).resolve().parents if (parent / "shared" / "models").is_dir()),
    Path("../shared/models"),
)
REAL_MESHES = ("stanford-bunny.obj", "teapot.obj", "suzanne.obj", "cow.obj")
BUILTIN_MESHES = ("builtin:torus", "builtin:sphere", "builtin:cube", "builtin:torus?segments=96")
SMOKE_MESHES = ("builtin:torus?segments=16", "builtin:cube")
FIRST_RUN = "batch, colour + depth, first run"  # the batch with an empty mesh cache
MODES = (
    "naive", "in-process", "in-process, 1 device", "dask 1 worker", "dask 2 workers",
    "naive, colour + depth", "batch, colour + depth", FIRST_RUN, "pyrender, colour + depth",
)
LOOPS = ("naive", "naive, colour + depth", "pyrender, colour + depth")  # plain loops: no chunks to time inside
# What the colour + depth batch is measured against (issue #29: its time inside chunks within
# 1.5× this): render_many of the same jobs' scenes, built and uploaded beforehand, each frame
# let go once read back (as the batch lets its frames go once written). Timed in the same
# rotation as the modes, so both figures come from the same passes under the same load.
FRAMES_ALONE = "render + readback, colour + depth"


@dataclass
class DatasetResult:
    meshes: list[str]
    views: int
    size: int
    seconds: dict[str, list[float]] = field(default_factory=dict)  # mode → seconds per pass
    outside: dict[str, list[float]] = field(default_factory=dict)  # mode → wall − time inside chunks, per pass
    busy: dict[str, list[float]] = field(default_factory=dict)  # mode → time inside chunks, per pass
    cpu: dict[str, list[float]] = field(default_factory=dict)  # mode → CPU seconds (this process + workers), per pass
    dask_startup: dict[str, float] = field(default_factory=dict)  # workers → seconds to a warm cluster
    stages: StageTimes = field(default_factory=StageTimes)  # the colour + depth batch's stages alone
    load_average: list[float] = field(default_factory=list)  # 1-minute load average after each pass
    new_file_us: list[float] = field(default_factory=list)  # creating an empty file in the scratch folder, before each pass
    new_file_spread_us: list[float] = field(default_factory=list)  # the same in a mesh folder made as the batch makes them

    @property
    def frames(self) -> int:
        return len(self.meshes) * self.views

    def fps(self, mode: str) -> float:
        return self.frames / statistics.median(self.seconds[mode])

    def ratio(self, mode: str, other: str) -> float:
        """Time per frame of `mode` ÷ that of `other` (medians of the passes)."""
        return self.fps(other) / self.fps(mode)

    def cpu_ratio(self, mode: str, other: str) -> float:
        return self.cpu_ms_per_frame(mode) / self.cpu_ms_per_frame(other)

    def cpu_ms_per_frame(self, mode: str) -> float:
        return 1000.0 * statistics.median(self.cpu[mode]) / self.frames

    def dask_overhead_ms(self) -> float:
        """Milliseconds a frame spends outside the worker's chunks on Dask, beyond in-process."""
        difference = statistics.median(self.outside["dask 1 worker"]) - statistics.median(self.outside["in-process, 1 device"])
        return 1000.0 * difference / self.frames

    def dask_overhead_percent(self) -> float:
        per_frame_busy = 1000.0 * statistics.median(self.busy["dask 1 worker"]) / self.frames
        return 100.0 * self.dask_overhead_ms() / per_frame_busy


def default_meshes() -> list[str]:
    if all((MODELS / name).exists() for name in REAL_MESHES):
        return [str(MODELS / name) for name in REAL_MESHES]
    return list(BUILTIN_MESHES)


def naive_loop(renderer: Renderer, jobs, out_dir: Path, level: int, *, depth: bool = False, pyrender=None) -> None:
    """What a user writes first: one scene after the other, render, then write the files
    (Pillow's PNG). depth: colour and eye depth, the depth written as float32 .npy like
    `batch --depth npy`; pyrender: a PyrenderScenes draws instead of `renderer` (colour and
    depth, like pyrender's render())."""
    bases: dict = {}
    for job in jobs:
        key = job.load_key()
        if key not in bases:
            bases[key] = base_scene(job)
        scene = job_scene(bases[key], job)
        distances = None
        if pyrender is not None:
            image, distances = pyrender.render(scene)
        elif depth:
            frame = renderer.render_frame(scene, depth=True)
            image, distances = frame.color, frame.depth
        else:
            image = renderer.render(scene)
        folder = out_dir / job.folder
        folder.mkdir(parents=True, exist_ok=True)
        Image.fromarray(image).save(folder / f"{job.name}.png", compress_level=level)
        if depth or pyrender is not None:
            np.save(folder / f"{job.name}_depth.npy", np.asarray(distances, np.float32))


PROBE_FILES = 100  # empty files created before each pass to time a file's creation


def new_file_micros(folder: Path, count: int = PROBE_FILES, spread: bool = False) -> float:
    """Median µs to create (and close) an empty file in a new subfolder of `folder`. The
    files are left there: removing them would make the next creations slower (below).
    spread: in a subfolder of a new output folder made as render_dataset makes one, i.e.
    where a dataset's mesh folder would be (dataset/output_folder.py), instead.

    Why it is measured: on ext4 without a journal (this VM's disk) the kernel avoids
    reusing an inode freed in the last 60 s, or 6 minutes while its inode table block is
    not yet written back, and checks each free inode it passes in the block group one by
    one (fs/ext4/ialloc.c: recently_deleted, RECENTCY_MIN + RECENTCY_DIRTY; `perf record`
    puts the time in recently_deleted and find_get_block_common). After another program
    removed many files nearby (a test run, a benchmark's clean-up, the tools that keep
    their job files in /tmp) one creation took 0.2–0.86 ms here, against 0.016–0.025 ms
    in a quiet folder: each view creates 3 files, so up to 2.5 ms of kernel CPU a frame.
    """
    if spread:
        parent = Path(tempfile.mkdtemp(prefix="new-file-probe-spread-", dir=folder))
        make_output_folder(parent)  # found empty: marked as render_dataset marks its folder
        probe = parent / "mesh"
        probe.mkdir()
    else:
        probe = Path(tempfile.mkdtemp(prefix="new-file-probe-", dir=folder))
    times = []
    for index in range(count):
        start = time.perf_counter()
        os.close(os.open(probe / f"{index}", os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644))
        times.append(time.perf_counter() - start)
    return 1e6 * statistics.median(times)


def run_dataset_benchmark(
    renderer: Renderer, meshes: list[str], views: int, sizes: tuple[int, ...], passes: int, *, dask: bool = True, chunk: int = 16,
    pyrender: bool = False, scratch_parent: Path | None = None,
) -> list[DatasetResult]:
    """pyrender: also time pyrender's colour + depth loop (benchmarks/pyrender_peer.py).
    scratch_parent: the folder the datasets are written in (a new folder there, removed at
    the end; None: the system's temporary folder)."""
    scratch = Path(tempfile.mkdtemp(prefix="wgpu-shading-dataset-bench-", dir=scratch_parent))
    with mesh_cache_in(scratch / "mesh-cache"):  # (set before the clusters start: their workers inherit it)
        return _run(renderer, meshes, views, sizes, passes, dask, chunk, pyrender, scratch)


@contextmanager
def mesh_cache_in(folder: Path) -> Iterator[None]:
    """The mesh cache (assets/disk_cache.py) in `folder` for what runs inside, as before after."""
    before = os.environ.get(CACHE_VARIABLE)
    os.environ[CACHE_VARIABLE] = str(folder)
    try:
        yield
    finally:
        if before is None:
            os.environ.pop(CACHE_VARIABLE, None)
        else:
            os.environ[CACHE_VARIABLE] = before


def _run(renderer, meshes, views, sizes, passes, dask, chunk, pyrender, scratch: Path) -> list[DatasetResult]:
    from wgpu_shading.dataset.cluster import local_cluster

    results = []
    clusters = {}
    cluster_clients: dict = {}  # workers → a Client of that cluster, held across the runs
    if dask:
        from distributed import Client
    try:
        if dask:
            for workers in (1, 2):
                start = time.perf_counter()
                cluster = local_cluster(workers)
                cluster_clients[workers] = Client(cluster)
                warm = mesh_jobs([meshes[0]], turntable_views(2), Outputs(), {"size": 32})
                render_dataset(warm, scratch / f"warm{workers}", client=cluster_clients[workers], progress=False)
                clusters[workers] = (cluster, time.perf_counter() - start)
        for size in sizes:
            jobs = mesh_jobs(meshes, turntable_views(views), Outputs(), {"size": size})
            depth_jobs = mesh_jobs(meshes, turntable_views(views), Outputs(depth="npy"), {"size": size})
            result = DatasetResult(meshes=[Path(m).name for m in meshes], views=views, size=size)
            result.dask_startup = {f"{w} worker(s)": round(s, 2) for w, (_, s) in clusters.items()}
            naive_loop(renderer, jobs[:2], scratch / "warmup", 1)  # compile pipelines first
            render_dataset(jobs[:2], scratch / "warmup2", progress=False, renderer=renderer)
            runs = {
                "naive": lambda out: naive_loop(renderer, jobs, out, 1),
                "in-process": lambda out: render_dataset(jobs, out, progress=False, renderer=renderer, chunk_size=chunk),
                "in-process, 1 device": lambda out: render_dataset(jobs, out, progress=False, renderer=renderer, chunk_size=chunk, parallel=1),
                "naive, colour + depth": lambda out: naive_loop(renderer, jobs, out, 1, depth=True),
                "batch, colour + depth": lambda out: render_dataset(
                    depth_jobs, out, progress=False, renderer=renderer, chunk_size=chunk
                ),
                FIRST_RUN: lambda out: first_run(renderer, depth_jobs, out, chunk),
            }
            depth_scenes = job_scenes(depth_jobs)
            render_all(renderer, depth_scenes)  # uploads every mesh on every device first
            runs[FRAMES_ALONE] = lambda out: render_all(renderer, depth_scenes)
            if pyrender:
                from .pyrender_peer import PyrenderScenes

                scenes = PyrenderScenes()
                naive_loop(renderer, jobs[:2], scratch / "warmup3", 1, pyrender=scenes)
                runs["pyrender, colour + depth"] = lambda out: naive_loop(renderer, jobs, out, 1, pyrender=scenes)
            for workers, client in cluster_clients.items():
                runs[f"dask {workers} worker{'s' if workers > 1 else ''}"] = lambda out, c=client: render_dataset(
                    jobs, out, client=c, progress=False, chunk_size=chunk
                )
            modes = list(runs)
            for index in range(passes):
                result.new_file_us.append(new_file_micros(scratch))
                result.new_file_spread_us.append(new_file_micros(scratch, spread=True))
                # Alternating, so load changes hit every mode alike, in an order rotated from
                # pass to pass: a run's place in the sequence moved one configuration's batch
                # by up to 7 % on this machine (docs/performance.md, "Where a dataset frame goes").
                for mode in modes[index % len(modes):] + modes[: index % len(modes)]:
                    run = runs[mode]
                    out = scratch / f"{size}-{index}-{mode.replace(' ', '_').replace(',', '')}"
                    # Frames per CPU-second is throughput per busy core, which the load other
                    # processes put on a shared machine changes much less than frames/s.
                    workers_before = _workers_cpu(cluster_clients.values())
                    own_before = _own_cpu()
                    # Every mode's folder made as render_dataset makes its own (its mesh
                    # folders spread over the disk's block groups: dataset/output_folder.py),
                    # so that the loops compared write their files alike.
                    make_output_folder(out)
                    start = time.perf_counter()
                    outcome = run(out)
                    wall = time.perf_counter() - start
                    own = _own_cpu() - own_before
                    result.cpu.setdefault(mode, []).append(own + _workers_cpu(cluster_clients.values()) - workers_before)
                    result.seconds.setdefault(mode, []).append(wall)
                    if outcome is not None:
                        result.outside.setdefault(mode, []).append(wall - outcome.busy_seconds)
                        result.busy.setdefault(mode, []).append(outcome.busy_seconds)
                    if outcome is not None and outcome.failed:
                        raise RuntimeError(f"{mode}: {len(outcome.failed)} jobs failed: {next(iter(outcome.failed.values()))}")
                    # Kept until the end (the scratch folder goes then): removing each mode's
                    # files made the next mode's file creations 10-40x slower on this machine's
                    # ext4 without a journal, which skips the inodes freed in the last seconds
                    # one by one (docs/performance.md, "And the files' creation"): the cost
                    # of the benchmark's own clean-up, not of writing a dataset.
                    print(f"  … {size}² {mode}: {result.seconds[mode][-1]:.2f} s", file=sys.stderr, flush=True)
                time_stages(renderer, depth_jobs, 1, result.stages, scratch / f"{size}-{index}-stages")
                result.load_average.append(os.getloadavg()[0])
            results.append(result)
    finally:
        for client in cluster_clients.values():
            client.close()
        for cluster, _ in clusters.values():
            cluster.close(timeout=10)
        shutil.rmtree(scratch, ignore_errors=True)
    return results


def first_run(renderer: Renderer, jobs, out: Path, chunk: int):
    """The batch as on a machine that never read these meshes: an empty mesh cache (beside
    `out`), every file parsed and every vertex-cache order made (and kept) anew."""
    with mesh_cache_in(out.parent / f"{out.name}-mesh-cache"):
        return render_dataset(jobs, out, progress=False, renderer=renderer, chunk_size=chunk)


def job_scenes(jobs) -> list:
    """Each job's Scene, every mesh loaded once (the batch's load_key), as the batch builds them."""
    bases: dict = {}
    for job in jobs:
        if job.load_key() not in bases:
            bases[job.load_key()] = base_scene(job)
    return [job_scene(bases[job.load_key()], job) for job in jobs]


def render_all(renderer: Renderer, scenes: list) -> None:
    """Render + readback of `scenes` with depth, pipelined, each frame let go once read."""
    for _ in renderer.render_many(scenes, depth=True):
        pass


def _workers_cpu(clients: Iterable) -> float:
    """CPU time (user + system, every thread) of every Dask worker process."""
    return sum(sum(client.run(time.process_time).values()) for client in clients)


def _own_cpu() -> float:
    """CPU time of this process, every thread (the LocalClusters' schedulers run here too)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def table(results: list[DatasetResult]) -> str:
    cores = os.cpu_count() or 1
    lines = [
        f"frames per second, {results[0].frames} jobs ({len(results[0].meshes)} meshes × {results[0].views} views: "
        f"{', '.join(results[0].meshes)}), colour PNG at zlib level 1, median of {len(next(iter(results[0].seconds.values())))} passes; "
        f"{cores} cores",
        "",
        "| size | " + " | ".join(MODES) + " | in-process ÷ naive | Dask overhead per frame |",
        "|---|" + "---|" * (len(MODES) + 2),
    ]
    for result in results:
        cells = [f"{result.fps(mode):.1f}" if mode in result.seconds else "–" for mode in MODES]
        overhead = (
            f"{result.dask_overhead_ms():+.2f} ms ({result.dask_overhead_percent():+.1f} %)" if "dask 1 worker" in result.seconds else "–"
        )
        lines.append(f"| {result.size}² | " + " | ".join(cells) + f" | {result.fps('in-process') / result.fps('naive'):.2f}× | {overhead} |")
    if "pyrender, colour + depth" in results[0].seconds:
        lines += ["", "colour + depth (PNG + depth .npy): ours ÷ pyrender in time per frame, wall (≤ 0.5 is issue #29's "
                  "target) and CPU: " + "; ".join(
                      f"{r.size}² batch {r.ratio('batch, colour + depth', 'pyrender, colour + depth'):.2f}× "
                      f"(CPU {r.cpu_ratio('batch, colour + depth', 'pyrender, colour + depth'):.2f}×), naive loop "
                      f"{r.ratio('naive, colour + depth', 'pyrender, colour + depth'):.2f}× "
                      f"(CPU {r.cpu_ratio('naive, colour + depth', 'pyrender, colour + depth'):.2f}×)" for r in results)]
    lines += [
        "",
        "milliseconds per frame inside chunks (loading, rendering, writing; summed over workers) / outside them",
        "(planning, skip checks, cameras.json, report; on Dask also submitting, scheduling, collecting), median pass:",
        "",
        "| size | " + " | ".join(mode for mode in MODES if mode not in LOOPS) + " |",
        "|---|" + "---|" * (len(MODES) - len(LOOPS)),
    ]
    for result in results:
        cells = [
            f"{1000 * statistics.median(result.busy[mode]) / result.frames:.2f} / "
            # Several workers' chunks overlap in time: wall − their sum means nothing there.
            + (f"{1000 * statistics.median(result.outside[mode]) / result.frames:.2f}" if "2 workers" not in mode else "–")
            if mode in result.busy else "–"
            for mode in MODES if mode not in LOOPS
        ]
        lines.append(f"| {result.size}² | " + " | ".join(cells) + " |")
    lines += [
        "",
        "CPU per frame (user + system, every thread of this process and of the Dask workers) and frames per "
        "CPU-second, i.e. throughput per fully busy core, median pass:",
        "",
        "| size | " + " | ".join(MODES) + " |",
        "|---|" + "---|" * len(MODES),
    ]
    for result in results:
        cells = [
            f"{result.cpu_ms_per_frame(mode):.1f} ms, {1000 / result.cpu_ms_per_frame(mode):.0f}/s" if mode in result.cpu else "–"
            for mode in MODES
        ]
        lines.append(f"| {result.size}² | " + " | ".join(cells) + " |")
    lines += ["", stage_table(results)]
    if results[0].dask_startup:
        lines += ["", "Dask start-up to a warm cluster (processes, plugin, first pipeline): "
                  + ", ".join(f"{k}: {v:.1f} s" for k, v in results[0].dask_startup.items())]
    return "\n".join(lines)


def stage_table(results: list[DatasetResult]) -> str:
    """The colour + depth batch's stages alone (dataset_stages.py), beside the batch itself."""
    lines = [
        "Where a colour + depth frame's time goes: each stage of the batch timed alone in this process "
        "(benchmarks/dataset_stages.py), ms per frame, wall / CPU (every thread), median pass; load is "
        "spread over the frames of its mesh (read from the mesh cache, as in the batch). Then the batch itself: "
        "end to end, and inside its chunks, against render + readback of the same scenes timed in the same "
        "rotation of modes (frames let go as read; wall / CPU), the figure issue #29's ≤ 1.5 is about; last, "
        "the same for the batch's first run over these meshes (an empty mesh cache: every file parsed, every "
        "vertex-cache order made).",
        "",
        "| size | " + " | ".join(STAGES) + " | sum of stages | batch inside chunks | batch end to end "
        "| render + readback, same passes | inside chunks ÷ render + readback (≤ 1.5) "
        "| first run inside chunks | first run ÷ render + readback |",
        "|---|" + "---:|" * (len(STAGES) + 7),
    ]
    for result in results:
        stages = result.stages
        wall = {stage: 1000 * statistics.median(stages.wall[stage]) for stage in stages.wall}
        cpu = {stage: 1000 * statistics.median(stages.cpu[stage]) for stage in stages.cpu}
        summed = [stage for stage in STAGES if stage != "render, one at a time"]
        mode = "batch, colour + depth"
        inside = 1000 * statistics.median(result.busy[mode]) / result.frames
        end_to_end = 1000 * statistics.median(result.seconds[mode]) / result.frames
        frames_alone = 1000 * statistics.median(result.seconds[FRAMES_ALONE]) / result.frames
        first = 1000 * statistics.median(result.busy[FIRST_RUN]) / result.frames
        cells = [f"{wall[stage]:.2f} / {cpu[stage]:.2f}" for stage in STAGES]
        lines.append(
            f"| {result.size}² | " + " | ".join(cells)
            + f" | {sum(wall[s] for s in summed):.2f} / {sum(cpu[s] for s in summed):.2f}"
            + f" | {inside:.2f} | {end_to_end:.2f} / {result.cpu_ms_per_frame(mode):.2f}"
            + f" | {frames_alone:.2f} / {result.cpu_ms_per_frame(FRAMES_ALONE):.2f} | {inside / frames_alone:.2f}× "
            + f"| {first:.2f} | {first / frames_alone:.2f}× |"
        )
    for result in results:  # pass by pass (each pass times both in one rotation of the modes): the spread
        frames_alone = result.seconds[FRAMES_ALONE]
        warm = ", ".join(f"{busy / alone:.2f}×" for busy, alone in zip(result.busy["batch, colour + depth"], frames_alone))
        first = ", ".join(f"{busy / alone:.2f}×" for busy, alone in zip(result.busy[FIRST_RUN], frames_alone))
        lines += ["", f"{result.size}², inside chunks ÷ render + readback pass by pass: {warm}; first run: {first}."]
    loads = [f"{value:.1f}" for result in results for value in result.load_average]
    lines += ["", f"1-minute load average after each pass: {', '.join(loads)} ({os.cpu_count()} cores)."]
    creations = [f"{value:.0f}" for result in results for value in result.new_file_us]
    spread = [f"{value:.0f}" for result in results for value in result.new_file_spread_us]
    if creations:
        lines += ["", f"A new empty file before each pass, in a new subfolder of the scratch folder: {', '.join(creations)} µs; "
                  f"in a mesh folder made as the batch makes them (its output folder marked for ext4 to spread "
                  f"its subfolders: dataset/output_folder.py): {', '.join(spread)} µs (medians of "
                  f"{PROBE_FILES}; each view creates 3 files; 16–25 µs in a quiet folder here, up to 860 µs where many "
                  "files were removed nearby in the minutes before, which ext4 without a journal skips one by one: "
                  "benchmarks/dataset.py, new_file_micros)."]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.dataset", description=__doc__.split("\n\n")[0])
    parser.add_argument("--smoke", action="store_true", help="tiny: 2 builtin meshes × 4 views at 32², one pass")
    parser.add_argument("--views", type=int, default=48)
    parser.add_argument("--passes", type=int, default=3)
    parser.add_argument("--scratch", type=Path, default=None,
                        help="folder to write the datasets in (a new folder there, removed at the end; default: the system's temporary folder)")
    args = parser.parse_args(argv)
    renderer = Renderer()
    from .pyrender_peer import pyrender_unusable

    pyrender = pyrender_unusable() is None
    if args.smoke:
        results = run_dataset_benchmark(renderer, list(SMOKE_MESHES), 4, (32,), 1, chunk=2, pyrender=pyrender, scratch_parent=args.scratch)
    else:
        results = run_dataset_benchmark(
            renderer, default_meshes(), args.views, (256, 512), args.passes, pyrender=pyrender, scratch_parent=args.scratch
        )
    print(table(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
