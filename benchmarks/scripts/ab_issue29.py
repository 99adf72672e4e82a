"""The A/B measurements of issue #29's small frame (docs/performance.md, "The small torus
frame and its hand-offs"), as they were run.

    python benchmarks/scripts/ab_issue29.py frame-memory --size 512 --frames 300 --runs 3
    python benchmarks/scripts/ab_issue29.py poll --size 512 --rounds 30
    python benchmarks/scripts/ab_issue29.py frame-plans --size 512 --rounds 30
    python benchmarks/scripts/ab_issue29.py turned-away --size 512 --rounds 30
    python benchmarks/scripts/ab_issue29.py start-up --rounds 20
    python benchmarks/scripts/ab_issue29.py chunks --size 512 --rounds 5
    python benchmarks/scripts/ab_issue29.py batch-parts --size 512 --rounds 5
    python benchmarks/scripts/ab_issue29.py batch-parts --size 256 --rounds 8 --views 12   # --quick's 12 views a mesh
    python benchmarks/scripts/ab_issue29.py kept-frames --size 512 --rounds 6
    python benchmarks/scripts/ab_issue29.py fresh-meshes --size 256 --rounds 10
    python benchmarks/scripts/ab_issue29.py frames-in-flight --size 256 --rounds 8
    python benchmarks/scripts/ab_issue29.py chunk-order --size 256 --rounds 10
    python benchmarks/scripts/ab_issue29.py thread-cpu --size 256 --rounds 3
    python benchmarks/scripts/ab_issue29.py output-folders --size 256 --rounds 8 --folders /tmp /var/tmp DIR
    python benchmarks/scripts/ab_issue29.py crease-split --rounds 12
    python benchmarks/scripts/ab_issue29.py encoder-threads --size 256 --rounds 16
    python benchmarks/scripts/ab_issue29.py dask-saturation --size 256 --rounds 8
    python benchmarks/scripts/ab_issue29.py dask-client --size 256 --rounds 12
    python benchmarks/scripts/ab_issue29.py per-mesh --size 256 --rounds 6
    python benchmarks/scripts/ab_issue29.py files-beside --size 256 --rounds 6
    python benchmarks/scripts/ab_issue29.py spread-folders --size 256 --rounds 8
    python benchmarks/scripts/ab_issue29.py poll-gap --size 256 --rounds 8
    python benchmarks/scripts/ab_issue29.py vertex-cache --size 512 --rounds 16
    python benchmarks/scripts/ab_issue29.py mesh-cache --size 256 --rounds 10 --views 12
    python benchmarks/scripts/ab_issue29.py mesh-cache-many --size 256 --rounds 5 --views 12
    python benchmarks/scripts/ab_issue29.py start-up --callgrind   # instructions, ~1.5 min
    python benchmarks/scripts/ab_issue29.py frame-memory --smoke   # what the benchmark smoke run does

frame-memory: warm frames of the 10K torus in fresh processes, alternately with the
driver's scratch memory kept mapped (render/frame_memory.py) and given back
(WGPU_SHADING_FRAME_MEMORY=0): a process's malloc thresholds depend on what it freed
before, so each variant gets a fresh process that renders nothing else. Per variant and
run: minor page faults, CPU ms of each thread and of the process, and the median wall ms
per frame, with the load average.

start-up: `wgpu-shading render builtin:torus -o OUT.png` in fresh processes, interleaved
round by round (the order rotating), as the program starts (cli/process_start.py) and with
one of its start-up settings undone at a time: the garbage collector as Python has it (on
during the imports, nothing frozen), pyglm's typing aliases imported with pyglm, every
installed Vulkan driver loaded;
then all three undone. Median wall and CPU (user + system) ms of each, and each ÷ the
program as shipped.

poll: in one process, interleaved rounds of 5 frames each: the map waited for on our own
thread (`map_async`, then wgpu-py's `device._poll_wait()`, i.e. wgpuDevicePoll(wait)) and
through wgpu-py's poll thread (map_sync, what the Renderer does), with moderngl beside them
when it is installed; median wall and process CPU ms per frame. The images are compared
first.

frame-plans: in one process, interleaved rounds of 5 frames each of the same Scene object:
drawn from its frame plan (render/gpu/frame_plans.py, what the Renderer does) and
prepared anew every frame (the plan cache made to miss), with moderngl beside them when
it is installed; median wall and process CPU ms per frame. The images are compared first.

turned-away: in one process, interleaved rounds of 5 frames each: the closed torus seen
from outside with its triangles turned away culled by the rasterizer (render/passes/
turned_away.py, what the Renderer does) and with every triangle drawn (no mesh small
enough to be culled: CULLED_MAX_TRIANGLES = -1), each variant its own Scene object (its
own frame plan), with moderngl beside them when it is installed (which draws every
triangle, as OpenGL does by default); median wall and process CPU ms per frame. The
images are compared first: this view of the torus has no silhouette pixel that drawing
every triangle gives to a triangle turned away.

chunks: the dataset benchmark's colour + depth scenes (its 4 meshes × 48 views) through
render_many as one stream and in chunks of 16 and of 48 (each chunk a render_many of its
own, so the frames in flight drain at its end, as `batch` does between chunks),
interleaved round by round in one process; median wall and process CPU ms per frame.
What a chunk boundary costs the frames themselves, without any writing.

batch-parts: where a colour + depth batch frame goes beyond its render + readback, as an
A/B in one process on the dataset benchmark's 192 jobs, round by round: `render_many` of
their scenes alone (built beforehand), then `render_dataset` with each job's files neither
encoded nor written (its write_view replaced by one that only names the files: what is
left is loading the meshes, building the scenes, the chunks' bookkeeping), encoded but not
written (the PNG, the .npy bytes and the record, into memory), with its meshes read
once before all runs but new Mesh objects each run (no file read; every mesh uploaded,
ordered and clustered anew), with its meshes loaded once before all runs (the same Mesh
objects every run: no file read, and no mesh uploaded, ordered or clustered anew), with
neither files nor loading, and as it is. `--views 12` gives each mesh the 12 views of
`python -m benchmarks --quick`, over which its load and upload are spread.
Median wall and process CPU (every thread) ms per frame, and each ÷ render_many's wall.

kept-frames: the dataset benchmark's 192 colour + depth scenes through render_many, every
frame kept until the stream ends (what the dataset stage table's render column did until
issue #29's eighth pass: 384 MB at 512²) and each let go once read back (what the batch
does once a frame is written), interleaved round by round in one process: what keeping
them costs on a VM that backs fresh pages on first touch.

fresh-meshes: the same scenes through render_many, drawn again (their meshes uploaded,
their clusters and closed-surface checks done) and with every mesh loaded anew before the
round (untimed), as each batch run draws meshes no frame has drawn: what a new mesh's
preparation costs its frames (vertex-cache order, uploads to both devices, the closed-
surface test, a cluster build's check).

frames-in-flight: render + readback alone and the colour + depth batch, each with 2, 3 and
4 frames in flight per device (render_many's in_flight, which the batch's chunks leave at
its default), interleaved round by round in one process; the batch's time inside its chunks ÷ render + readback at the default 2.

chunk-order: the colour + depth batch with its jobs as listed (the bunny's chunks first,
so its ~90 ms load precedes every frame) and with the bunny's chunks last (its load on the
loader thread while other meshes' frames render), beside render + readback alone.

thread-cpu: where the CPU of a frame goes, by thread: render + readback alone and the
batch, each for --rounds passes, twice, alternating; the process's user and system time,
the main thread's (time.thread_time), the encoder threads' write_view and the loads
(thread_time around each call; a load counts in the thread that ran it too: the loader's,
or the main thread's for a chunk's first mesh), and the rest (the driver's, wgpu's, the
loader's and the cluster builder's threads), ms a frame.

output-folders: the colour + depth batch writing in a new folder of each of --folders
(default: the system's temporary folder), interleaved round by round beside render +
readback alone, each folder's file creation time (benchmarks/dataset.py, new_file_micros)
measured before the rounds and after them.

encoder-threads: the colour + depth batch with 1, 2 and 3 encoder threads
(dataset/chunk.py, default_encoder_threads), interleaved round by round beside render +
readback alone; each batch's time inside its chunks, and paired with the default's run
of the same round: the median of the per-round ratios and in how many rounds it was
faster (a run's place in a slow or fast minute of the machine cancels out in the pair).

poll-gap: render + readback of the dataset benchmark's 192 colour + depth scenes alone,
and the colour + depth batch, each with wgpu-py's poll threads given a gap after a poll
that did not wait (render/poll_thread.py, as shipped) and without it, interleaved round by
round: wall and CPU a frame, the waiting polls of the two devices' poll threads a frame,
each batch's time inside its chunks ÷ render + readback alone with the same setting, and
each setting's runs paired with the other's of the same round.

dask-saturation: the colour batch on two warm one-worker local clusters, one with the
shipped worker-saturation (dataset/cluster.py, LOCAL_CLUSTER_CONFIG: 1.0, one chunk a
1-thread worker) and one with 2.0 (the next chunk waiting on the worker), alternating; the time per frame end to end, outside
the chunks (the scheduler's round trips between chunks among it) and inside them, and the
first two paired.

dask-client: the colour batch on one warm one-worker local cluster, alternately through
render_dataset(scheduler=ADDRESS) (a client connected and closed each run, as `batch
--scheduler` does) and render_dataset(client=CLIENT) (one client held across runs); the
time per frame end to end, outside the chunks and inside them, the first two paired, and
what a bare Client(ADDRESS) and its close() cost in the same rounds.

per-mesh: each mesh of the dataset benchmark alone, its views' render + readback and then
its colour + depth batch (its load included, as each run loads anew), round by round: the
ratio of the two for each mesh, which shows which meshes set the benchmark's ratio.

files-beside: what a view's files cost the frames on these cores when nothing else of the
batch is there: render + readback of the dataset benchmark's scenes alone, and with another
process (spawned, no wgpu in it, so no interpreter lock or driver shared) writing one view's
files (the colour PNG at level 1, the depth `.npy`, a record, each through a temporary and a
rename, with the batch's own writers) for every frame read back, at normal priority, at
nice 19 and at SCHED_IDLE, rotated round by round: ms a frame, the ratio to the frames
alone, how many views the writer kept up with a frame, and what creating an empty file
took before each round (the file system's state moves the writes' cost most).

spread-folders: the colour + depth batch with its output folder as render_dataset makes it
(marked for ext4 to spread its mesh folders over block groups: dataset/output_folder.py) and
without the mark, each round after removing each batch's output of the round before (as
`rm -r OUT` before rendering a dataset again), rotated with render + readback alone: each
batch's time inside its chunks, both paired round by round, and what creating an empty file
took after the removals in a plain subfolder and in a mesh folder of a marked folder.

vertex-cache: the vertex-cache order an upload makes (render/gpu/vertex_order.py), with
meshoptimizer's Forsyth-like optimize_vertex_cache (as shipped) and with its faster FIFO
ordering (optimize_vertex_cache_fifo, a 16-vertex cache): the time to order the bunny's and
the teapot's triangles, then frames of 24 views of each mesh uploaded in either order, and
a second upload in the shipped order as a control (what the same order reads twice),
interleaved round by round (clusters off: their build orders the triangles again); wall
and CPU a frame, each paired with the shipped order's of the same round. The images are
compared first.

crease-split: the 70K-triangle bunny's load_mesh with crease_normals.split_vertices and
with the formulation it replaced (np.unique over every corner's (vertex, fan) key),
alternating in one process; both give the same arrays (checked first).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))  # the repository (benchmarks/ and the package)


def _one_process(size: int, frames: int, segments: int) -> dict:
    """Run in the child: warm frames of the torus, measured."""
    from benchmarks.measure import thread_cpu_seconds
    from benchmarks.scenes import torus_scene
    from wgpu_shading import Renderer

    scene = torus_scene(size, segments)
    renderer = Renderer()
    for _ in range(10):
        renderer.render(scene)
    walls = []
    threads_before = thread_cpu_seconds()
    faults_before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    cpu_before = time.process_time()
    for _ in range(frames):
        start = time.perf_counter()
        renderer.render(scene)
        walls.append(time.perf_counter() - start)
    cpu = (time.process_time() - cpu_before) / frames
    faults = (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - faults_before) / frames
    threads: dict[str, float] = {}
    for key, seconds in thread_cpu_seconds().items():
        spent = seconds - threads_before.get(key, 0.0)
        if spent > 0:
            role = key.split("#")[0]
            threads[role] = threads.get(role, 0.0) + spent * 1e3 / frames
    return {"wall_ms": statistics.median(walls) * 1e3, "cpu_ms": cpu * 1e3, "faults": faults, "threads": threads}


def frame_memory(size: int, frames: int, runs: int, segments: int) -> None:
    variants = {"kept mapped": "1", "given back": "0"}
    print(f"torus ({segments}×{segments} segments) at {size}², {frames} warm frames a process; "
          f"load average {os.getloadavg()[0]:.2f} at the start")
    for run in range(runs):
        for name, switch in variants.items():
            environment = {**os.environ, "WGPU_SHADING_FRAME_MEMORY": switch}
            result = subprocess.run(
                [sys.executable, __file__, "child", "--size", str(size), "--frames", str(frames), "--segments", str(segments)],
                capture_output=True, text=True, env=environment, cwd=REPO, check=True,
            )
            measured = json.loads(result.stdout.strip().splitlines()[-1])
            threads = ", ".join(f"{role} {ms:.2f}" for role, ms in sorted(measured["threads"].items(), key=lambda kv: -kv[1]))
            print(f"run {run + 1} {name:12s}: {measured['faults']:6.0f} faults, CPU {measured['cpu_ms']:.2f} ms "
                  f"({threads}), wall median {measured['wall_ms']:.2f} ms; load {os.getloadavg()[0]:.2f}")


def poll(size: int, rounds: int, segments: int) -> None:
    import wgpu_shading.render.gpu.readback as readback
    from benchmarks.scenes import torus_scene
    from wgpu_shading import Renderer

    scene = torus_scene(size, segments)
    renderer = Renderer()
    device = renderer.device
    through_poll_thread = readback.map_for_reading

    def on_our_thread(buffer) -> None:
        promise = buffer.map_async("READ_NOSYNC")
        device._poll_wait()  # wgpuDevicePoll(wait): the map's callback runs here
        promise.sync_wait()

    _switched_with_moderngl(
        scene, lambda: renderer.render(scene), readback, "map_for_reading",
        {"map waited for on our thread": on_our_thread, "through wgpu-py's poll thread": through_poll_thread}, rounds, "waits",
    )


def _switched_with_moderngl(scene, render, owner, name: str, values: dict, rounds: int, what: str) -> None:
    """_interleaved_with_moderngl of `render()` with `owner.name` set to each of `values`
    (label → value) in turn; `owner.name` is put back as it was afterwards."""
    shipped = getattr(owner, name)

    def with_value(value):
        def run() -> object:
            setattr(owner, name, value)
            return render()
        return run

    try:
        _interleaved_with_moderngl(scene, {label: with_value(value) for label, value in values.items()}, rounds, what)
    finally:
        setattr(owner, name, shipped)


def _interleaved_with_moderngl(scene, contenders: dict, rounds: int, what: str) -> None:
    """Compare the two variants' images, then time them interleaved (5 frames a round) with
    moderngl beside them when it is installed; print median wall and process CPU ms."""
    import importlib.util

    from benchmarks.measure import interleaved
    from benchmarks.scenes import geometry_draw

    first, second = (call() for call in contenders.values())
    if not (first == second).all():
        raise SystemExit(f"the two {what} gave different images")
    contenders = dict(contenders)
    if importlib.util.find_spec("moderngl") is not None:
        from benchmarks.peers import ModernGLPeer

        contenders["moderngl"] = ModernGLPeer(geometry_draw(scene, "torus")).render
    size = scene.size[0]
    start_load = os.getloadavg()[0]
    timings = interleaved(contenders, rounds=rounds, frames=5)
    print(f"torus at {size}², {rounds} interleaved rounds of 5 frames; load average {start_load:.2f} → {os.getloadavg()[0]:.2f}")
    for name, timing in timings.items():
        print(f"  {name:32s} wall {timing.median_ms:.2f} ms, CPU {timing.cpu_median_ms:.2f} ms")


def frame_plans(size: int, rounds: int, segments: int) -> None:
    from benchmarks.scenes import torus_scene
    from wgpu_shading import Renderer
    from wgpu_shading.render.gpu.frame_plans import FramePlans

    scene = torus_scene(size, segments)
    renderer = Renderer()
    cache = renderer.device_cache
    kept = cache.frame_plans
    changes = iter(range(1 << 62))
    never_kept = FramePlans(lambda: next(changes))  # the caches "change" at every look-up: no plan is used

    _switched_with_moderngl(
        scene, lambda: renderer.render(scene), cache, "frame_plans",
        {"drawn from its frame plan": kept, "prepared anew every frame": never_kept}, rounds, "paths",
    )


def turned_away(size: int, rounds: int, segments: int) -> None:
    from dataclasses import replace

    from benchmarks.scenes import torus_scene
    from wgpu_shading import Renderer
    from wgpu_shading.render.passes import turned_away as module

    culled_scene = torus_scene(size, segments)
    every_triangle_scene = replace(culled_scene)
    renderer = Renderer()
    shipped = module.CULLED_MAX_TRIANGLES

    def culled() -> object:
        return renderer.render(culled_scene)

    def every_triangle() -> object:
        module.CULLED_MAX_TRIANGLES = -1
        try:
            return renderer.render(every_triangle_scene)
        finally:
            module.CULLED_MAX_TRIANGLES = shipped

    _interleaved_with_moderngl(
        culled_scene, {"triangles turned away culled": culled, "every triangle drawn": every_triangle}, rounds, "variants",
    )


# Views of each mesh in the dataset A/Bs: the full benchmark's 48 (`--views 12`: --quick's).
DATASET_VIEWS = 48


def _dataset_jobs(size: int, smoke: bool, depth: bool) -> tuple[str, list]:
    """The dataset benchmark's jobs (its 4 meshes × DATASET_VIEWS views; tiny when smoke),
    colour or colour + depth, and a line saying what they are."""
    from benchmarks.dataset import SMOKE_MESHES, default_meshes
    from wgpu_shading.dataset import Outputs, mesh_jobs, turntable_views

    meshes, views = (list(SMOKE_MESHES), 4) if smoke else (default_meshes(), DATASET_VIEWS)
    jobs = mesh_jobs(meshes, turntable_views(views), Outputs(depth="npy") if depth else Outputs(), {"size": size})
    return f"{len(meshes)} meshes × {views} views at {size}², colour{' + depth' if depth else ''}", jobs


def _dataset_scenes(size: int, smoke: bool) -> tuple[str, list, list]:
    """The dataset benchmark's colour + depth jobs and their scenes, built beforehand."""
    from benchmarks.dataset import job_scenes

    what, jobs = _dataset_jobs(size, smoke, depth=True)
    return what, jobs, job_scenes(jobs)


