"""Where a dataset frame's time goes: each stage of `batch` (colour PNG + depth .npy) timed
alone, in one process, on the same jobs as benchmarks/dataset.py, beside the batch itself.

    load       the mesh file to a Scene (assets: read, normals), once per mesh
    scenes     each job's Scene (camera turned, lights following it)
    render     render + readback: render_many(scenes, depth=True) on meshes already uploaded
               (the pipelined path a chunk uses); "one at a time" is render_frame in a loop
    encode     the PNG (assets/png.py at the batch's level), the .npy bytes and the record
    write      those bytes written atomically into a fresh folder (temporary, rename) the way the
               batch writes them: the folder made as render_dataset makes one (output_folder.py),
               files of 512 KiB and more around the page cache (dataset/direct_writes.py);
               removed only at the end of the benchmark (as the batch modes' folders are)

Every stage is wall and CPU time (this process, every thread), per frame; load is spread over
the frames of its mesh. The batch's own time inside its chunks, per frame, is then compared
with render + readback: what the chunk adds to the frames themselves.
"""

from __future__ import annotations

import io
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpu_shading.assets.png import encode_png
from wgpu_shading.dataset.cameras import camera_record
from wgpu_shading.dataset.direct_writes import write_bytes
from wgpu_shading.dataset.output_folder import make_output_folder
from wgpu_shading.dataset.views import base_scene, job_scene
from wgpu_shading.dataset.writer import atomic_write, json_text

STAGES = ("load", "scenes", "render", "render, one at a time", "encode", "write")


@dataclass
class StageTimes:
    wall: dict[str, list[float]] = field(default_factory=dict)  # stage → seconds per frame, per pass
    cpu: dict[str, list[float]] = field(default_factory=dict)

    def add(self, stage: str, wall: float, cpu: float, frames: int) -> None:
        self.wall.setdefault(stage, []).append(wall / frames)
        self.cpu.setdefault(stage, []).append(cpu / frames)


class _Clock:
    def __enter__(self):
        self.wall, self.cpu = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.wall, self.cpu = time.perf_counter() - self.wall, time.process_time() - self.cpu


def time_stages(renderer, jobs, level: int, times: StageTimes, folder: Path) -> None:
    """One pass over every stage of `jobs` (all with colour and depth), writing into `folder`
    (new; left there for the caller to remove with the rest of its scratch files)."""
    frames = len(jobs)
    with _Clock() as clock:
        bases = {}
        for job in jobs:
            if job.load_key() not in bases:
                bases[job.load_key()] = base_scene(job)
    times.add("load", clock.wall, clock.cpu, frames)
    with _Clock() as clock:
        scenes = [job_scene(bases[job.load_key()], job) for job in jobs]
    times.add("scenes", clock.wall, clock.cpu, frames)
    for scene in {id(s.objects[0].mesh): s for s in scenes}.values():  # upload every mesh on every device first
        for _ in renderer.render_many([scene] * 4, depth=True):
            pass
    # Each frame is let go as soon as it is read back, as the batch lets its frames go once
    # written: keeping all of them (384 MB at 512²) made every frame take fresh pages, which
    # cost this VM +1.3 ms wall and +2.1 ms CPU a 512² frame (an A/B in one process, 6
    # rounds) and inflated the render column the batch is measured against.
    with _Clock() as clock:
        for _ in renderer.render_many(scenes, depth=True):
            pass
    times.add("render", clock.wall, clock.cpu, frames)
    rendered = [(frame.color, frame.depth) for frame in renderer.render_many(scenes, depth=True)]  # for encode, untimed
    with _Clock() as clock:
        for scene in scenes:
            renderer.render_frame(scene, depth=True)
    times.add("render, one at a time", clock.wall, clock.cpu, frames)
    def encode(job, scene, color, depth) -> tuple:
        buffer = io.BytesIO()
        np.save(buffer, depth.astype(np.float32))
        record = {"id": job.id, "digest": job.digest(), "source": job.source, "files": job.files(), "camera": camera_record(scene)}
        return job, encode_png(color, level), buffer.getvalue(), json_text(record)

    with _Clock() as clock:  # each frame's bytes let go once made, as the batch's are once written
        for job, scene, (color, depth) in zip(jobs, scenes, rendered):
            encode(job, scene, color, depth)
    times.add("encode", clock.wall, clock.cpu, frames)
    encoded = [encode(job, scene, *frame) for job, scene, frame in zip(jobs, scenes, rendered)]  # for write, untimed
    make_output_folder(folder)  # as render_dataset makes its folder: mesh folders spread
    with _Clock() as clock:
        for job, png, npy, record in encoded:
            (folder / job.folder).mkdir(exist_ok=True)
            atomic_write(folder / job.folder / f"{job.name}.png", lambda file, data=png: write_bytes(file, data))
            atomic_write(folder / job.folder / f"{job.name}_depth.npy", lambda file, data=npy: write_bytes(file, data))
            atomic_write(folder / job.record_path(), lambda file, data=record: write_bytes(file, data))
    times.add("write", clock.wall, clock.cpu, frames)
