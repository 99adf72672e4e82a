"""The dataset benchmark (benchmarks/dataset.py) compares like with like: its naive loop
writes the pixels `batch` writes. (Its smoke run is in test_benchmarks.py.) Nothing timed."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository's benchmarks/ package

from benchmarks.dataset import naive_loop  # noqa: E402
from wgpu_shading.dataset import Outputs, mesh_jobs, render_dataset, turntable_views  # noqa: E402


def test_naive_loop_writes_the_pixels_of_render_dataset(tmp_path, renderer):
    jobs = mesh_jobs(["builtin:torus?segments=16", "builtin:cube"], turntable_views(3), Outputs(), {"size": 40})
    naive_loop(renderer, jobs, tmp_path / "naive", 1)
    render_dataset(jobs, tmp_path / "batch", progress=False, renderer=renderer)
    for job in jobs:
        name = f"{job.folder}/{job.name}.png"
        assert np.array_equal(np.array(Image.open(tmp_path / "naive" / name)), np.array(Image.open(tmp_path / "batch" / name)))