def _interleaved_per_frame(variants: dict, rounds: int, frames: int, before_round=None) -> tuple[dict, dict]:
    """Each variant run once per round, in turn, the order rotated from round to round (on
    this machine a variant's place in the round moved batch runs of one configuration by
    ±0.6 ms a frame, 7 %: docs/performance.md): wall and process CPU ms per frame, per round."""
    walls: dict[str, list[float]] = {name: [] for name in variants}
    cpus: dict[str, list[float]] = {name: [] for name in variants}
    names = list(variants)
    for round_index in range(rounds):
        if before_round is not None:  # untimed
            before_round()
        shift = round_index % len(names)
        for name in names[shift:] + names[:shift]:
            run = variants[name]
            wall, cpu = time.perf_counter(), time.process_time()
            run()
            walls[name].append((time.perf_counter() - wall) * 1e3 / frames)
            cpus[name].append((time.process_time() - cpu) * 1e3 / frames)
    return walls, cpus


def chunks(size: int, rounds: int, smoke: bool) -> None:
    from wgpu_shading import Renderer

    what, _, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()

    def in_chunks(length: int):
        def run() -> None:
            for start in range(0, len(scenes), length):
                for _ in renderer.render_many(scenes[start:start + length], depth=True):
                    pass
        return run

    variants = {"one stream": in_chunks(len(scenes)), "chunks of 16": in_chunks(16), "chunks of 48": in_chunks(48)}
    in_chunks(len(scenes))()  # uploads and pipelines on every device first
    _print_per_frame(what, variants, rounds, len(scenes))


