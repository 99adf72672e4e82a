"""Rendering a chunk of jobs on one warm Renderer: the mesh is loaded and uploaded once per
chunk, frames are pipelined (Renderer.render_many), and PNG encoding and file writing run on
a small thread pool while the next frames render. The next chunk's mesh can be loaded on a
thread of its own meanwhile (`prefetch`): loading a file is Python and numpy work that the
frames of this chunk leave room for, since the main thread mostly waits for the driver.

Errors are data: a job that fails (unreadable mesh, bad camera, full disk) gets a record
with ok=False and its error; the other jobs of the chunk go on.
"""

from __future__ import annotations

import os
import socket
import threading
import time
from collections import OrderedDict, deque
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path

from ..errors import WgpuShadingError
from ..render.passes.extra_outputs import ExtraFrame
from ..render.renderer import Renderer
from .cameras import camera_record, id_legend
from .jobs import Job
from .views import base_scene, job_scene
from .writer import write_view

MAX_PENDING_WRITES = 8  # frames waiting for the encoder: bounds memory when encoding lags
MAX_ENCODER_THREADS = 4
# Base scenes kept between chunks of one run: the next chunk is usually the same mesh's next
# views, and loading a mesh file can cost more than rendering its chunk (the 70k-triangle
# bunny OBJ: 0.14 s). Never between runs: a file may have changed since (start(), `run`).
KEPT_SCENES = 2
HOST = socket.gethostname()  # with the pid, which worker a record's spans belong to


