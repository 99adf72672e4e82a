"""What runs inside a Dask worker: the plugin that makes its warm renderer, and the task.

Imports distributed at the top: import this module only once Dask is known to be there
(cluster.py checks and names the extra otherwise). Workers are spawned and unpickle these
by name, so they live in an importable module, never in __main__.
"""

from __future__ import annotations

from distributed import WorkerPlugin, get_worker, secede

from .chunk import ChunkRenderer, failed
from .jobs import Job

_ATTRIBUTE = "_wgpu_shading_chunk_renderers"  # on the distributed.Worker: plugin name → ChunkRenderer


class RendererPlugin(WorkerPlugin):
    """One warm ChunkRenderer per worker. Only the settings are pickled; the Renderer (not
    picklable) is built in setup(), which runs before the worker takes any task, on every
    worker, including those that join or are restarted later.

    The name carries the settings and the plugin is idempotent: the next run on the same
    cluster finds it registered and keeps the warm renderers (their pipelines, uploads)."""

    idempotent = True

    def __init__(self, adapter: str | None = None, parallel: int | None = 1):
        self.adapter, self.parallel = adapter, parallel
        self.name = f"wgpu-shading-renderer[adapter={adapter or 'default'},parallel={parallel}]"

    def setup(self, worker) -> None:
        renderers = getattr(worker, _ATTRIBUTE, None)
        if renderers is None:
            renderers = {}
            setattr(worker, _ATTRIBUTE, renderers)
        renderers[self.name] = ChunkRenderer(adapter=self.adapter, parallel=self.parallel)

    def teardown(self, worker) -> None:
        chunk_renderer = chunk_renderers(worker).pop(self.name, None)
        if chunk_renderer is not None:
            chunk_renderer.close()


def chunk_renderers(worker) -> dict[str, ChunkRenderer]:
    """The warm renderers RendererPlugin made on this worker, by plugin name (empty before
    its setup, or where setup failed)."""
    return getattr(worker, _ATTRIBUTE, {})


def render_chunk_task(jobs: list[Job], out_dir: str, plugin_name: str, run: str | None = None) -> list[dict]:
    """The Dask task: render a chunk on this worker's warm renderer; its result is the
    chunk's records once all its files are complete. `run`: the run's own name, so that
    meshes the renderer kept from an earlier run are read again (ChunkRenderer.start).

    Once its frames are rendered, the task leaves the worker's thread pool (Dask's
    `secede`) to wait for its last writes, so that the worker starts its next chunk
    meanwhile, as the in-process loop does (ChunkRenderer.start): the device does not sit
    idle at every task's end while up to MAX_PENDING_WRITES frames are encoded and written.
    A seceded task "opens up a new scheduling slot and a new thread for a new task"
    (distributed.secede's docstring): the scheduler counts it as long-running, not
    against the worker's threads (`_task_slots_available` in distributed/scheduler.py)."""
    chunk_renderer = chunk_renderers(get_worker()).get(plugin_name)
    if chunk_renderer is None:  # the plugin's setup failed on this worker (logged there)
        return [failed(job, "this Dask worker has no renderer: its set-up failed (see the worker's log)") for job in jobs]
    pending = chunk_renderer.start(jobs, out_dir, run)
    secede()
    return pending.finish()