def batch_parts(size: int, rounds: int, smoke: bool) -> None:
    import io
    import shutil
    import tempfile

    import numpy as np

    from wgpu_shading import Renderer
    from wgpu_shading.assets.png import write_png
    from benchmarks.dataset import render_all
    from wgpu_shading.dataset import chunk, direct_writes, render_dataset
    from wgpu_shading.dataset.direct_writes import write_npy
    from wgpu_shading.dataset.writer import json_text

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    as_shipped, as_shipped_load = chunk.write_view, chunk.base_scene
    loaded: dict = {}

    def loaded_before(job):
        """The job's base scene loaded once for every run: the same Mesh objects each run,
        so no run loads a file or uploads, orders or clusters a mesh anew."""
        if job.load_key() not in loaded:
            loaded[job.load_key()] = as_shipped_load(job)
        return loaded[job.load_key()]

    def read_before(job):
        """The job's base scene read once for every run, but with Mesh objects new to the
        renderer each run: no file read, and every mesh uploaded, ordered and clustered anew."""
        import dataclasses

        base = loaded_before(job)
        return dataclasses.replace(base, objects=[dataclasses.replace(o, mesh=dataclasses.replace(o.mesh)) for o in base.objects])

    def named_only(out_dir, job, frame, extra, camera) -> list[str]:
        return [f"{job.folder}/{name}" for name in job.outputs.file_names(job.name)]

    def encoded_only(out_dir, job, frame, extra, camera) -> list[str]:
        write_png(io.BytesIO(), frame.color, 1)
        write_npy(io.BytesIO(), frame.depth, np.float32)
        json_text({"id": job.id, "digest": job.digest(), "source": job.source, "files": job.files(), "camera": camera})
        return named_only(out_dir, job, frame, extra, camera)

    folder = Path(tempfile.mkdtemp(prefix="ab-batch-parts-"))
    runs = iter(range(1 << 30))

    def batch(write_view, smallest_direct: int = direct_writes.SMALLEST_DIRECT_FILE, load=as_shipped_load):
        def run() -> None:
            chunk.write_view, chunk.base_scene = write_view, load
            direct_writes.SMALLEST_DIRECT_FILE = smallest_direct
            try:
                render_dataset(jobs, folder / str(next(runs)), progress=False, renderer=renderer)
            finally:
                chunk.write_view, chunk.base_scene = as_shipped, as_shipped_load
                direct_writes.SMALLEST_DIRECT_FILE = as_shipped_min
        return run

    as_shipped_min = direct_writes.SMALLEST_DIRECT_FILE
    variants = {
        "render + readback alone": lambda: render_all(renderer, scenes),
        "batch, files neither encoded nor written": batch(named_only),
        "batch, files encoded, not written": batch(encoded_only),
        "batch, every file through the page cache": batch(as_shipped, 1 << 62),
        "batch, meshes read before, uploaded anew": batch(as_shipped, load=read_before),
        "batch, meshes loaded before the run": batch(as_shipped, load=loaded_before),
        "batch, neither files nor meshes loaded": batch(named_only, load=loaded_before),
        "batch": batch(as_shipped),
    }
    print(f"{what}; load average {os.getloadavg()[0]:.2f} at the start")
    try:
        for run in variants.values():  # pipelines, uploads, thread pools
            run()
        walls, cpus = _interleaved_per_frame(variants, rounds, len(jobs))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    alone = statistics.median(walls["render + readback alone"])
    for name in variants:
        wall = statistics.median(walls[name])
        print(f"{name:43s}: wall {wall:6.2f} ms a frame ({min(walls[name]):.2f}–{max(walls[name]):.2f}), "
              f"CPU {statistics.median(cpus[name]):6.2f} ms; {wall / alone:.2f}× the frames alone")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def kept_frames(size: int, rounds: int, smoke: bool) -> None:
    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer

    what, _, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()

    def kept() -> None:
        frames = [(frame.color, frame.depth) for frame in renderer.render_many(scenes, depth=True)]
        del frames

    variants = {"every frame kept": kept, "each let go once read": lambda: render_all(renderer, scenes)}
    render_all(renderer, scenes)  # uploads and pipelines on every device first
    _print_per_frame(what, variants, rounds, len(scenes))