def default_encoder_threads() -> int:
    """Half the cores, 1 to MAX_ENCODER_THREADS. On lavapipe the frames themselves keep ~1.5
    of 2 cores busy, and a second encoder thread there competes with them: in six runs of
    alternating rounds of the dataset benchmark (256² and 512²) one thread was faster
    inside the chunks in 61 of 92 rounds, by 0-5 % (`ab_issue29.py encoder-threads`;
    docs/performance.md, "Where a dataset frame goes", the tenth pass).
    With more cores, or frames drawn by a GPU in a fraction of the ~1-2 ms of CPU a
    frame's files take, one thread could not keep up."""
    return max(1, min(MAX_ENCODER_THREADS, (os.cpu_count() or 2) // 2))


def describe(error: BaseException) -> str:
    """One line: our own errors are already sentences; others get their type."""
    if isinstance(error, WgpuShadingError):
        return str(error)
    return f"{type(error).__name__}: {error}"


def failed(job: Job, error: BaseException | str) -> dict:
    message = error if isinstance(error, str) else describe(error)
    return {"id": job.id, "ok": False, "error": message, "files": [], "pid": os.getpid()}


def _load(job: Job):
    """The job's base scene, or the error that loading it raised (it fails that mesh's jobs only)."""
    try:
        return base_scene(job)
    except Exception as error:  # noqa: BLE001
        return error


class ChunkRenderer:
    """One per process (or Dask worker): a warm Renderer and the encoders.
    Calls of render() from several threads (a Dask worker with --nthreads above 1) take
    turns: a Renderer is used by one thread at a time.

    parallel: devices render_many spreads frames over (None: its default, 2 on lavapipe;
    1 when several workers already share the cores). encoder_threads: threads that encode
    and write the files (None: default_encoder_threads())."""

    def __init__(self, renderer: Renderer | None = None, *, adapter: str | None = None,
                 parallel: int | None = None, encoder_threads: int | None = None):
        self.renderer = renderer if renderer is not None else Renderer(adapter=adapter)
        self.parallel = parallel
        self._kept: OrderedDict[tuple, object] = OrderedDict()  # load_key → base scene, newest last
        self._run: object = None  # the run whose scenes are kept (start())
        self._loading: dict[tuple, Future] = {}  # load_key → its base scene being loaded by prefetch()
        self._loading_lock = threading.Lock()  # prefetch() may run while another thread renders
        self._lock = threading.Lock()
        threads = default_encoder_threads() if encoder_threads is None else encoder_threads
        self._encoders = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="wgpu-shading-encode")
        self._loader = ThreadPoolExecutor(max_workers=1, thread_name_prefix="wgpu-shading-load")

    def close(self) -> None:
        self._encoders.shutdown(wait=True)
        self._loader.shutdown(wait=True, cancel_futures=True)

    def prefetch(self, jobs: list[Job]) -> None:
        """Start loading the meshes of `jobs` (the next chunk) on the loader thread, unless
        they are kept or loading already; render() then takes them from there."""
        with self._loading_lock:
            for job in jobs:
                key = job.load_key()
                if key not in self._kept and key not in self._loading:
                    self._loading[key] = self._loader.submit(_load, job)

    def _base_scene(self, job: Job):
        """The job's base scene, kept for the next chunks; a load error is returned (it fails
        this chunk's jobs of that mesh) and not kept (the file may be fixed by the next run)."""
        key = job.load_key()
        if key in self._kept:
            self._kept.move_to_end(key)
            return self._kept[key]
        with self._loading_lock:
            loading = self._loading.pop(key, None)
        scene = loading.result() if loading is not None else _load(job)
        if isinstance(scene, BaseException):
            return scene
        self._kept[key] = scene
        while len(self._kept) > KEPT_SCENES:
            self._kept.popitem(last=False)
        return scene

    def render(self, jobs: list[Job], out_dir: str | Path, run: object = None) -> list[dict]:
        """Render and write `jobs`; one record per job, in order, with the chunk's `spans`
        of work (PendingChunk.finish)."""
        return self.start(jobs, out_dir, run).finish()

    def start(self, jobs: list[Job], out_dir: str | Path, run: object = None) -> "PendingChunk":
        """Render `jobs` and queue their writes; `finish()` of the result waits for the writes
        and gives the records. A process that renders chunk after chunk starts the next one
        before it finishes this one, so that this chunk's last writes run while the next
        chunk renders, instead of leaving the device idle at every chunk's end (up to
        MAX_PENDING_WRITES frames each; docs/performance.md, "Where a dataset frame goes").

        `run`: what the chunk's run calls itself (render_dataset gives each run on Dask a
        new one; calls that give none are one run). The meshes kept from another run's
        chunks are let go first: a Dask worker's renderer serves run after run, and a mesh
        file (or its materials, textures, a scene's meshes) edited between two runs must be
        read again, not drawn as it was."""
        with self._lock:
            if run != self._run:
                self._kept.clear()
                self._run = run
            return self._render(jobs, out_dir)

    def _render(self, jobs: list[Job], out_dir: str | Path) -> "PendingChunk":
        start = time.monotonic()
        out_dir = Path(out_dir)
        records: dict[str, dict] = {}
        writes: deque[tuple[Job, dict, Future]] = deque()
        ready: list[tuple[Job, object]] = []
        bases: dict[tuple, object] = {}
        for job in jobs:
            key = job.load_key()
            try:
                if key not in bases:
                    bases[key] = self._base_scene(job)
                base = bases[key]
                if isinstance(base, BaseException):
                    raise base
                scene = job_scene(base, job)
                # Checked here, so a size the adapter cannot render fails this job only.
                float_target = job.outputs.color == "png16" or job.outputs.normals != "none" or job.outputs.ids
                self.renderer.check_size(scene.size, float32=float_target)
                ready.append((job, scene))
            except Exception as error:  # noqa: BLE001
                records[job.id] = failed(job, error)
        # Jobs with the same outputs share one pipelined stream of frames.
        streams: dict[tuple, list] = {}
        for job, scene in ready:
            streams.setdefault((job.outputs.color, job.outputs.depth, job.outputs.normals, job.outputs.ids), []).append((job, scene))
        for (color, depth, normals, ids), items in streams.items():
            self._render_stream(items, out_dir, color, depth, normals, ids, writes, records)
        return PendingChunk(jobs, records, writes, (start, time.monotonic()))

    def _render_stream(self, items, out_dir, color, depth, normals, ids, writes, records) -> None:
        scenes = [scene for _, scene in items]
        # One pipelined stream: each frame's colour pass (when colour or depth is written)
        # and its normals-and-ids pass are encoded together (render/passes/extra_outputs.py).
        extras = normals != "none" or ids
        frames = self.renderer.render_many(
            scenes, float32=color == "png16", depth=depth != "none",
            normals=(normals if normals != "none" else "eye") if extras else None, ids=ids,
            color=color != "none" or depth != "none", parallel=self.parallel,
        )
        done = 0
        try:
            for (job, scene), frame in zip(items, frames):
                extra = ExtraFrame(normals=frame.normals, ids=frame.ids) if extras else None
                if frame.color is None:
                    frame = None  # only normals and ids were asked for
                camera = camera_record(scene)
                if ids:
                    camera["ids"] = id_legend(scene)
                writes.append((job, camera, self._encoders.submit(write_view, out_dir, job, frame, extra, camera)))
                done += 1
                while len(writes) > MAX_PENDING_WRITES:
                    _collect(writes.popleft(), records)
        except Exception as error:  # noqa: BLE001 - the device failed: the rest of this stream fails
            for job, _ in items[done:]:
                records[job.id] = failed(job, error)


def _collect(entry: tuple[Job, dict, Future], records: dict) -> None:
    """The record of one job whose files were being written: its files and camera (what
    cameras.json lists, so the run need not read them back), or its error."""
    job, camera, future = entry
    try:
        files = future.result()
    except Exception as error:  # noqa: BLE001
        records[job.id] = failed(job, error)
        return
    records[job.id] = {"id": job.id, "ok": True, "error": None, "files": files, "camera": camera, "pid": os.getpid()}


class PendingChunk:
    """A rendered chunk whose last writes may still run (ChunkRenderer.start)."""

    def __init__(self, jobs: list[Job], records: dict[str, dict], writes: deque, rendering: tuple[float, float]):
        self.jobs, self._records, self._writes, self._rendering = jobs, records, writes, rendering

    def finish(self) -> list[dict]:
        """Wait for the chunk's writes; one record per job, in order. Each carries the
        chunk's `spans`: when it rendered and when it waited for its last writes
        (time.monotonic(), one clock for every process of a machine), and the worker's
        `pid` and `host`: on Dask the wait of one chunk runs while the next one renders,
        so a run's time inside chunks is the union of each worker's spans
        (run.busy_time), not their sum."""
        start = time.monotonic()
        while self._writes:
            _collect(self._writes.popleft(), self._records)
        spans = [list(self._rendering), [start, time.monotonic()]]
        return [{**self._records[job.id], "spans": spans, "host": HOST} for job in self.jobs]
