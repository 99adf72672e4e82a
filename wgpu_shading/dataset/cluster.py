"""Dask execution: a LocalCluster of spawned processes, or an existing cluster by address.

Each worker keeps one warm ChunkRenderer, made once by a WorkerPlugin (the scheduler hands
the plugin to workers that join later, and to a worker the nanny restarts after a crash).
Only the plugin's settings are pickled; the Renderer (not picklable) is built on the worker.
A task is a chunk of views of one mesh. A chunk whose worker died (KilledWorker) is retried
one job per task, and a single job that died is tried once more when nothing else runs, so
a job that kills its worker fails alone and is named in the report, and a job that only
waited on a dying worker is rendered.
Workers write their files themselves (atomically) and return only small records.

Processes are spawned, never forked: forking after wgpu is set up hangs the child.
"""

from __future__ import annotations

import logging
import os
import uuid
from pathlib import Path
from typing import Iterator

from ..errors import UsageError, WgpuShadingError
from .jobs import Job


class DaskMissingError(WgpuShadingError):
    pass


def _distributed():
    try:
        import distributed
    except ImportError:
        from ..errors import install_hint

        raise DaskMissingError(f"--workers above 1 and --scheduler need Dask; {install_hint('dask')}") from None
    return distributed


# Dask's settings for the local cluster's scheduler and workers (local_cluster).
LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.multiprocessing-method": "spawn",
    # A worker's death blames every task it was processing: with one task in flight per
    # 1-thread worker, only the chunk it was running. Two a worker (2.0: the next chunk
    # waiting on the worker, so no scheduler round trip between chunks) was tried and not
    # kept: 0.52-0.58 against 0.58-0.63 ms a 256² frame outside the chunks, but end to end
    # 1.0 was faster in 11 of 20 alternating rounds (`ab_issue29.py dask-saturation`;
    # docs/performance.md, "Where a dataset frame goes", the tenth pass).
    "distributed.scheduler.worker-saturation": 1.0,
    "distributed.scheduler.allowed-failures": 1,
    # Dask starts workers with MALLOC_TRIM_THRESHOLD_=65536, which turns off glibc's
    # adaptive mmap threshold: every frame-sized array is then mmapped and page-faulted
    # afresh. Measured: 25 % more CPU per 256² frame (5.2 → 4.1 ms in a worker).
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
    # The statistical profiler samples the task thread every 10 ms; nobody reads it here.
    "distributed.worker.profile.enabled": False,
}


def local_cluster(workers: int, lavapipe_threads: int | None = None):
    """A LocalCluster of `workers` spawned single-threaded processes; lavapipe's threads
    (LP_NUM_THREADS) split between them: cores // workers each unless given."""
    distributed = _distributed()
    import dask

    threads = lavapipe_threads if lavapipe_threads is not None else max(1, (os.cpu_count() or 1) // workers)
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        return distributed.LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            # No dashboard; the scheduler's small HTTP server (health, metrics) on a free port.
            scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"},
            silence_logs=logging.CRITICAL,
            host="127.0.0.1",
            memory_limit=0,
            env={"LP_NUM_THREADS": str(threads)},
        )


def run_on_dask(
    work: list[list[Job]],
    out_dir: Path,
    *,
    workers: int = 2,
    scheduler: str | None = None,
    client=None,
    adapter: str | None = None,
    lavapipe_threads: int | None = None,
) -> Iterator[list[dict]]:
    """Records of every chunk as they finish (any order). `client`: the caller's, used and
    left open; otherwise a client of a new local cluster or of `scheduler`, closed at the end."""
    distributed = _distributed()
    cluster = None
    own_client = client is None
    if client is not None:
        if not isinstance(client, distributed.Client):
            raise UsageError(f"client: expected a distributed.Client, got {type(client).__name__}")
        if client.status not in ("running", "connecting"):
            raise UsageError(f"client: this Dask client is {client.status}, not running")
        if client.asynchronous:
            raise UsageError("client: an asynchronous Dask client; render_dataset waits for results, so it needs a synchronous one")
    elif scheduler is None:
        cluster = local_cluster(workers, lavapipe_threads)
        client = distributed.Client(cluster)
    else:
        client = _connect(distributed, scheduler)
    try:
        from .worker import RendererPlugin

        # Workers share the cores: one device each (render_many's second device would
        # oversubscribe them). Idempotent: a cluster that has it keeps its warm renderers.
        plugin = RendererPlugin(adapter, parallel=1)
        client.register_plugin(plugin)
        yield from _stream(client, work, str(out_dir.resolve()), plugin.name, distributed)
    finally:
        if own_client:
            client.close(timeout=10)
        if cluster is not None:
            cluster.close(timeout=10)


