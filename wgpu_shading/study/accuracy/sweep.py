"""The accuracy/time sweep: `run_study` renders every size × tessellation × variant on the GPU,
measures its errors (metrics.py) against the analytic truth and the same-mesh float64
reference, and times it; plus the Blinn-Phong comparison, the best k_blinn and the
environment the numbers were measured on.

Frame time: the median of warm frames rendered to the user-facing RGBA8 target, render and
readback, with all shading variants of one mesh interleaved round-robin. The same-mesh
float64 reference of each mesh is rasterized once and shaded for every variant
(reference/shading.py, RasterizedScene).
"""

from __future__ import annotations

import math
import os
import platform
import time

import numpy as np

from ...scene import sphere_for_triangles
from ...render.auto_shading import Variant
from .config import StudyConfig, study_scene
from ...render.image_error import ErrorStats, pixel_error
from .metrics import EDGE_BAND, Truth, analytic_truth, highlight_error, peak_error
from .progress import Progress
from .results import Study
from ..reference import RasterizedScene


def _weight(triangles: int, size: int) -> float:
    """Rough relative cost of one (size, tessellation) block, for the progress estimate."""
    return 1.0 + (size * size) / 512**2 + triangles / 70_000


def run_study(
    config: StudyConfig = StudyConfig(),
    renderer=None,
    progress: Progress | bool | None = None,
    command: str = "",
) -> Study:
    """Run the sweep: for each size and tessellation, every variant is rendered once to a
    float32 target for its errors, then timed (RGBA8, warm, interleaved); the same-mesh
    reference is rasterized once and shaded for every variant."""
    if renderer is None:
        from ...render.renderer import Renderer

        renderer = Renderer()
    started = time.perf_counter()
    variants = config.variants
    if progress is True:
        progress = Progress(sum(_weight(n, s) for s in config.sizes for n in config.triangles))
    report = progress.advance if isinstance(progress, Progress) else (lambda amount, what: None)
    rows: list[dict] = []
    frames: dict = {}
    error_maps: dict = {}
    truths: dict = {}
    phong = Variant("phong", "phong", 1.0)
    meshes = {n: sphere_for_triangles(n) for n in config.triangles}
    for size in config.sizes:
        for model in dict.fromkeys(v.model for v in variants):
            truths[size, model] = analytic_truth(study_scene(meshes[config.triangles[0]], size, Variant("phong", *model)))
        for requested in config.triangles:
            mesh = meshes[requested]
            block = f"{size}×{size}, {mesh.triangle_count:,} triangles"
            weight = _weight(requested, size)
            scenes = [study_scene(mesh, size, v) for v in variants]
            # 1. Accuracy: one float32 frame per variant, against the analytic truths.
            float_frames = []
            for variant, scene in zip(variants, scenes):
                frame = renderer.render_frame(scene, float32=True, depth=True)
                float_frames.append(frame)
                truth = truths[size, variant.model]
                mask = truth.interior & np.isfinite(frame.depth)
                errors = pixel_error(frame.color, truth.image.color)
                stats = ErrorStats.of(errors[mask])
                phong_truth = truths[size, phong.model]
                phong_mask = phong_truth.interior & np.isfinite(frame.depth)
                phong_errors = pixel_error(frame.color, phong_truth.image.color)
                rows.append(
                    dict(
                        size=size, requested=requested, triangles=mesh.triangle_count,
                        frequency=variant.frequency, reflection=variant.reflection,
                        k_blinn=variant.k_blinn if variant.reflection == "blinn-phong" else "",
                        time_ms=float("nan"), time_min_ms=float("nan"),
                        rmse=stats.rmse, p999=stats.p999, max=stats.max,
                        peak=peak_error(errors, mask, truth.peak),
                        highlight=highlight_error(frame.color, truth.image.color, mask), pixels=stats.pixels,
                        coverage=float(mask.sum() / max(truth.interior.sum(), 1)),
                        phong_p999=ErrorStats.of(phong_errors[phong_mask]).p999,
                        phong_peak=peak_error(phong_errors, phong_mask, phong_truth.peak),
                        same_p999=float("nan"), same_max=float("nan"), same_within=float("nan"), same_pixels=0,
                    )
                )
                if size == config.figure_size and requested in config.figure_points and variant == Variant(variant.frequency):
                    error_maps[requested, variant.frequency] = (errors, mask)
            report(0.3 * weight, f"{block}: errors against the analytic sphere")
            # 2. Time: warm every variant once, then interleave the timed frames.
            block_rows = rows[-len(variants):]
            times: list[list[float]] = [[] for _ in variants]
            for scene in scenes:
                renderer.render(scene)
            timing_started = time.perf_counter()
            rounds = 0
            # At least `frames` rounds; cheap frames get more (up to 5×) until the block has
            # been timed for `min_seconds`, so that their medians are not at the mercy of noise.
            while rounds < config.frames or (
                rounds < 5 * config.frames and time.perf_counter() - timing_started < config.min_seconds
            ):
                rounds += 1
                for k, scene in enumerate(scenes):
                    start = time.perf_counter()
                    image = renderer.render(scene)
                    times[k].append(time.perf_counter() - start)
                    variant = variants[k]
                    if size == config.figure_size and requested in config.figure_points and variant == Variant(variant.frequency):
                        frames[requested, variant.frequency] = image
            for row, samples in zip(block_rows, times):
                row["time_ms"] = 1e3 * float(np.median(samples))
                row["time_min_ms"] = 1e3 * float(np.min(samples))
            report(0.4 * weight, f"{block}: frame times")
            # 3. The same mesh in float64: one rasterization, every variant shaded.
            if config.same_mesh:
                same = RasterizedScene(scenes[0])
                compared = same.covered & (same.edge_margin >= EDGE_BAND)
                for row, variant, frame in zip(block_rows, variants, float_frames):
                    errors = pixel_error(frame.color, same.shade(variant.shading()))[compared]
                    stats = ErrorStats.of(errors)
                    row.update(
                        same_p999=stats.p999, same_max=stats.max,
                        same_within=float((errors <= 1.0).mean()) if errors.size else float("nan"),
                        same_pixels=stats.pixels,
                    )
                del same
            report(0.3 * weight, f"{block}: same-mesh float64 reference")
    blinn = blinn_comparison(config, rows, truths)
    if any(model == "blinn-phong" for model, _ in config.reflections):
        size = max(config.sizes)
        k, rmse = best_blinn_k(meshes[config.triangles[0]], size, truths[size, ("phong", 1.0)])
        blinn.append(dict(k_blinn=k, size=size, rmse=rmse, best=True))
        report(0.0, "best k_blinn")
    return Study(
        config=config, rows=rows, blinn=blinn, environment=environment(renderer),
        seconds=time.perf_counter() - started, command=command, frames=frames, error_maps=error_maps,
    )