def fresh_meshes(size: int, rounds: int, smoke: bool) -> None:
    from benchmarks.dataset import job_scenes, render_all
    from wgpu_shading import Renderer

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    loaded = [job_scenes(jobs) for _ in range(rounds + 1)]  # loaded before the timing: only the drawing is timed
    variants = {"meshes drawn before": lambda: render_all(renderer, scenes),
                "meshes never drawn": lambda: render_all(renderer, loaded.pop())}
    for run in variants.values():
        run()
    _print_per_frame(what, variants, rounds, len(jobs))


def _batch_runner(renderer, folder: Path, inside: dict):
    """A function making a variant that runs `render_dataset(jobs)` into a new subfolder of
    `folder` and keeps its time inside chunks, ms a frame, in inside[name]."""
    from wgpu_shading.dataset import render_dataset

    runs = iter(range(1 << 30))

    def variant(name: str, jobs: list):
        def run() -> None:
            result = render_dataset(jobs, folder / f"{next(runs)}", progress=False, renderer=renderer)
            inside.setdefault(name, []).append(1000 * result.busy_seconds / len(jobs))
        return run
    return variant


def _print_batches(what: str, variants: dict, rounds: int, frames: int, inside: dict, alone_name: str,
                   before_round=None) -> None:
    """Each variant once first (pipelines, uploads, thread pools), then the interleaved rounds
    (before_round() untimed before each): wall and CPU a frame, and each batch's time inside
    its chunks ÷ `alone_name`'s wall."""
    for run in variants.values():
        run()
    inside.clear()
    walls = _print_per_frame(what, variants, rounds, frames, before_round)
    alone = statistics.median(walls[alone_name])
    for name, values in inside.items():
        print(f"{name}: inside its chunks {statistics.median(values):.2f} ms a frame, "
              f"{statistics.median(values) / alone:.2f}× {alone_name}")


def frames_in_flight(size: int, rounds: int, smoke: bool) -> None:
    import functools
    import tempfile

    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    shipped = type(renderer).render_many

    def with_in_flight(count: int, run):
        def variant() -> None:
            # The batch's chunks call renderer.render_many without in_flight: this sets theirs too.
            renderer.render_many = functools.partial(shipped, renderer, in_flight=count)
            try:
                run()
            finally:
                del renderer.render_many
        return variant

    with tempfile.TemporaryDirectory(prefix="ab-in-flight-") as folder:
        inside: dict = {}
        batch = _batch_runner(renderer, Path(folder), inside)
        variants = {}
        for count in (2, 3, 4):
            variants[f"render + readback, {count} in flight"] = with_in_flight(count, lambda: render_all(renderer, scenes))
            variants[f"batch, {count} in flight"] = with_in_flight(count, batch(f"batch, {count} in flight", jobs))
        _print_batches(what, variants, rounds, len(jobs), inside, "render + readback, 2 in flight")


def chunk_order(size: int, rounds: int, smoke: bool) -> None:
    import tempfile

    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer

    what, jobs, scenes = _dataset_scenes(size, smoke)
    first = jobs[0].load_key()  # the bunny, when the real meshes are there
    last = [job for job in jobs if job.load_key() != first] + [job for job in jobs if job.load_key() == first]
    renderer = Renderer()
    with tempfile.TemporaryDirectory(prefix="ab-chunk-order-") as folder:
        inside: dict = {}
        batch = _batch_runner(renderer, Path(folder), inside)
        variants = {"render + readback alone": lambda: render_all(renderer, scenes),
                    "batch, first mesh's chunks first": batch("batch, first mesh's chunks first", jobs),
                    "batch, first mesh's chunks last": batch("batch, first mesh's chunks last", last)}
        _print_batches(what, variants, rounds, len(jobs), inside, "render + readback alone")


def mesh_cache(size: int, rounds: int, smoke: bool) -> None:
    """The batch with the mesh cache (assets/disk_cache.py) off, warm (filled by the first,
    untimed runs) and empty (a new folder each run: a first run over these meshes)."""
    import tempfile

    what, jobs, scenes = _dataset_scenes(size, smoke)
    with tempfile.TemporaryDirectory(prefix="ab-mesh-cache-") as folder:
        _compare_mesh_caches(what, jobs, scenes, Path(folder), rounds)


def mesh_cache_many(size: int, rounds: int, smoke: bool) -> None:
    """mesh-cache over 12 distinct files (4 copies of the bunny, the teapot and the cow, each
    copy's first line a comment of its own, so each is a file of its own to the cache): a
    run's later meshes load on the loader thread while earlier ones draw, as in a dataset
    of many meshes, instead of the first mesh's load alone before any frame."""
    import tempfile

    from benchmarks.dataset import MODELS, job_scenes, mesh_cache_in
    from wgpu_shading.dataset import Outputs, mesh_jobs, turntable_views

    with tempfile.TemporaryDirectory(prefix="ab-mesh-cache-many-") as folder:
        names = ("builtin:torus?segments=16",) if smoke else ("stanford-bunny.obj", "teapot.obj", "cow.obj")
        sources = []
        for copy in range(1 if smoke else 4):
            for name in names:
                if name.startswith("builtin:"):
                    sources.append(name)
                    continue
                path = Path(folder) / f"{copy}-{name}"
                path.write_bytes(f"# copy {copy}\n".encode() + (MODELS / name).read_bytes())
                sources.append(str(path))
        views = 4 if smoke else DATASET_VIEWS
        jobs = mesh_jobs(sources, turntable_views(views), Outputs(depth="npy"), {"size": size})
        with mesh_cache_in(Path("off")):
            scenes = job_scenes(jobs)
        _compare_mesh_caches(f"{len(sources)} meshes × {views} views at {size}², colour + depth", jobs, scenes, Path(folder), rounds)


def _compare_mesh_caches(what: str, jobs: list, scenes: list, folder: Path, rounds: int) -> None:
    """render + readback of `scenes` alone, and the batch of `jobs` with the mesh cache off,
    warm and empty (in folders under `folder`), in interleaved rounds."""
    from benchmarks.dataset import mesh_cache_in, render_all
    from wgpu_shading import Renderer

    renderer = Renderer()
    inside: dict = {}
    batch = _batch_runner(renderer, folder, inside)
    empties = iter(range(1 << 30))

    def with_cache(name: str, cache_folder) -> object:
        run = batch(name, jobs)

        def variant() -> None:
            with mesh_cache_in(Path(cache_folder() if callable(cache_folder) else cache_folder)):
                run()
        return variant

    variants = {"render + readback alone": lambda: render_all(renderer, scenes),
                "batch, mesh cache off": with_cache("batch, mesh cache off", "off"),
                "batch, mesh cache warm": with_cache("batch, mesh cache warm", folder / "warm-cache"),
                "batch, mesh cache empty": with_cache("batch, mesh cache empty", lambda: folder / f"empty-{next(empties)}")}
    _print_batches(what, variants, rounds, len(jobs), inside, "render + readback alone")


