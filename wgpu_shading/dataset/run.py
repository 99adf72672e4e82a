"""Running a dataset: skip what is done, render the rest in chunks (in this process, on a
local Dask cluster, or on an existing one), show progress, write cameras.json per mesh
folder and report.json for the run."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Iterable, Iterator

from ..errors import UsageError
from .cameras import CONVENTION
from .jobs import Job, chunks
from .lock import folder_lock
from .names import CAMERAS_FILE, REPORT_FILE, check_output_names
from .output_folder import make_output_folder
from .writer import atomic_write, finished, json_text, remove_stale_temporaries

if TYPE_CHECKING:  # the optional `dask` extra
    from distributed import Client

DEFAULT_CHUNK = 16  # views of one mesh per task: spreads Dask's 2-5 ms a task over many frames


@dataclass
class BatchResult:
    """What a run did. failed: job id → one-line error (also in OUTPUT/report.json)."""

    total: int
    rendered: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    failed: dict[str, str] = field(default_factory=dict)
    seconds: float = 0.0
    busy_seconds: float = 0.0  # time inside chunks (loading, rendering, writing), summed over workers: busy_time()

    @property
    def frames_per_second(self) -> float:
        return len(self.rendered) / self.seconds if self.seconds > 0 else 0.0

    def summary(self) -> str:
        text = (
            f"{len(self.rendered)} rendered, {len(self.skipped)} skipped (already done), "
            f"{len(self.failed)} failed of {self.total} jobs in {self.seconds:.1f} s "
            f"({self.frames_per_second:.1f} frames/s)"
        )
        return text


def render_dataset(
    jobs: list[Job],
    output: str | Path,
    *,
    workers: int = 1,
    scheduler: str | None = None,
    chunk_size: int = DEFAULT_CHUNK,
    progress: bool = True,
    adapter: str | None = None,
    lavapipe_threads: int | None = None,
    renderer=None,
    parallel: int | None = None,
    client: Client | None = None,
) -> BatchResult:
    """Render every job into `output` (one folder per mesh) and return what happened.

    workers=1 renders in this process with frame pipelining; workers=N>1 starts a Dask
    LocalCluster of N processes; scheduler="tcp://host:port" (or a scheduler file) uses an
    existing Dask cluster. Jobs whose outputs exist and match their manifest row are skipped.
    `renderer`: render in-process on this Renderer (yours, on your device) instead of a new one;
    `parallel`: its render_many devices (None: 2 on lavapipe). Dask workers use one each.
    `client`: a distributed.Client you hold (a notebook's, a service's): render on its cluster
    and leave it open. One connection for many runs, where scheduler= connects and closes
    each time (~17 ms a run on a local cluster: docs/datasets.md).
    """
    if not jobs:
        raise UsageError("batch: no jobs")
    if workers < 1:
        raise UsageError(f"--workers must be at least 1, got {workers}")
    if client is not None and (workers != 1 or scheduler is not None):
        raise UsageError("render_dataset: give one of workers above 1 (a new local cluster), scheduler or client, not several")
    if client is not None and renderer is not None:
        raise UsageError("render_dataset: renderer renders in this process, client on a Dask cluster: give one of them")
    check_output_names(jobs)  # before anything is made: two jobs never write one file
    out_dir = Path(output)
    try:
        make_output_folder(out_dir)  # its mesh folders away from files removed nearby
    except OSError as error:
        raise UsageError(f"output folder {str(out_dir)!r}: {error.strerror or error}") from None
    with folder_lock(out_dir):  # one run per folder: its clean-up removes nothing of another's
        return _run(jobs, out_dir, workers, scheduler, client, chunk_size, progress, adapter, lavapipe_threads, renderer, parallel)


def _run(jobs, out_dir: Path, workers, scheduler, client, chunk_size, progress, adapter, lavapipe_threads, renderer, parallel) -> BatchResult:
    start = time.perf_counter()
    remove_stale_temporaries(out_dir)  # left by killed runs: no other run writes here now
    result = BatchResult(total=len(jobs))
    todo = []
    views: dict[str, dict] = {}  # job id → the files and camera of its finished view, for cameras.json
    for job in jobs:
        record = finished(out_dir, job)
        if record is not None:
            result.skipped.append(job.id)
            views[job.id] = record
        else:
            todo.append(job)
    work = chunks(todo, chunk_size) if todo else []
    bar = _progress_bar(len(todo), progress)
    spans: dict[tuple, set] = {}  # worker (host, pid) → its chunks' spans of work (a chunk's jobs share them)
    completed = False
    try:
        for records in _execute(work, out_dir, workers, scheduler, client, adapter, lavapipe_threads, renderer, parallel):
            for record in records:
                if "spans" in record:
                    spans.setdefault((record.get("host"), record["pid"]), set()).update(map(tuple, record["spans"]))
                if record["ok"]:
                    result.rendered.append(record["id"])
                    if "camera" in record:  # (a worker of an older version sends none: read back below)
                        views[record["id"]] = record
                else:
                    result.failed[record["id"]] = record["error"]
            if bar is not None:
                elapsed = time.perf_counter() - start
                bar.set_postfix(failed=len(result.failed), fps=f"{len(result.rendered) / max(elapsed, 1e-9):.1f}", refresh=False)
                bar.update(len(records))  # redraws, with the postfix
        completed = True
    finally:
        if bar is not None:
            bar.close()
        result.seconds = time.perf_counter() - start
        result.busy_seconds = sum(busy_time(worker_spans) for worker_spans in spans.values())
        remove_stale_temporaries(out_dir)
        # A run that stopped early may have written views whose records never reached this
        # loop: then every view not known is looked for on disk, as a later run would.
        _write_cameras(out_dir, jobs, views, None if not completed else set(result.rendered))
        _write_report(out_dir, result)
    return result


def busy_time(spans: Iterable[tuple[float, float]]) -> float:
    """Seconds covered by a worker's spans of work (their union: a Dask worker renders its
    next chunk while the last one waits for its writes; the spans of one chunk's jobs are
    the same spans)."""
    covered, reached = 0.0, float("-inf")
    for start, end in sorted(set(spans)):
        if end > reached:
            covered += end - max(start, reached)
            reached = end
    return covered


def _progress_bar(total: int, enabled: bool):
    if not enabled or total == 0:
        return None
    from tqdm import tqdm

    return tqdm(total=total, unit="frame", smoothing=0.1, dynamic_ncols=True)


def _execute(work, out_dir: Path, workers: int, scheduler: str | None, client, adapter, lavapipe_threads, renderer, parallel) -> Iterator[list[dict]]:
    if not work:
        return
    if workers == 1 and scheduler is None and client is None:
        yield from _in_process(work, out_dir, adapter, renderer, parallel)
        return
    from .cluster import run_on_dask

    yield from run_on_dask(work, out_dir, workers=workers, scheduler=scheduler, client=client, adapter=adapter, lavapipe_threads=lavapipe_threads)


def _in_process(work: list[list[Job]], out_dir: Path, adapter, renderer, parallel) -> Iterator[list[dict]]:
    from .chunk import ChunkRenderer

    chunk_renderer = ChunkRenderer(renderer, adapter=adapter, parallel=parallel)
    pending = None
    try:
        for index, chunk in enumerate(work):
            if index + 1 < len(work):
                chunk_renderer.prefetch(work[index + 1])  # loads while this chunk renders
            started = chunk_renderer.start(chunk, out_dir)  # renders while the last chunk's writes end
            if pending is not None:
                yield pending.finish()
            pending = started
        if pending is not None:
            yield pending.finish()
    finally:
        chunk_renderer.close()  # waits for every write queued: its file is complete or absent


def _write_cameras(out_dir: Path, jobs: list[Job], known: dict[str, dict], read_back: set[str] | None) -> None:
    """cameras.json in each mesh folder: the camera of every finished view of this manifest.
    `known`: the records of the views found finished at the start and of those this run
    wrote (files and camera, as in their record files: reading 192 of them back cost
    ~10 ms of a 1.2 s run). Views not known are looked for on disk if in `read_back`
    (None: all of them)."""
    folders: dict[str, dict] = {}
    for job in jobs:
        views = folders.setdefault(job.folder, {})
        record = known.get(job.id)
        if record is None and (read_back is None or job.id in read_back):
            record = finished(out_dir, job)
        if record is not None:
            views[job.name] = {"id": job.id, "files": record["files"], **record["camera"]}
    for folder, views in folders.items():
        if views and (out_dir / folder).is_dir():  # a mesh folder removed meanwhile gets none
            data = {"convention": CONVENTION, "views": views}
            atomic_write(out_dir / folder / CAMERAS_FILE, lambda file, data=data: file.write(json_text(data)))


def _write_report(out_dir: Path, result: BatchResult) -> None:
    report = {
        "jobs": result.total,
        "rendered": len(result.rendered),
        "skipped": len(result.skipped),
        "failed": result.failed,
        "seconds": round(result.seconds, 3),
        "frames_per_second": round(result.frames_per_second, 2),
    }
    atomic_write(out_dir / REPORT_FILE, lambda file: file.write(json_text(report)))