def blinn_comparison(config: StudyConfig, rows: list[dict], truths: dict) -> list[dict]:
    """Each Blinn-Phong k against Phong reflection: the model difference on the exact sphere
    (no tessellation involved) at the largest size, and the frame-time ratio Blinn/Phong at
    the same frequency and tessellation (median over the tessellations)."""
    size = max(config.sizes)
    phong_truth = truths[size, ("phong", 1.0)]
    results = []
    for model, k in config.reflections:
        if model != "blinn-phong":
            continue
        truth = truths[size, (model, k)]
        mask = phong_truth.interior & truth.interior
        errors = pixel_error(truth.image.color, phong_truth.image.color)
        stats = ErrorStats.of(errors[mask])
        entry = dict(
            k_blinn=k, size=size, rmse=stats.rmse, p999=stats.p999, max=stats.max,
            peak=peak_error(errors, mask, phong_truth.peak),
        )
        for frequency in config.frequencies:
            ratios = []
            for r in rows:
                if r["size"] == size and r["frequency"] == frequency and r["reflection"] == model and r["k_blinn"] == k:
                    match = [p for p in rows if p["size"] == size and p["frequency"] == frequency and p["reflection"] == "phong" and p["requested"] == r["requested"]]
                    if match and match[0]["time_ms"] > 0:
                        ratios.append(r["time_ms"] / match[0]["time_ms"])
            entry[f"time_ratio_{frequency}"] = float(np.median(ratios)) if ratios else float("nan")
        results.append(entry)
    return results


def best_blinn_k(mesh, size: int, phong_truth: Truth, low: float = 1.0, high: float = 12.0, steps: int = 14) -> tuple[float, float]:
    """The k_blinn for which Blinn-Phong on the exact sphere is closest (RMSE over the
    interior, 1/255) to Phong reflection in the study's scene: golden-section search."""

    def rmse(k: float) -> float:
        truth = analytic_truth(study_scene(mesh, size, Variant("phong", "blinn-phong", k)))
        mask = truth.interior & phong_truth.interior
        return ErrorStats.of(pixel_error(truth.image.color, phong_truth.image.color)[mask]).rmse

    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = low, high
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = rmse(c), rmse(d)
    for _ in range(steps):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - ratio * (b - a)
            fc = rmse(c)
        else:
            a, c, fc = c, d, fd
            d = a + ratio * (b - a)
            fd = rmse(d)
    return (c, fc) if fc < fd else (d, fd)


def environment(renderer) -> dict:
    """What the numbers were measured on (absolute times are not portable)."""
    import wgpu

    from ... import __version__
    from ...render.device import describe_device

    try:
        load = os.getloadavg()[0]
    except OSError:  # pragma: no cover
        load = float("nan")
    return dict(
        device=describe_device(renderer.device),
        cpus=os.cpu_count(),
        cpu=platform.processor() or platform.machine(),
        load_before=load,
        python=platform.python_version(),
        numpy=np.__version__,
        wgpu=wgpu.__version__,
        wgpu_shading=__version__,
        date=time.strftime("%Y-%m-%d"),
    )
