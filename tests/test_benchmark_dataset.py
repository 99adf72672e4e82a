"""The dataset benchmark (benchmarks/dataset.py) in its smoke mode: every mode runs and
writes what the others write, so the comparison is fair. Nothing is timed here."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository's benchmarks/ package

from benchmarks.dataset import MODES, naive_loop, run_dataset_benchmark, table  # noqa: E402
from wgpu_shading.dataset import Outputs, mesh_jobs, render_dataset, turntable_views  # noqa: E402


def test_naive_loop_writes_the_pixels_of_render_dataset(tmp_path, renderer):
    jobs = mesh_jobs(["builtin:torus?segments=16", "builtin:cube"], turntable_views(3), Outputs(), {"size": 40})
    naive_loop(renderer, jobs, tmp_path / "naive", 1)
    render_dataset(jobs, tmp_path / "batch", progress=False, renderer=renderer)
    for job in jobs:
        name = f"{job.folder}/{job.name}.png"
        assert np.array_equal(np.array(Image.open(tmp_path / "naive" / name)), np.array(Image.open(tmp_path / "batch" / name)))


def test_dataset_benchmark_smoke(renderer):
    results = run_dataset_benchmark(renderer, ["builtin:torus?segments=16", "builtin:cube"], 3, (24,), 1, chunk=2)
    (result,) = results
    assert set(result.seconds) == set(MODES) and result.frames == 6
    assert all(result.fps(mode) > 0 for mode in MODES)
    text = table(results)
    assert "| 24² |" in text and "Dask overhead" in text
