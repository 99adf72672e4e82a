"""Dataset rendering on Dask: a worker killed mid-run, and a separately started cluster."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

distributed = pytest.importorskip("distributed")  # the test extra installs it

from wgpu_shading.cli import main  # noqa: E402
from wgpu_shading.dataset import Outputs, mesh_jobs, render_dataset, turntable_views  # noqa: E402
from wgpu_shading.dataset.cluster import local_cluster  # noqa: E402
from wgpu_shading.dataset.worker import chunk_renderers  # noqa: E402
from wgpu_shading.errors import UsageError  # noqa: E402

MESHES = ["builtin:torus?segments=24", "builtin:sphere?slices=24&stacks=12", "builtin:cube"]
BIN = Path(sys.executable).parent


def test_killing_a_worker_mid_run_loses_nothing(tmp_path, renderer):
    """SIGKILL one of two workers while chunks run: its nanny restarts it (the plugin gives the
    new process a renderer), the lost chunk runs again; every job ends rendered, every file
    that existed at the kill is still there, no partial file is left, and the pixels are
    those of an in-process run."""
    jobs = mesh_jobs(MESHES, turntable_views(24), Outputs(depth="npy"), {"size": 64})
    out = tmp_path / "dask"
    cluster = local_cluster(2, lavapipe_threads=1)
    try:
        with distributed.Client(cluster) as client:
            pids = list(client.run(os.getpid).values())
            outcome: dict = {}
            run = threading.Thread(
                target=lambda: outcome.setdefault(
                    "result", render_dataset(jobs, out, scheduler=cluster.scheduler_address, chunk_size=4, progress=False)
                )
            )
            run.start()
            deadline = time.monotonic() + 30
            while not list(out.glob("*/view_*.json")) and time.monotonic() < deadline:
                time.sleep(0.005)
            os.kill(pids[0], signal.SIGKILL)
            present_at_kill = {path for path in out.glob("*/view_*.json")}
            run.join(timeout=60)
            assert not run.is_alive()
            # The restarted process joined later; the plugin gave it a warm renderer too.
            client.wait_for_workers(2, timeout=30)
            has_renderer = client.run(lambda dask_worker: (os.getpid(), bool(chunk_renderers(dask_worker))))
            assert pids[0] not in {pid for pid, _ in has_renderer.values()}
            assert all(ready for _, ready in has_renderer.values()) and len(has_renderer) == 2
    finally:
        cluster.close(timeout=10)
    result = outcome["result"]
    assert 0 < len(present_at_kill) < len(jobs), "the kill did not land mid-run"
    assert not result.failed, result.failed
    assert sorted(result.rendered) == sorted(job.id for job in jobs)
    assert present_at_kill <= set(out.glob("*/view_*.json"))
    assert not [p for p in out.rglob("*") if p.name.endswith(".tmp")]
    reference = render_dataset(jobs, tmp_path / "local", progress=False, renderer=renderer)
    assert not reference.failed
    for job in jobs:
        for file in job.files():
            a, b = out / file, tmp_path / "local" / file
            if file.endswith(".png"):
                assert np.array_equal(np.array(Image.open(a)), np.array(Image.open(b))), file
            else:
                assert np.array_equal(np.load(a), np.load(b)), file


def test_batch_on_a_separately_started_scheduler(tmp_path):
    """`dask scheduler` and `dask worker --nthreads 1` as their own processes (a real cluster
    on 127.0.0.1); `batch --scheduler FILE` renders there; shutting the cluster down ends both."""
    scheduler_file = tmp_path / "scheduler.json"
    env = {**os.environ, "LP_NUM_THREADS": "1"}
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "start_new_session": True, "env": env}
    processes = [
        subprocess.Popen(
            [str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(scheduler_file)], **quiet
        )
    ]
    try:
        deadline = time.monotonic() + 30
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        address = json.loads(scheduler_file.read_text())["address"]
        processes.append(
            subprocess.Popen(
                [str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1", "--host", "127.0.0.1",
                 "--no-dashboard", "--death-timeout", "10"], **quiet
            )
        )
        with distributed.Client(address, timeout=20) as client:
            client.wait_for_workers(1, timeout=30)
        out = tmp_path / "out"
        status = main(["batch", "--meshes", MESHES[0], "--views", "6", "--size", "40", "--ids", "-o", str(out), "--scheduler", str(scheduler_file), "-q"])
        assert status == 0
        assert main(["batch", "--meshes", MESHES[0], "--views", "6", "--size", "40", "--ids", "-o", str(tmp_path / "local"), "-q"]) == 0
        for name in [f"view_{i:03d}{suffix}" for i in range(6) for suffix in (".png", "_ids.png")]:
            assert np.array_equal(np.array(Image.open(out / "torus" / name)), np.array(Image.open(tmp_path / "local" / "torus" / name)))
        with distributed.Client(address, timeout=20) as client:
            client.shutdown()
        assert [process.wait(timeout=20) for process in processes] == [0, 0]
    finally:
        for process in processes:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()


def test_batch_workers_2_starts_a_local_cluster_with_the_same_pixels(tmp_path, renderer):
    out = tmp_path / "dask"
    assert main(["batch", "--meshes", MESHES[1], "--views", "4", "--size", "32", "--depth", "png16", "--workers", "2", "-o", str(out), "-q"]) == 0
    jobs = mesh_jobs([MESHES[1]], turntable_views(4), Outputs(depth="png16"), {"size": 32})
    assert not render_dataset(jobs, tmp_path / "local", progress=False, renderer=renderer).failed
    for job in jobs:
        for file in job.files():
            assert np.array_equal(np.array(Image.open(out / file)), np.array(Image.open(tmp_path / "local" / file))), file
    report = json.loads((out / "report.json").read_text())
    assert report["rendered"] == 4 and report["failed"] == {}


def test_a_job_that_kills_its_worker_fails_alone_and_is_named(tmp_path):
    """A job whose rendering kills the worker process (as a driver crash would): its chunk is
    retried, then split into single jobs, so only that job fails, with the reason; its
    chunk's other job and every other mesh's jobs are rendered."""

    class Poison(distributed.WorkerPlugin):  # pickled by value: spawned workers need no test module
        name = "poison-cube-view-1"

        def setup(self, worker):
            from wgpu_shading.dataset import chunk

            original = chunk.job_scene

            def job_scene(base, job):
                if job.folder == "cube" and job.name == "view_001":
                    os._exit(1)  # the process dies mid-chunk, like a segfault in the driver
                return original(base, job)

            chunk.job_scene = job_scene

    jobs = mesh_jobs([MESHES[0], MESHES[2]], turntable_views(2), Outputs(), {"size": 24})
    cluster = local_cluster(2, lavapipe_threads=1)
    try:
        with distributed.Client(cluster) as client:
            client.register_plugin(Poison())  # also given to every restarted worker
            result = render_dataset(jobs, tmp_path / "out", scheduler=cluster.scheduler_address, chunk_size=2, progress=False)
    finally:
        cluster.close(timeout=10)
    assert list(result.failed) == ["cube/view_001"], result.failed
    assert "worker rendering it died" in result.failed["cube/view_001"]
    assert sorted(result.rendered) == ["cube/view_000", "torus/view_000", "torus/view_001"]
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert list(report["failed"]) == ["cube/view_001"]
    assert not (tmp_path / "out" / "cube" / "view_001.png").exists()
    assert not [p for p in (tmp_path / "out").rglob("*") if p.name.endswith(".tmp")]


def test_a_one_thread_worker_holds_one_chunk_at_a_time():
    """The local cluster gives each 1-thread worker one chunk at a time (cluster.py,
    worker-saturation 1.0); the others wait on the scheduler, so a worker's death blames
    only the chunk it was running."""
    cluster = local_cluster(1, lavapipe_threads=1)
    try:
        with distributed.Client(cluster) as client:
            # One graph of 6 chunk-like tasks: the scheduler queues what the worker cannot take.
            futures = client.map(time.sleep, [0.5] * 6, pure=False)
            counts = []
            deadline = time.monotonic() + 20
            while time.monotonic() < deadline and not all(future.done() for future in futures):
                counts.append(len(next(iter(client.processing().values()), [])))
                time.sleep(0.05)
            assert max(counts) == 1, counts
            client.gather(futures)
    finally:
        cluster.close(timeout=10)


def test_a_callers_client_renders_run_after_run_and_stays_open(tmp_path, renderer):
    """render_dataset(client=...) on a client the caller holds: the same pixels as in-process,
    the client still running afterwards, and nothing of the runs left on it (no futures, so
    a notebook's client does not grow run after run)."""
    jobs = mesh_jobs(MESHES[:2], turntable_views(3), Outputs(depth="npy"), {"size": 32})
    assert not render_dataset(jobs, tmp_path / "local", progress=False, renderer=renderer).failed
    cluster = local_cluster(1, lavapipe_threads=1)
    try:
        with distributed.Client(cluster) as client:
            for run in range(2):
                result = render_dataset(jobs, tmp_path / f"dask{run}", client=client, chunk_size=2, progress=False)
                assert not result.failed and sorted(result.rendered) == sorted(job.id for job in jobs)
                assert client.status == "running"
                # Futures are let go on the client's loop (Future.release): soon, not at once.
                deadline = time.monotonic() + 10
                while (client.futures or any(client.has_what().values())) and time.monotonic() < deadline:
                    time.sleep(0.01)
                assert not client.futures and not any(client.has_what().values()), (client.futures, client.has_what())
            for job in jobs:
                for file in job.files():
                    a, b = tmp_path / "dask1" / file, tmp_path / "local" / file
                    if file.endswith(".png"):
                        assert np.array_equal(np.array(Image.open(a)), np.array(Image.open(b))), file
                    else:
                        assert np.array_equal(np.load(a), np.load(b)), file
            with pytest.raises(UsageError, match="not several"):
                render_dataset(jobs, tmp_path / "x", client=client, workers=2, progress=False)
            with pytest.raises(UsageError, match="give one of them"):
                render_dataset(jobs, tmp_path / "x", client=client, renderer=renderer, progress=False)
        with pytest.raises(UsageError, match="closed, not running"):
            render_dataset(jobs, tmp_path / "y", client=client, progress=False)
        with pytest.raises(UsageError, match="expected a distributed.Client"):
            render_dataset(jobs, tmp_path / "z", client="tcp://127.0.0.1:1", progress=False)
    finally:
        cluster.close(timeout=10)


def test_a_mesh_file_edited_between_runs_on_a_callers_client_is_read_again(tmp_path, renderer):
    """The workers' renderers outlive a run (their pipelines stay warm), but not the meshes a
    run loaded: the second run draws the file as it is now, as a fresh process would.
    (Until the runs were told apart, the worker drew the first run's mesh again.)"""
    mesh = tmp_path / "m.obj"
    mesh.write_text("v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n")
    jobs = mesh_jobs([str(mesh)], turntable_views(1), Outputs(), {"size": 32})
    cluster = local_cluster(1, lavapipe_threads=1)
    try:
        with distributed.Client(cluster) as client:
            assert not render_dataset(jobs, tmp_path / "before", client=client, progress=False).failed
            mesh.write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n")
            assert not render_dataset(jobs, tmp_path / "after", client=client, progress=False).failed
    finally:
        cluster.close(timeout=10)
    assert not render_dataset(jobs, tmp_path / "fresh", progress=False, renderer=renderer).failed
    file = jobs[0].files()[0]
    before, after, fresh = (np.array(Image.open(tmp_path / name / file)) for name in ("before", "after", "fresh"))
    assert not np.array_equal(before, fresh)
    assert np.array_equal(after, fresh)


def test_a_run_stopped_early_cancels_its_chunks_on_a_callers_client(tmp_path, monkeypatch):
    """Ctrl-C in the run's loop (here: at the progress bar's first update) while a held
    client's cluster still has chunks queued: the chunks not begun are cancelled, not
    rendered behind the caller's back, and nothing of the run stays on the client."""
    import tqdm

    def interrupted(self, n=1):
        raise KeyboardInterrupt

    jobs = mesh_jobs(MESHES[:1], turntable_views(48), Outputs(), {"size": 32})
    cluster = local_cluster(1, lavapipe_threads=1)
    try:
        with distributed.Client(cluster) as client:
            monkeypatch.setattr(tqdm.tqdm, "update", interrupted)
            with pytest.raises(KeyboardInterrupt):
                render_dataset(jobs, tmp_path / "out", client=client, chunk_size=2, progress=True)
            monkeypatch.undo()
            deadline = time.monotonic() + 10
            while (client.futures or any(client.processing().values())) and time.monotonic() < deadline:
                time.sleep(0.01)
            assert not client.futures and not any(client.processing().values())
            # A chunk already running when the cancel came finishes its files (Dask cannot
            # stop a running task); wait until nothing more appears, then count.
            written, stable_since = -1, time.monotonic()
            while time.monotonic() - stable_since < 1.5 and time.monotonic() < deadline + 20:
                now = len(list((tmp_path / "out").glob("*/view_*.json")))
                if now != written:
                    written, stable_since = now, time.monotonic()
                time.sleep(0.05)
            assert 0 < written <= len(jobs) // 2, written  # the queued chunks never ran
            # The client still renders the next run.
            assert not render_dataset(jobs[:2], tmp_path / "again", client=client, progress=False).failed
    finally:
        cluster.close(timeout=10)
