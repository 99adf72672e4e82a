"""What runs inside a Dask worker: the plugin that makes its warm renderer, and the task.

Imports distributed at the top: import this module only once Dask is known to be there
(cluster.py checks and names the extra otherwise). Workers are spawned and unpickle these
by name, so they live in an importable module, never in __main__.
"""

from __future__ import annotations

from distributed import WorkerPlugin, get_worker

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


def render_chunk_task(jobs: list[Job], out_dir: str, plugin_name: str) -> list[dict]:
    """The Dask task: render a chunk on this worker's warm renderer."""
    chunk_renderer = chunk_renderers(get_worker()).get(plugin_name)
    if chunk_renderer is None:  # the plugin's setup failed on this worker (logged there)
        return [failed(job, "this Dask worker has no renderer: its set-up failed (see the worker's log)") for job in jobs]
    return chunk_renderer.render(jobs, out_dir)