def output_folders(size: int, rounds: int, smoke: bool, folders: list[Path]) -> None:
    import contextlib
    import tempfile

    from benchmarks.dataset import new_file_micros, render_all
    from wgpu_shading import Renderer

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    with contextlib.ExitStack() as stack:
        made = {str(parent): Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="ab-output-folders-", dir=parent)))
                for parent in folders}
        inside: dict = {}
        variants = {"render + readback alone": lambda: render_all(renderer, scenes)}
        for parent, folder in made.items():
            variants[f"batch in {parent}"] = _batch_runner(renderer, folder, inside)(f"batch in {parent}", jobs)
        before = {parent: new_file_micros(folder) for parent, folder in made.items()}
        _print_batches(what, variants, rounds, len(jobs), inside, "render + readback alone")
        for parent, folder in made.items():
            print(f"a new file in {parent}: {before[parent]:.0f} µs before the rounds, {new_file_micros(folder):.0f} µs after")


def thread_cpu(size: int, rounds: int, smoke: bool) -> None:
    import tempfile
    import threading
    from collections import Counter

    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer
    from wgpu_shading.dataset import chunk, render_dataset

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    spent: Counter = Counter()
    lock = threading.Lock()

    def timed(name: str, function):
        def call(*args, **kwargs):
            start = time.thread_time()
            try:
                return function(*args, **kwargs)
            finally:
                with lock:
                    spent[name] += time.thread_time() - start
        return call

    shipped_write, shipped_load = chunk.write_view, chunk.base_scene  # what ChunkRenderer writes and loads with
    scratch = tempfile.TemporaryDirectory(prefix="ab-thread-cpu-")
    folder = Path(scratch.name)
    runs = iter(range(1 << 30))
    variants = {"render + readback alone": lambda: render_all(renderer, scenes),
                "batch": lambda: render_dataset(jobs, folder / f"{next(runs)}", progress=False, renderer=renderer)}
    print(f"{what}; load average {os.getloadavg()[0]:.2f} at the start; ms of CPU a frame")
    chunk.write_view, chunk.base_scene = timed("encoder threads (write_view)", shipped_write), timed("loads", shipped_load)
    try:
        for run in variants.values():
            run()
        for name in list(variants) * 2:
            spent.clear()
            wall, times, main = time.perf_counter(), os.times(), time.thread_time()
            for _ in range(rounds):
                variants[name]()
            frames = rounds * len(jobs)
            after = os.times()
            user, system = (after.user - times.user) * 1e3 / frames, (after.system - times.system) * 1e3 / frames
            main = (time.thread_time() - main) * 1e3 / frames
            parts = {part: seconds * 1e3 / frames for part, seconds in spent.items()}
            encoders = parts.get("encoder threads (write_view)", 0.0)
            print(f"{name}: wall {(time.perf_counter() - wall) * 1e3 / frames:.2f}, CPU {user + system:.2f} (user {user:.2f}, "
                  f"system {system:.2f}); main thread {main:.2f}"
                  + "".join(f", {part} {value:.2f}" for part, value in parts.items())
                  + f"; the driver's, wgpu's and other threads {user + system - main - encoders:.2f}")
    finally:
        chunk.write_view, chunk.base_scene = shipped_write, shipped_load
        scratch.cleanup()
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def per_mesh(size: int, rounds: int, smoke: bool) -> None:
    import tempfile

    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer
    from wgpu_shading.dataset import render_dataset

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    meshes: dict[str, tuple[list, list]] = {}
    for job, scene in zip(jobs, scenes):
        their_jobs, their_scenes = meshes.setdefault(Path(job.source).name, ([], []))
        their_jobs.append(job)
        their_scenes.append(scene)
    alone: dict[str, list[float]] = {}
    inside: dict[str, list[float]] = {}
    print(f"{what}, each mesh's views alone; load average {os.getloadavg()[0]:.2f} at the start")
    with tempfile.TemporaryDirectory(prefix="ab-per-mesh-") as folder:
        runs = iter(range(1 << 30))
        for round_index in range(rounds + 1):  # the first round warms pipelines and uploads, untimed
            for name, (their_jobs, their_scenes) in meshes.items():
                start = time.perf_counter()
                render_all(renderer, their_scenes)
                wall = time.perf_counter() - start
                result = render_dataset(their_jobs, Path(folder) / f"{next(runs)}", progress=False, renderer=renderer)
                if round_index:
                    alone.setdefault(name, []).append(wall * 1e3 / len(their_scenes))
                    inside.setdefault(name, []).append(result.busy_seconds * 1e3 / len(their_jobs))
    for name in meshes:
        frames, batch = statistics.median(alone[name]), statistics.median(inside[name])
        print(f"{name}: render + readback {frames:.2f} ms a frame, the batch inside its chunks {batch:.2f} "
              f"(its load included), {batch / frames:.2f}×")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def _write_views_beside(policy: str, ready, tokens, stop, written, color: bytes, depth: bytes, size: int, folder: str) -> None:
    """files-beside's writer, in a spawned process: one view's files for every token the
    parent releases (one a frame read back), until `stop`."""
    import numpy as np

    from wgpu_shading.assets.png import encode_png
    from wgpu_shading.dataset.direct_writes import write_bytes, write_npy
    from wgpu_shading.dataset.writer import atomic_write, json_text

    if policy == "SCHED_IDLE":
        os.sched_setscheduler(0, os.SCHED_IDLE, os.sched_param(0))
    elif policy == "nice 19":
        os.nice(19)
    image = np.frombuffer(color, np.uint8).reshape(size, size, 4)
    distance = np.frombuffer(depth, np.float64).reshape(size, size)
    record = {"id": "mesh/view", "files": ["mesh/view.png", "mesh/view_depth.npy"], "camera": {"K": np.eye(3).tolist()}}
    out = Path(folder)
    out.mkdir()
    ready.set()
    count = 0
    while not stop.is_set():
        if not tokens.acquire(timeout=0.05):
            continue
        atomic_write(out / f"{count}.png", lambda file: write_bytes(file, encode_png(image, 1)))
        atomic_write(out / f"{count}_depth.npy", lambda file: write_npy(file, distance))
        atomic_write(out / f"{count}.json", lambda file: file.write(json_text(record)))
        count += 1
        with written.get_lock():
            written.value += 1


def files_beside(size: int, rounds: int, smoke: bool) -> None:
    import multiprocessing
    import tempfile

    import numpy as np

    from benchmarks.dataset import new_file_micros, render_all
    from wgpu_shading import Renderer

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    render_all(renderer, scenes)  # pipelines and uploads
    frame = renderer.render_frame(scenes[0], depth=True)
    color, depth = np.ascontiguousarray(frame.color).tobytes(), np.ascontiguousarray(frame.depth, np.float64).tobytes()
    spawn = multiprocessing.get_context("spawn")
    policies = ("none", "normal priority", "nice 19", "SCHED_IDLE")
    walls: dict[str, list[float]] = {policy: [] for policy in policies}
    kept_up: dict[str, list[float]] = {policy: [] for policy in policies}
    print(f"{what}: render + readback, with another process writing a view's files a frame; "
          f"load average {os.getloadavg()[0]:.2f} at the start")
    creations = []
    with tempfile.TemporaryDirectory(prefix="ab-files-beside-") as folder:
        for round_index in range(rounds):
            creations.append(new_file_micros(Path(folder)))
            shift = round_index % len(policies)
            for policy in policies[shift:] + policies[:shift]:
                ready, stop, tokens, written = spawn.Event(), spawn.Event(), spawn.Semaphore(0), spawn.Value("l", 0)
                writer = None
                if policy != "none":
                    writer = spawn.Process(target=_write_views_beside, args=(
                        policy, ready, tokens, stop, written, color, depth, size, f"{folder}/{round_index}-{policy}"))
                    writer.start()
                    if not ready.wait(60):
                        raise RuntimeError("the writer process did not start")
                start = time.perf_counter()
                for _ in renderer.render_many(scenes, depth=True):
                    tokens.release()
                walls[policy].append((time.perf_counter() - start) * 1e3 / len(scenes))
                kept_up[policy].append(written.value / len(scenes))
                if writer is not None:
                    stop.set()
                    writer.join()
    alone = statistics.median(walls["none"])
    for policy in policies:
        wall = statistics.median(walls[policy])
        print(f"{policy}: {wall:.2f} ms a frame, {wall / alone:.2f}× the frames alone; the writer wrote "
              f"{statistics.median(kept_up[policy]):.2f} views a frame meanwhile")
    print(f"a new empty file before each round: {', '.join(f'{us:.0f}' for us in creations)} µs (each view creates 3 "
          f"files; files removed nearby in the minutes before make it slower: benchmarks/dataset.py, new_file_micros)")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def _print_paired(inside: dict, baseline: str) -> None:
    """Each variant's runs against the baseline's run of the same round: the median ratio
    and in how many rounds the variant was faster."""
    for name, values in inside.items():
        paired = [value / base for value, base in zip(values, inside[baseline])]
        print(f"{name}: paired with {baseline}, median {statistics.median(paired):.3f}×, faster in "
              f"{sum(ratio < 1.0 for ratio in paired)} of {len(paired)} rounds")


