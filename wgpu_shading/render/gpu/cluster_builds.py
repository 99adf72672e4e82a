"""The CPU work of a clustered upload, done off the render thread.

An upload that asks for clusters (mesh_uploads.asks_for_clusters) costs the 1.3M-triangle
sphere ~1.65 s CPU before any buffer is made: the exact closed-surface check (0.65 s) and
the vertex-cache order with its clusters (clusters.py, 1.0 s). Done inside a frame, that
froze a live view for two seconds (docs/performance.md, "the vertex-bound sphere"). So
it runs on a worker thread while frames keep drawing the upload without clusters; the
first frame after it is done makes the clustered upload from its result (the GPU buffers,
made on the render thread: ~35 ms for the sphere). Frames are the same pixels either way.

The rules it keeps (docs/reliability.md, "Threads"):
- One worker per renderer, shared with its render_many helpers (Renderer.parallel_renderers):
  one big build at a time, whose working arrays are about twice the mesh's arrays. A
  build's queue is at most one build per upload (an upload keeps the one it started).
- A build belongs to the upload that asked for it (GpuMesh.cluster_build). The worker holds
  only weak references to it and to the mesh: once that upload is gone (the mesh garbage-
  collected, the upload evicted or replaced, the renderer dropped), the worker stops at its
  next step and nothing it made is ever applied, to that mesh or another one.
- When the interpreter exits (which joins the executor's threads) the worker stops at its
  next step too, so exit waits for at most one step (~1 s for the sphere), not a whole build.
- An exception in the build is logged; the mesh simply stays without clusters.
- workers=0 builds on the calling thread, inside the frame that asks (the synchronous way
  the tests use); `wait()` lets a benchmark wait for every build started so far
  (benchmarks/scenes.settle), after which the next frame of each mesh is clustered.
"""

from __future__ import annotations

import logging
import threading
import weakref
from dataclasses import dataclass
from functools import cache, partial
from typing import TYPE_CHECKING

import numpy as np

from .vertex_order import ScratchIndices, SharedOrders, VertexOrder, cache_order

if TYPE_CHECKING:
    from concurrent.futures import Future, ThreadPoolExecutor

logger = logging.getLogger(__name__)

# Worker threads of a renderer's builds (ClusterBuilds reads it when made; 0: none, each
# build runs inside the frame that asks for it).
BUILD_WORKERS = 1


@cache
def _exiting() -> threading.Event:
    """Set when the interpreter begins to exit, by the standard library's hook that runs
    before exit joins worker threads. concurrent.futures.thread registers its own join there
    when imported, so it is imported first: the hooks run newest first, and this one is set
    before that join. Made once, with the first worker (a process that never builds on one
    imports neither: cold start)."""
    import concurrent.futures.thread  # noqa: F401  (its hook first)

    event = threading.Event()
    threading._register_atexit(event.set)
    return event


@dataclass
class BuiltOrder:
    """What a build made: the reordered flat index buffer and its vertex order, clusters
    included; `scratch` holds `indices` when the build computed them (release() after the
    upload), None when they are a sibling device's copy (vertex_order.SharedOrders)."""

    indices: np.ndarray
    order: VertexOrder
    scratch: ScratchIndices | None = None

    def release(self) -> None:
        if self.scratch is not None:
            self.scratch.close()


class ClusterBuild:
    """One build, held by the upload that asked for it (GpuMesh.cluster_build)."""

    def __init__(self) -> None:
        self.future: Future | None = None

    def done(self) -> bool:
        return self.future is not None and self.future.done()

    def result(self) -> BuiltOrder | None:
        """The built order (once done()), or None: the mesh stays without clusters (not a
        closed surface, no part big enough, the build failed or was stopped)."""
        return self.future.result() if self.future is not None else None


class ClusterBuilds:
    """The worker that builds a renderer's clusters (module docstring), made on its first
    build: a renderer that never clusters starts no thread. Thread-safe: the render threads
    of a renderer and its helpers start builds on it."""

    def __init__(self, workers: int | None = None):
        self.workers = BUILD_WORKERS if workers is None else workers
        self._executor: ThreadPoolExecutor | None = None
        self._lock = threading.Lock()
        self._running: set[Future] = set()

    def start(self, mesh, in_order: frozenset[int], shared: SharedOrders | None) -> ClusterBuild:
        """Start building the clustered order of `mesh` (the parts not in `in_order`);
        keep the returned build with the upload that waits for it."""
        from concurrent.futures import Future, ThreadPoolExecutor

        build = ClusterBuild()
        job = partial(_build, weakref.ref(build), weakref.ref(mesh), frozenset(in_order), shared)
        if self.workers <= 0:
            build.future = Future()
            build.future.set_result(job())
            return build
        running, lock = self._running, self._lock

        def finished(future: Future) -> None:  # (holds the set, not this object)
            with lock:
                running.discard(future)

        with lock:
            if self._executor is None:
                _exiting()
                self._executor = ThreadPoolExecutor(self.workers, thread_name_prefix="wgpu-shading-clusters")
            build.future = self._executor.submit(job)
            running.add(build.future)
        build.future.add_done_callback(finished)
        return build

    def wait(self, timeout: float | None = None) -> None:
        """Wait until every build started so far is done (or `timeout` seconds have passed)."""
        from concurrent.futures import wait

        with self._lock:
            running = list(self._running)
        wait(running, timeout)


def _build(build_ref, mesh_ref, in_order: frozenset[int], shared: SharedOrders | None) -> BuiltOrder | None:
    try:
        return _steps(build_ref, mesh_ref, in_order, shared)
    except Exception:  # a bug or a full memory: the mesh is drawn as it is, the view goes on
        mesh = mesh_ref()
        logger.exception("building the clusters of %s failed: it is drawn without them", getattr(mesh, "name", "a mesh"))
        return None


def _steps(build_ref, mesh_ref, in_order: frozenset[int], shared: SharedOrders | None) -> BuiltOrder | None:
    """The build, a step at a time; before each step, the mesh (None: stop, module docstring)."""

    def still_wanted():
        mesh = mesh_ref()
        if mesh is None or build_ref() is None or _exiting().is_set():
            return None
        return mesh

    mesh = still_wanted()
    if mesh is None:
        return None
    taken = shared.take(mesh, in_order, clusters=True) if shared is not None else None
    if taken is not None:  # a sibling device built it already
        return BuiltOrder(taken[0], taken[1])
    if mesh.exact_solid != 1:  # (clusters.py: only a closed surface wound outwards)
        return None
    arrays = mesh.indices, mesh.vertex_count, mesh.parts
    positions = mesh.positions
    del mesh  # (its arrays are enough: the mesh may go meanwhile)
    if still_wanted() is None:
        return None
    scratch, order = cache_order(*arrays, in_order, positions)
    del arrays, positions
    mesh = still_wanted()
    if order.clusters is None or mesh is None:  # no part big enough, or no longer wanted
        scratch.close()
        return None
    if shared is not None:
        shared.offer(mesh, in_order, scratch.array, order)
    return BuiltOrder(scratch.array, order, scratch)