def _connect(distributed, scheduler: str):
    """A client of an existing cluster; a malformed or unreachable address is bad input
    (exit 2, one line), not Dask's ValueError or OSError traceback."""
    try:
        if not scheduler.startswith(("tcp://", "tls://", "inproc://", "ucx://")) and Path(scheduler).is_file():
            return distributed.Client(scheduler_file=scheduler, timeout=30)
        return distributed.Client(scheduler, timeout=30)
    except (ValueError, OSError, TimeoutError) as error:  # OSError covers refused connections
        message = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise UsageError(f"--scheduler {scheduler!r}: cannot connect to a Dask scheduler there ({message})") from None


def _stream(client, work: list[list[Job]], out_dir: str, plugin_name: str, distributed) -> Iterator[list[dict]]:
    from .worker import render_chunk_task

    # Unique per run: in the keys (a reused key returns an old result) and for the workers'
    # renderers, which read a run's meshes anew (ChunkRenderer.start).
    run = uuid.uuid4().hex[:12]

    def submit(chunk: list[Job], key: str):
        return client.submit(render_chunk_task, chunk, out_dir, plugin_name, run, key=f"wgpu-shading-{key}-{run}", pure=False)

    futures = {submit(chunk, f"chunk-{index}"): chunk for index, chunk in enumerate(work)}
    try:
        yield from _gather(futures, submit, client, distributed)
    finally:
        # Stopped early (an error, Ctrl-C, a caller that closed the generator): the chunks
        # not begun are cancelled, also on a caller's client that stays open. A running
        # one finishes its files (each complete or absent) and is let go.
        if futures:
            try:
                client.cancel(list(futures))
            except Exception:  # noqa: BLE001 - a client closed or cut off meanwhile: its futures went with it,
                pass  # and the error that stopped the run is the one to report


def _gather(futures: dict, submit, client, distributed) -> Iterator[list[dict]]:
    # This client's loop, not the default client's: a process may hold other clients (a
    # notebook's, a test's), and as_completed would otherwise wait on another loop.
    pending = distributed.as_completed(futures, loop=client.loop)
    # A worker's death blames every task it held, not only the one that killed it: a job
    # waiting on that worker twice is called KilledWorker too. So a single job that died is
    # only a suspect until it has died again while nothing else ran (tried last, one by one).
    suspects: list[list[Job]] = []
    for future in pending:
        chunk = futures.pop(future)
        try:
            records = future.result()
        except distributed.KilledWorker:
            future.release()
            if len(chunk) > 1:  # find the job that kills workers: retry one job per task
                for job in chunk:
                    single = submit([job], f"job-{job.id}")
                    futures[single] = [job]
                    pending.add(single)
            else:
                suspects.append(chunk)
            continue
        except Exception as error:  # noqa: BLE001 - a bug in the task itself: report, go on
            records = [_failure(job, f"{type(error).__name__}: {error}") for job in chunk]
        future.release()
        yield _checked(records, chunk)
    for chunk in suspects:
        future = submit(chunk, f"alone-{chunk[0].id}")
        futures[future] = chunk  # cancelled if the run stops meanwhile
        try:
            records = future.result()
        except distributed.KilledWorker as error:
            records = [_failure(job, f"the worker rendering it died repeatedly ({error})") for job in chunk]
        except Exception as error:  # noqa: BLE001
            records = [_failure(job, f"{type(error).__name__}: {error}") for job in chunk]
        del futures[future]
        future.release()
        yield _checked(records, chunk)


def _checked(records: list[dict], chunk: list[Job]) -> list[dict]:
    """The records of the chunk's jobs, in order, or each job failed if a worker answered for others."""
    if [record["id"] for record in records] != [job.id for job in chunk]:
        return [_failure(job, "internal error: the worker returned results of other jobs") for job in chunk]
    return records


def _failure(job: Job, message: str) -> dict:
    from .chunk import failed

    return failed(job, message)