def poll_gap(size: int, rounds: int, smoke: bool) -> None:
    import tempfile
    from collections import Counter

    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer
    from wgpu_shading.render.poll_thread import with_poll_gap

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    devices = [worker.device for worker in renderer.parallel_renderers(2)]
    polls: Counter = Counter()
    for device in devices:  # count the waiting polls under the gap (or with none)
        with_poll_gap(device, False)
        poll = device._poller._poll_func

        def counting(wait: bool, poll=poll):
            polls[wait] += 1
            return poll(wait)
        device._poller._poll_func = counting
    counted: dict[str, list[float]] = {}

    def setting(name: str, gap: bool, run):
        def variant() -> None:
            for device in devices:
                with_poll_gap(device, gap)
            polls.clear()
            try:
                run()
            finally:
                for device in devices:
                    with_poll_gap(device, True)
            counted.setdefault(name, []).append(polls[True] / len(jobs))
        return name, variant

    with tempfile.TemporaryDirectory(prefix="ab-poll-gap-") as folder:
        inside: dict = {}
        batch = _batch_runner(renderer, Path(folder), inside)
        variants = dict([
            setting("render + readback alone, gap (shipped)", True, lambda: render_all(renderer, scenes)),
            setting("render + readback alone, no gap", False, lambda: render_all(renderer, scenes)),
            setting("batch, gap (shipped)", True, batch("batch, gap (shipped)", jobs)),
            setting("batch, no gap", False, batch("batch, no gap", jobs)),
        ])
        for run in variants.values():  # pipelines, uploads, thread pools
            run()
        inside.clear()
        counted.clear()
        walls = _print_per_frame(what, variants, rounds, len(jobs))
    for name, values in counted.items():
        print(f"{name}: {statistics.median(values):.0f} waiting polls a frame (median of rounds)")
    for gap in ("gap (shipped)", "no gap"):
        alone = statistics.median(walls[f"render + readback alone, {gap}"])
        within = statistics.median(inside[f"batch, {gap}"])
        print(f"batch, {gap}: inside its chunks {within:.2f} ms a frame, {within / alone:.2f}× render + readback alone, {gap}")
    for kind in ("render + readback alone", "batch"):
        paired = [a / b for a, b in zip(walls[f"{kind}, gap (shipped)"], walls[f"{kind}, no gap"])]
        print(f"{kind}: gap ÷ no gap, paired by round, median {statistics.median(paired):.3f}×, "
              f"faster with the gap in {sum(ratio < 1.0 for ratio in paired)} of {len(paired)} rounds")


def encoder_threads(size: int, rounds: int, smoke: bool) -> None:
    import tempfile

    from benchmarks.dataset import render_all
    from wgpu_shading import Renderer
    from wgpu_shading.dataset import chunk

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    shipped = chunk.default_encoder_threads

    def label(count: int) -> str:
        return f"batch, {count} encoder thread(s)" + (" (the default here)" if count == shipped() else "")

    with tempfile.TemporaryDirectory(prefix="ab-encoder-threads-") as folder:
        inside: dict = {}
        batch = _batch_runner(renderer, Path(folder), inside)

        def with_threads(count: int):
            run = batch(label(count), jobs)

            def variant() -> None:
                chunk.default_encoder_threads = lambda: count  # what ChunkRenderer asks when made
                try:
                    run()
                finally:
                    chunk.default_encoder_threads = shipped
            return variant

        variants = {"render + readback alone": lambda: render_all(renderer, scenes)}
        variants.update({f"{count} encoder thread(s)": with_threads(count) for count in (1, 2, 3)})
        _print_batches(what, variants, rounds, len(jobs), inside, "render + readback alone")
        _print_paired(inside, label(shipped()))


def _alternate_dask_runs(variants: dict, rounds: int, frames: int, between_rounds=None) -> dict:
    """Each variant (name → run(out_dir) returning a BatchResult) once to warm up, then
    `rounds` rounds alternating their order; ms a frame end to end, outside the chunks and
    inside them, per variant. between_rounds(): called after each round."""
    import tempfile

    times: dict = {"end to end": {}, "outside the chunks": {}, "inside": {}}
    with tempfile.TemporaryDirectory(prefix="ab-dask-") as scratch:
        folders = (Path(scratch) / str(index) for index in range(1 << 30))
        for run in variants.values():  # the workers' pipelines and uploads
            run(next(folders))
        names = list(variants)
        for round_index in range(rounds):
            for name in names[round_index % 2:] + names[: round_index % 2]:
                start = time.perf_counter()
                result = variants[name](next(folders))
                wall = time.perf_counter() - start
                times["end to end"].setdefault(name, []).append(wall * 1e3 / frames)
                times["outside the chunks"].setdefault(name, []).append((wall - result.busy_seconds) * 1e3 / frames)
                times["inside"].setdefault(name, []).append(result.busy_seconds * 1e3 / frames)
            if between_rounds is not None:
                between_rounds()
    return times


def _print_dask_runs(times: dict) -> None:
    walls, outside, inside = times["end to end"], times["outside the chunks"], times["inside"]
    for name in walls:
        print(f"{name}: end to end {statistics.median(walls[name]):.2f} ms a frame, outside the chunks "
              f"{statistics.median(outside[name]):.3f} ({min(outside[name]):.2f}–{max(outside[name]):.2f}), "
              f"inside {statistics.median(inside[name]):.2f}")
    baseline = next(iter(walls))
    print("end to end:")
    _print_paired(walls, baseline)
    print("outside the chunks:")
    _print_paired(outside, baseline)


def dask_saturation(size: int, rounds: int, smoke: bool) -> None:
    from wgpu_shading.dataset import cluster, render_dataset

    what, jobs = _dataset_jobs(size, smoke, depth=False)
    shipped = cluster.LOCAL_CLUSTER_CONFIG
    key = "distributed.scheduler.worker-saturation"
    other = 2.0 if shipped[key] == 1.0 else 1.0
    clusters = {f"worker-saturation {shipped[key]} (shipped)": cluster.local_cluster(1)}
    cluster.LOCAL_CLUSTER_CONFIG = {**shipped, key: other}
    try:
        clusters[f"worker-saturation {other}"] = cluster.local_cluster(1)
    finally:
        cluster.LOCAL_CLUSTER_CONFIG = shipped
    print(f"{what}, one-worker local clusters; load average {os.getloadavg()[0]:.2f} at the start")
    try:
        variants = {
            name: (lambda out, local=local: render_dataset(jobs, out, scheduler=local.scheduler_address, progress=False))
            for name, local in clusters.items()
        }
        times = _alternate_dask_runs(variants, rounds, len(jobs))
    finally:
        for local in clusters.values():
            local.close(timeout=10)
    _print_dask_runs(times)
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def dask_client(size: int, rounds: int, smoke: bool) -> None:
    import distributed

    from wgpu_shading.dataset import cluster, render_dataset

    what, jobs = _dataset_jobs(size, smoke, depth=False)
    local = cluster.local_cluster(1)
    held = distributed.Client(local)
    connects, closes = [], []

    def bare_client() -> None:
        start = time.perf_counter()
        bare = distributed.Client(local.scheduler_address)
        connected = time.perf_counter()
        bare.close()
        connects.append((connected - start) * 1e3)
        closes.append((time.perf_counter() - connected) * 1e3)

    print(f"{what}, a one-worker local cluster; load average {os.getloadavg()[0]:.2f} at the start")
    try:
        variants = {
            "scheduler= (a client a run)": lambda out: render_dataset(jobs, out, scheduler=local.scheduler_address, progress=False),
            "client= (one client held)": lambda out: render_dataset(jobs, out, client=held, progress=False),
        }
        times = _alternate_dask_runs(variants, rounds, len(jobs), between_rounds=bare_client)
    finally:
        held.close()
        local.close(timeout=10)
    _print_dask_runs(times)
    print(f"a bare Client(address): {statistics.median(connects):.1f} ms to connect, {statistics.median(closes):.1f} ms to close "
          f"(median of {len(connects)}), i.e. {(statistics.median(connects) + statistics.median(closes)) / len(jobs):.3f} ms "
          f"a frame of this run")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def crease_split(rounds: int, smoke: bool) -> None:
    import numpy as np

    from benchmarks.dataset import MODELS
    from wgpu_shading.assets.meshes import load_mesh
    from wgpu_shading.scene.geometry import crease_normals

    path = MODELS / "stanford-bunny.obj"
    if smoke or not path.exists():
        path = MODELS / "suzanne.obj" if (MODELS / "suzanne.obj").exists() else None
    if path is None:
        print("crease-split: no model file to load (../shared/models)")
        return
    shipped = crease_normals.split_vertices

    def np_unique(flat_corners, label, vertex_fan, table, split=None):
        """The formulation split_vertices replaced."""
        key = flat_corners.astype(np.int64) * len(table) + label
        unique_keys, inverse = np.unique(key, return_inverse=True)
        return unique_keys // len(table), inverse.reshape(-1, 3).astype(np.uint32), table[unique_keys % len(table)]

    def load_with(split):
        def run():
            crease_normals.split_vertices = split
            try:
                return load_mesh(path)
            finally:
                crease_normals.split_vertices = shipped
        return run

    variants = {"np.unique over every corner": load_with(np_unique), "split_vertices": load_with(shipped)}
    meshes = [run() for run in variants.values()]
    same = all(np.array_equal(getattr(meshes[0], name), getattr(meshes[1], name)) for name in ("positions", "normals", "indices"))
    print(f"{path.name}: the same arrays: {same}; load average {os.getloadavg()[0]:.2f} at the start")
    walls, _ = _interleaved_per_frame(variants, rounds, 1)
    for name in variants:
        print(f"{name:28s}: load_mesh {statistics.median(walls[name]):.1f} ms ({min(walls[name]):.1f}–{max(walls[name]):.1f})")


def vertex_cache(size: int, rounds: int, smoke: bool) -> None:
    from unittest import mock

    from benchmarks.dataset import MODELS, SMOKE_MESHES
    from wgpu_shading import Renderer
    from wgpu_shading.render.gpu import vertex_order

    names = ("stanford-bunny.obj", "teapot.obj")
    sources = [str(MODELS / name) for name in names] if not smoke and all((MODELS / n).exists() for n in names) else [SMOKE_MESHES[0]]
    shipped = vertex_order.optimize_for_cache

    def fifo(destination, indices, vertex_count):
        import meshoptimizer

        meshoptimizer.optimize_vertex_cache_fifo(destination, indices, indices.size, vertex_count, 16)

    orders = {"Forsyth (shipped)": shipped, "FIFO": fifo, "Forsyth again (control)": shipped}
    renderer = Renderer()
    with mock.patch.dict(os.environ, {"WGPU_SHADING_CLUSTERS": "0"}):  # (clusters_enabled() reads it each frame)
        for source in sources:
            _vertex_cache_of(source, orders, renderer, size, rounds, smoke)
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


def _vertex_cache_of(source: str, orders: dict, renderer, size: int, rounds: int, smoke: bool) -> None:
    """vertex-cache for one mesh: each order's making time, then its frames, paired with the shipped order's."""
    import numpy as np

    from benchmarks.dataset import render_all
    from wgpu_shading.assets.meshes import load_mesh
    from wgpu_shading.dataset import Outputs, mesh_jobs, turntable_views
    from wgpu_shading.dataset.views import base_scene, job_scene
    from wgpu_shading.render.gpu import vertex_order

    shipped = vertex_order.optimize_for_cache
    mesh = load_mesh(source)
    flat = np.ascontiguousarray(mesh.indices, dtype=np.uint32).reshape(-1)
    destination = np.empty_like(flat)
    for name in ("Forsyth (shipped)", "FIFO"):
        times = []
        for _ in range(max(3, min(rounds, 10))):
            start = time.perf_counter()
            orders[name](destination, flat, mesh.vertex_count)
            times.append((time.perf_counter() - start) * 1e3)
        print(f"{Path(source).name}, {mesh.triangle_count} triangles: {name} order made in {statistics.median(times):.2f} ms")
    jobs = mesh_jobs([source], turntable_views(2 if smoke else 24), Outputs(depth="npy"), {"size": size})
    variants, images = {}, {}
    for name, order in orders.items():
        base = base_scene(jobs[0])  # a mesh of its own: its own upload, in this order
        scenes = [job_scene(base, job) for job in jobs]
        vertex_order.optimize_for_cache = order
        try:
            images[name] = [frame.color for frame in renderer.render_many(scenes, depth=True)]
        finally:
            vertex_order.optimize_for_cache = shipped
        variants[name] = lambda scenes=scenes: render_all(renderer, scenes)
    same = all(np.array_equal(a, b) for a, b in zip(images["Forsyth (shipped)"], images["FIFO"]))
    print(f"the same images in either order: {same}")
    walls, cpus = _interleaved_per_frame(variants, rounds, len(jobs))
    for name in variants:
        wall = [a / b for a, b in zip(walls[name], walls["Forsyth (shipped)"])]
        cpu = [a / b for a, b in zip(cpus[name], cpus["Forsyth (shipped)"])]
        print(f"  {name:23s}: wall {statistics.median(walls[name]):.2f} ms a frame, CPU {statistics.median(cpus[name]):.2f} ms; "
              f"÷ shipped, paired by round: wall {statistics.median(wall):.3f}×, CPU {statistics.median(cpu):.3f}×")


def _print_per_frame(what: str, variants: dict, rounds: int, frames: int, before_round=None) -> dict:
    print(f"{what}; load average {os.getloadavg()[0]:.2f} at the start")
    walls, cpus = _interleaved_per_frame(variants, rounds, frames, before_round)
    width = max(map(len, variants))
    for name in variants:
        print(f"{name:{width}s}: wall {statistics.median(walls[name]):.2f} ms a frame ({min(walls[name]):.2f}–"
              f"{max(walls[name]):.2f}), CPU {statistics.median(cpus[name]):.2f} ms")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")
    return walls


# The program with one start-up setting undone (cli/process_start.py), patched where the
# program (cli/main.py, `program`) or process_start reads it when it runs.
_UNDO = {
    "garbage collector as by default (on, nothing frozen)": (
        "import gc; _start, _command = program.start_process, program.command_starts; "
        "program.start_process = lambda: (_start(), gc.enable()); "
        "program.command_starts = lambda command, adapter: (_command(command, adapter), gc.unfreeze())"
    ),
    "pyglm's typing aliases imported": "process_start.DEFERRED_MODULES.clear()",
    "every Vulkan driver loaded": "device.load_only_lavapipe_driver = lambda adapter=None: False",
}
_PROGRAM = (
    "import sys; sys.argv = ['wgpu-shading', 'render', 'builtin:torus', '-o', sys.argv[1], '-q']; "
    "import importlib; program = importlib.import_module('wgpu_shading.cli.main'); "
    "import wgpu_shading.cli.process_start as process_start; import wgpu_shading.render.device as device; "
    "{undo}; program.console_main()"
)


def start_up(rounds: int, out: Path, callgrind: bool = False) -> None:
    variants = {"as shipped": "pass", **_UNDO, "all three undone": "; ".join(_UNDO.values())}
    environment = {key: value for key, value in os.environ.items() if key not in ("PYTHONDONTWRITEBYTECODE", "OPENBLAS_NUM_THREADS")}
    environment["PYTHONPYCACHEPREFIX"] = str(out.parent / "pycache")  # bytecode cached, as installed packages have it
    if callgrind:
        _start_up_instructions(variants, environment, out)
        return
    walls: dict[str, list[float]] = {name: [] for name in variants}
    cpus: dict[str, list[float]] = {name: [] for name in variants}
    start_load = os.getloadavg()[0]
    names = list(variants)
    for round_ in range(rounds + 1):  # the first round fills the bytecode and shader caches, untimed
        for name in names[round_ % len(names):] + names[: round_ % len(names)]:
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", _PROGRAM.format(undo=variants[name]), str(out)],
                           env=environment, cwd=REPO, check=True, capture_output=True)
            wall = time.perf_counter() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            if round_:
                walls[name].append(wall)
                cpus[name].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    print(f"`wgpu-shading render builtin:torus`, {rounds} interleaved rounds of fresh processes; "
          f"load average {start_load:.2f} → {os.getloadavg()[0]:.2f}")
    shipped_wall, shipped_cpu = statistics.median(walls["as shipped"]), statistics.median(cpus["as shipped"])
    for name in variants:
        wall, cpu = statistics.median(walls[name]), statistics.median(cpus[name])
        print(f"  {name:52s} wall {wall * 1e3:6.1f} ms ({wall / shipped_wall:.3f}×), CPU {cpu * 1e3:6.1f} ms ({cpu / shipped_cpu:.3f}×)")


def _start_up_instructions(variants: dict[str, str], environment: dict[str, str], out: Path) -> None:
    """Each variant once under callgrind (after an untimed run that fills the caches): the
    instructions of the whole process, which the machine's load does not change."""
    import re

    print("`wgpu-shading render builtin:torus`, instructions of the whole process (valgrind --tool=callgrind)")
    counts = {}
    for name, undo in variants.items():
        command = [sys.executable, "-c", _PROGRAM.format(undo=undo), str(out)]
        subprocess.run(command, env=environment, cwd=REPO, check=True, capture_output=True)
        result = subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out.parent / 'callgrind.out'}", *command],
            env=environment, cwd=REPO, check=True, capture_output=True, text=True,
        )
        counts[name] = int(re.search(r"Collected : (\d+)", result.stderr).group(1))
        print(f"  {name:52s} {counts[name] / 1e6:8.1f} M ({counts[name] / counts['as shipped']:.3f}×)")


def spread_folders(size: int, rounds: int, smoke: bool) -> None:
    import shutil
    import tempfile

    from benchmarks.dataset import new_file_micros, render_all
    from wgpu_shading import Renderer
    from wgpu_shading.dataset import output_folder

    what, jobs, scenes = _dataset_scenes(size, smoke)
    renderer = Renderer()
    shipped = output_folder.spread_subfolders
    creations: list[tuple[float, float]] = []
    with tempfile.TemporaryDirectory(prefix="ab-spread-folders-") as scratch:
        outputs = Path(scratch) / "runs"
        outputs.mkdir()
        inside: dict = {}
        batch = _batch_runner(renderer, outputs, inside)

        def with_mark(name: str, marked: bool):
            run = batch(name, jobs)

            def variant() -> None:
                output_folder.spread_subfolders = shipped if marked else (lambda folder: False)
                try:
                    run()
                finally:
                    output_folder.spread_subfolders = shipped
            return variant

        def remove_outputs() -> None:
            """The round before's outputs removed, as `rm -r OUT` before a rerun; then a new file timed."""
            for folder in list(outputs.iterdir()):
                shutil.rmtree(folder)
            creations.append((new_file_micros(Path(scratch)), new_file_micros(Path(scratch), spread=True)))

        variants = {"render + readback alone": lambda: render_all(renderer, scenes),
                    "marked (as shipped)": with_mark("batch, output folder marked (as shipped)", True),
                    "not marked": with_mark("batch, output folder not marked", False)}
        _print_batches(f"{what}; each round first removes the batches' outputs of the round before", variants,
                       rounds, len(jobs), inside, "render + readback alone", before_round=remove_outputs)
        _print_paired(inside, "batch, output folder not marked")
    print("a new empty file after the removals, µs (plain subfolder / mesh folder of a marked folder): "
          + ", ".join(f"{plain:.0f} / {spread:.0f}" for plain, spread in creations))


# The A/Bs on the dataset benchmark's scenes, each called as f(size, rounds, smoke).
DATASET_SCENE_ABS = {
    "chunks": chunks, "batch-parts": batch_parts, "kept-frames": kept_frames, "fresh-meshes": fresh_meshes,
    "frames-in-flight": frames_in_flight, "chunk-order": chunk_order, "thread-cpu": thread_cpu,
    "encoder-threads": encoder_threads, "dask-saturation": dask_saturation, "dask-client": dask_client, "per-mesh": per_mesh,
    "files-beside": files_beside, "spread-folders": spread_folders, "poll-gap": poll_gap, "vertex-cache": vertex_cache,
    "mesh-cache": mesh_cache, "mesh-cache-many": mesh_cache_many,
}


def main(argv: list[str] | None = None) -> int:
    global DATASET_VIEWS  # (--views)
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=("frame-memory", "poll", "frame-plans", "turned-away", "start-up", *DATASET_SCENE_ABS,
                                         "output-folders", "crease-split", "child"))
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--segments", type=int, default=72)
    parser.add_argument("--views", type=int, default=DATASET_VIEWS,
                        help="the dataset A/Bs: views of each mesh (48: the full benchmark's; 12: --quick's)")
    parser.add_argument("--smoke", action="store_true", help="a tiny torus at 32², a few frames, one run")
    parser.add_argument("--callgrind", action="store_true", help="start-up: instruction counts under valgrind instead of times")
    parser.add_argument("--folders", type=Path, nargs="+", default=None,
                        help="output-folders: the folders to write in (default: the system's temporary folder)")
    args = parser.parse_args(argv)
    if args.smoke:
        args.size, args.frames, args.runs, args.segments, args.rounds = 32, 3, 1, 8, 1
    # Every A/B parses the files it loads, as under `python -m benchmarks`, and writes nothing
    # into the user's cache folder; mesh-cache and mesh-cache-many choose their own folders.
    from wgpu_shading.assets.disk_cache import CACHE_VARIABLE

    os.environ[CACHE_VARIABLE] = "off"
    DATASET_VIEWS = args.views
    if args.what == "child":
        print(json.dumps(_one_process(args.size, args.frames, args.segments)))
    elif args.what in DATASET_SCENE_ABS:
        DATASET_SCENE_ABS[args.what](args.size, args.rounds, args.smoke)
    elif args.what == "output-folders":
        import tempfile

        output_folders(args.size, args.rounds, args.smoke, args.folders or [Path(tempfile.gettempdir())])
    elif args.what == "crease-split":
        crease_split(args.rounds, args.smoke)
    elif args.what == "poll":
        poll(args.size, args.rounds, args.segments)
    elif args.what == "frame-plans":
        frame_plans(args.size, args.rounds, args.segments)
    elif args.what == "turned-away":
        turned_away(args.size, args.rounds, args.segments)
    elif args.what == "start-up":
        import tempfile

        with tempfile.TemporaryDirectory() as folder:
            start_up(args.rounds, Path(folder) / "torus.png", callgrind=args.callgrind)
    else:
        frame_memory(args.size, args.frames, args.runs, args.segments)
    return 0


if __name__ == "__main__":
    sys.exit(main())
