"""What accuracy costs in time: the accuracy/time study and the automatic shading choice.

Errors are measured against two float64 references (`wgpu_shading.reference`):

- the **analytic truth**: the exact sphere, ray-cast through every pixel centre and shaded
  per pixel with its exact normal (what any tessellation and frequency should converge to);
- the **same-mesh reference**: the very triangles the GPU draws, rasterized and shaded in
  float64 (what this frequency on this mesh should give; any difference is float32 rounding).

**Error** (everywhere in this module, in units of 1/255, one 8-bit step): per pixel, the
largest absolute difference over R, G and B of the colours clamped to [0, 1], between the
GPU's float32 render target and the reference. Against the analytic truth it is taken
over the pixels that both the exact sphere and the mesh cover, leaving out a band of
`SILHOUETTE_BAND` (1) pixel inside the exact silhouette; against the same-mesh reference,
over the pixels the reference covers, leaving out those within `EDGE_BAND` (1/16) pixel of
an edge of their triangle (float32 window coordinates may hand those to a neighbour).
From the per-pixel errors: RMSE, the 99.9th percentile (`p99.9`), the maximum, and the
error **at the specular peak**: the largest error in the 3×3 pixels around the pixel where
the analytic truth's specular term is largest (where Gouraud shading loses the highlight).
Besides, `highlight`: how far the image's brightest value is from the truth's, wherever
each lies (a lost highlight, as opposed to a moved one).

Frame time: the median of warm frames rendered to the user-facing RGBA8 target, render and
readback, with all shading variants of one mesh interleaved round-robin.

Public API:

    run_study(config=StudyConfig(), renderer=None, progress=None) -> Study
    write_study(study, out_dir, markdown=None) -> list of written paths
    auto_shading(scene, max_error=1.0, renderer=None) -> AutoChoice
    pixel_error(image, reference) -> per-pixel error in 1/255
The same-mesh float64 reference of each mesh is rasterized once and shaded for every
variant (reference.RasterizedScene).
"""

from __future__ import annotations

import csv
import json
import math
import os
import platform
import re
import sys
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from . import reference as ref
from ..errors import WgpuShadingError
from ..scene import FREQUENCIES, sphere_for_triangles, Camera, Material, PositionalLight, Scene, SceneObject, Shading

ERROR_UNIT = 1.0 / 255.0  # errors are reported in multiples of one 8-bit step
SILHOUETTE_BAND = 1.0  # pixels inside the exact silhouette left out of the analytic comparison
EDGE_BAND = 1.0 / 16.0  # pixels from a triangle edge left out of the same-mesh comparison
PEAK_WINDOW = 1  # the specular-peak error is the largest in a (2·1 + 1)² window


class AccuracyError(WgpuShadingError):
    """A study or an automatic choice cannot be made as asked (bad option, missing plot library)."""


# --------------------------------------------------------------------------- errors


def pixel_error(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per pixel, max over RGB of |clamp(image) − clamp(reference)|, in units of 1/255.
    `image` may be float (0..1) or uint8 (0..255)."""
    image = np.asarray(image)
    if image.dtype == np.uint8:
        image = image.astype(np.float64) / 255.0
    a = np.clip(np.asarray(image, dtype=np.float64)[..., :3], 0.0, 1.0)
    b = np.clip(np.asarray(reference, dtype=np.float64)[..., :3], 0.0, 1.0)
    return np.abs(a - b).max(axis=-1) / ERROR_UNIT


@dataclass(frozen=True)
class ErrorStats:
    """Summary of per-pixel errors (1/255 units) over the compared pixels."""

    rmse: float
    p999: float
    max: float
    pixels: int

    @classmethod
    def of(cls, errors: np.ndarray) -> "ErrorStats":
        errors = np.asarray(errors, dtype=np.float64).reshape(-1)
        if errors.size == 0:
            return cls(float("nan"), float("nan"), float("nan"), 0)
        return cls(
            rmse=float(np.sqrt(np.mean(errors**2))),
            p999=float(np.percentile(errors, 99.9)),
            max=float(errors.max()),
            pixels=int(errors.size),
        )


def highlight_error(image: np.ndarray, reference: np.ndarray, mask: np.ndarray) -> float:
    """How far the brightest value of `image` is from the brightest value of `reference`,
    each taken over the compared pixels wherever it lies: max over RGB of
    |max_pixels clamp(image) − max_pixels clamp(reference)|, in 1/255. A highlight that is
    lost (Gouraud shading with no vertex under it) shows here even when it is merely moved."""
    if not mask.any():
        return float("nan")
    a = np.clip(np.asarray(image, dtype=np.float64)[..., :3][mask], 0.0, 1.0).max(axis=0)
    b = np.clip(np.asarray(reference, dtype=np.float64)[..., :3][mask], 0.0, 1.0).max(axis=0)
    return float(np.abs(a - b).max() / ERROR_UNIT)


def peak_error(error_map: np.ndarray, mask: np.ndarray, peak: tuple[int, int]) -> float:
    """The largest error among compared pixels in the window around `peak` (NaN if none)."""
    row, col = peak
    r0, c0 = max(row - PEAK_WINDOW, 0), max(col - PEAK_WINDOW, 0)
    window = error_map[r0 : row + PEAK_WINDOW + 1, c0 : col + PEAK_WINDOW + 1]
    inside = mask[r0 : row + PEAK_WINDOW + 1, c0 : col + PEAK_WINDOW + 1]
    return float(window[inside].max()) if inside.any() else float("nan")


# --------------------------------------------------------------------------- the study's scene

# A gold-like, fairly glossy material under one white positional light: the highlight
# stays just below saturation (so clamping hides no error) and is well inside the disc.
STUDY_MATERIAL = Material(
    ambient=(0.45, 0.34, 0.15, 1.0),
    diffuse=(0.45, 0.34, 0.15, 1.0),
    specular=(0.45, 0.45, 0.45, 1.0),
    shininess=80.0,
    name="study-gold",
)
STUDY_LIGHT = PositionalLight(position=(3.0, 3.0, 5.0))
STUDY_CAMERA = Camera(eye=(0.0, 0.0, 3.2), target=(0.0, 0.0, 0.0), fov_y=45.0, near=0.5, far=10.0)
STUDY_ROTATION = (25.0, 35.0, 0.0)  # no vertex or pole sits exactly under the highlight


@dataclass(frozen=True)
class Variant:
    """One point on the shading axes: frequency × reflection model (× k_blinn)."""

    frequency: str
    reflection: str = "phong"
    k_blinn: float = 1.0

    def shading(self, base: Shading | None = None) -> Shading:
        base = base or Shading()
        k = self.k_blinn if self.reflection == "blinn-phong" else base.blinn_exponent_scale
        return replace(base, frequency=self.frequency, reflection=self.reflection, blinn_exponent_scale=k)

    @property
    def reflection_label(self) -> str:
        return "phong" if self.reflection == "phong" else f"blinn-phong k={self.k_blinn:g}"

    @property
    def label(self) -> str:
        return f"{self.frequency} / {self.reflection_label}"

    @property
    def model(self) -> tuple[str, float]:
        """The reflection model alone (what the analytic truth depends on)."""
        return (self.reflection, self.k_blinn if self.reflection == "blinn-phong" else 1.0)


def study_scene(mesh, size: int, variant: Variant, material: Material = STUDY_MATERIAL) -> Scene:
    """The study's scene: a unit sphere mesh at the origin, rotated, seen from z = 3.2."""
    return Scene(
        objects=(SceneObject(mesh, material, rotate=STUDY_ROTATION),),
        lights=(STUDY_LIGHT,),
        camera=STUDY_CAMERA,
        shading=variant.shading(),
        ambient=(0.2, 0.2, 0.2, 1.0),
        size=(size, size),
        background=(0.0, 0.0, 0.0, 1.0),
    )


@dataclass(frozen=True)
class Truth:
    """The analytic sphere for one size and reflection model, with its specular peak."""

    image: ref.ReferenceImage
    interior: np.ndarray  # covered, at least SILHOUETTE_BAND pixels inside the silhouette
    peak: tuple[int, int]  # (row, col) where the specular term is largest


def analytic_truth(scene: Scene, obj: SceneObject | None = None) -> Truth:
    """Ray-cast the exact sphere that `obj` (default: the scene's first object, a sphere mesh
    of radius 1) tessellates, and find the pixel where its specular term peaks."""
    obj = obj or scene.objects[0]
    center, radius = ref.sphere_in_world(obj)
    image = ref.render_analytic_sphere(scene, center, radius, obj.material)
    return Truth(image=image, interior=image.covered & (image.edge_margin >= SILHOUETTE_BAND), peak=specular_peak(scene, center, radius, obj.material, image))


def specular_peak(scene: Scene, center, radius: float, material: Material, image: ref.ReferenceImage) -> tuple[int, int]:
    """(row, col) of the covered pixel where the exact sphere's specular part (summed over RGB)
    is largest: the hit point is the pixel's ray scaled to the depth, the normal points away
    from the centre."""
    covered = np.flatnonzero(image.covered)
    if covered.size == 0:
        raise AccuracyError("the analytic sphere covers no pixel")
    rays = ref.pixel_rays(scene.camera, scene.size).reshape(-1, 3)[covered]
    points = rays * image.depth.reshape(-1)[covered, None]  # rays have z = −1: t is the depth
    view = ref.view_matrix(scene.camera)
    center_eye = view[:3, :3] @ np.asarray(center, dtype=np.float64) + view[:3, 3]
    normals = (points - center_eye) / radius
    to_viewer = ref.view_vectors(points, normals, scene.shading.local_viewer)
    _, specular = ref.shade(points, normals, to_viewer, scene, material)
    best = covered[int(np.argmax(specular.sum(axis=1)))]
    row, col = divmod(int(best), scene.size[0])
    return row, col


# --------------------------------------------------------------------------- same-mesh reference


# --------------------------------------------------------------------------- progress


class Progress:
    """A one-line progress report on a stream: overwritten in place on a terminal, one line
    per update (at most every few seconds) elsewhere."""

    def __init__(self, total: float, stream=None, every: float = 5.0):
        self.total = max(total, 1e-9)
        self.done = 0.0
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.perf_counter()
        self.every = every
        self._last = -math.inf
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def advance(self, amount: float, what: str) -> None:
        self.done = min(self.done + amount, self.total)
        now = time.perf_counter()
        if not self._tty and now - self._last < self.every and self.done < self.total:
            return
        self._last = now
        elapsed = now - self.start
        fraction = self.done / self.total
        left = elapsed * (1.0 - fraction) / fraction if fraction > 0 else float("nan")
        line = f"[{fraction:4.0%}] {_duration(elapsed)} elapsed, ~{_duration(left)} left: {what}"
        if self._tty:
            self.stream.write("\r\033[K" + line[:150])
            if self.done >= self.total:
                self.stream.write("\n")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


def _duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    seconds = int(round(seconds))
    return f"{seconds // 60}m{seconds % 60:02d}s" if seconds >= 60 else f"{seconds}s"


# --------------------------------------------------------------------------- the sweep

FULL_TRIANGLES = (20, 80, 320, 1_280, 5_120, 20_480, 81_920, 327_680, 1_000_000)
BLINN_KS = (1.0, 3.0, 4.0)


@dataclass(frozen=True)
class StudyConfig:
    """The grid of the study. `reflections` are (model, k_blinn) pairs; the figures use the
    first size and the `figure_triangles` (which must be in `triangles`)."""

    triangles: tuple[int, ...] = FULL_TRIANGLES
    sizes: tuple[int, ...] = (256, 512)
    frequencies: tuple[str, ...] = FREQUENCIES
    reflections: tuple[tuple[str, float], ...] = (("phong", 1.0),) + tuple(("blinn-phong", k) for k in BLINN_KS)
    frames: int = 5  # timed frames per variant at least (after one warm-up frame)
    min_seconds: float = 2.0  # more frames (up to 5 × frames) until a block has been timed this long
    same_mesh: bool = True
    figure_triangles: tuple[int, ...] = (80, 1_280, 20_480)
    figure_size: int = 256

    def __post_init__(self) -> None:
        if not self.triangles or not self.sizes or not self.frequencies or not self.reflections:
            raise AccuracyError("the study needs at least one tessellation, size, frequency and reflection")
        for n in self.triangles:
            if not 8 <= n <= 20_000_000:
                raise AccuracyError(f"triangles: {n} is outside 8..20,000,000")
        for s in self.sizes:
            if not 16 <= s <= 4096:
                raise AccuracyError(f"sizes: {s} is outside 16..4096 pixels")
        for f in self.frequencies:
            if f not in FREQUENCIES:
                raise AccuracyError(f"frequencies: unknown frequency {f!r}")
        for model, k in self.reflections:
            if model not in ("phong", "blinn-phong") or not k > 0:
                raise AccuracyError(f"reflections: bad reflection model {model!r} with k_blinn {k}")
        if self.frames < 1:
            raise AccuracyError("frames must be at least 1")
        if ("phong", 1.0) not in self.reflections:
            raise AccuracyError("reflections must include Phong reflection (the models are compared with it)")

    @property
    def variants(self) -> list[Variant]:
        return [Variant(f, model, k) for model, k in self.reflections for f in self.frequencies]

    @property
    def figure_points(self) -> tuple[int, ...]:
        return tuple(n for n in self.figure_triangles if n in self.triangles)


QUICK = StudyConfig(
    triangles=(20, 320, 5_120),
    sizes=(128,),
    reflections=(("phong", 1.0), ("blinn-phong", 4.0)),
    frames=2,
    min_seconds=0.0,
    figure_triangles=(20, 320, 5_120),
    figure_size=128,
)


@dataclass
class Study:
    """The study's results. rows: one dict per (size, tessellation, variant), keys as in
    ROW_FIELDS; blinn: one dict per k_blinn; figures: images for the contact sheets."""

    config: StudyConfig
    rows: list[dict]
    blinn: list[dict]
    environment: dict
    seconds: float
    command: str = ""
    frames: dict = field(default_factory=dict)  # (triangles, frequency) -> RGBA8 image
    error_maps: dict = field(default_factory=dict)  # (triangles, frequency) -> (error map, mask)

    def select(self, **where) -> list[dict]:
        return [r for r in self.rows if all(r[k] == v for k, v in where.items())]


ROW_FIELDS = (
    "size", "requested", "triangles", "frequency", "reflection", "k_blinn", "time_ms", "time_min_ms",
    "rmse", "p999", "max", "peak", "highlight", "pixels", "coverage",
    "phong_p999", "phong_peak", "same_p999", "same_max", "same_within", "same_pixels",
)


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
        from ..render.renderer import Renderer

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
                same = ref.RasterizedScene(scenes[0])
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

    from .. import __version__
    from ..render.device import describe_device

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


# --------------------------------------------------------------------------- derived answers


def cheapest(rows: Sequence[dict], size: int, budget: float, key: str = "phong_p999") -> dict | None:
    """The fastest row at `size` whose `key` error (1/255) is within `budget`. With the default
    key, every variant is judged against the Phong-reflection truth (what a user of the Phong
    model wants to see), so a Blinn-Phong variant qualifies only where it looks like Phong."""
    fitting = [r for r in rows if r["size"] == size and r[key] <= budget and math.isfinite(r["time_ms"])]
    return min(fitting, key=lambda r: r["time_ms"]) if fitting else None


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the points (time, error) not dominated by another (faster and more accurate),
    sorted by time."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


# --------------------------------------------------------------------------- outputs


def _fmt(value, digits: int = 2) -> str:
    if value == "" or value is None:
        return ""
    if isinstance(value, (int, np.integer)):
        return f"{value:,}"
    if not math.isfinite(value):
        return "–"
    if value == 0:
        return "0"
    if abs(value) < 0.01:
        return f"{value:.1g}"
    if abs(value) >= 100:
        return f"{value:,.0f}"
    if abs(value) >= 10:
        return f"{value:.1f}"
    return f"{value:.{digits}f}"


def _row_model(row: dict) -> str:
    return "phong" if row["reflection"] == "phong" else f"blinn-phong k={row['k_blinn']:g}"


def markdown_full_table(rows: Sequence[dict]) -> str:
    """Every row of the sweep (what `bench accuracy` writes to table.md)."""
    header = (
        "| size | triangles | frequency | reflection | frame ms | RMSE | p99.9 | max | peak | highlight | covered | vs Phong p99.9 | same-mesh p99.9 | same-mesh ≤ 1/255 |\n"
        "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    )
    lines = []
    for r in rows:
        within = "–" if not math.isfinite(r["same_within"]) else f"{r['same_within']:.2%}"
        lines.append(
            f"| {r['size']} | {r['triangles']:,} | {r['frequency']} | {_row_model(r)} | {_fmt(r['time_ms'])} | "
            f"{_fmt(r['rmse'])} | {_fmt(r['p999'])} | {_fmt(r['max'])} | {_fmt(r['peak'])} | {_fmt(r['highlight'])} | {r['coverage']:.1%} | "
            f"{_fmt(r['phong_p999'])} | {_fmt(r['same_p999'])} | {within} |"
        )
    return header + "\n".join(lines) + "\n"


def markdown_grid(rows: Sequence[dict], size: int, reflection: str = "phong", k_blinn="") -> str:
    """One line per tessellation, frame time and errors (vs the analytic truth) per frequency."""
    chosen = [r for r in rows if r["size"] == size and r["reflection"] == reflection and (reflection == "phong" or r["k_blinn"] == k_blinn)]
    frequencies = list(dict.fromkeys(r["frequency"] for r in chosen))
    header = "| triangles | " + " | ".join(f"{f} ms | RMSE | p99.9 | max | peak" for f in frequencies) + " |\n"
    header += "|---:|" + "---:|" * (5 * len(frequencies)) + "\n"
    lines = []
    for requested in dict.fromkeys(r["requested"] for r in chosen):
        cells = []
        triangles = None
        for f in frequencies:
            match = [r for r in chosen if r["requested"] == requested and r["frequency"] == f]
            if not match:
                cells += [""] * 5
                continue
            r = match[0]
            triangles = r["triangles"]
            cells += [_fmt(r["time_ms"]), _fmt(r["rmse"]), _fmt(r["p999"]), _fmt(r["max"]), _fmt(r["peak"])]
        lines.append(f"| {triangles:,} | " + " | ".join(cells) + " |")
    return header + "\n".join(lines) + "\n"


def markdown_cheapest(rows: Sequence[dict], sizes: Iterable[int], budgets=(0.5, 1.0, 2.0, 4.0, 8.0)) -> str:
    header = "| size | budget (p99.9 vs Phong truth) | cheapest setting | triangles | frame ms | p99.9 | peak | next cheapest |\n|---:|---:|---|---:|---:|---:|---:|---|\n"
    lines = []
    for size in sizes:
        for budget in budgets:
            best = cheapest(rows, size, budget)
            if best is None:
                lines.append(f"| {size} | {budget:g}/255 | none in the sweep | | | | | |")
                continue
            others = [r for r in rows if r["size"] == size and r["phong_p999"] <= budget and r is not best and math.isfinite(r["time_ms"])]
            runner = min(others, key=lambda r: r["time_ms"]) if others else None
            runner_text = f"{runner['frequency']} / {_row_model(runner)}, {runner['triangles']:,} tri, {_fmt(runner['time_ms'])} ms" if runner else ""
            lines.append(
                f"| {size} | {budget:g}/255 | **{best['frequency']} / {_row_model(best)}** | {best['triangles']:,} | "
                f"{_fmt(best['time_ms'])} | {_fmt(best['phong_p999'])} | {_fmt(best['phong_peak'])} | {runner_text} |"
            )
    return header + "\n".join(lines) + "\n"


def markdown_blinn(blinn: Sequence[dict], frequencies: Sequence[str]) -> str:
    header = (
        "| k_blinn | RMSE | p99.9 | max | at Phong's peak | "
        + " | ".join(f"time Blinn/Phong ({f})" for f in frequencies)
        + " |\n|---:|---:|---:|---:|---:|" + "---:|" * len(frequencies) + "\n"
    )
    lines = []
    best = [b for b in blinn if b.get("best")]
    for b in (b for b in blinn if not b.get("best")):
        ratios = " | ".join(f"{b[f'time_ratio_{f}']:.2f}" if math.isfinite(b[f"time_ratio_{f}"]) else "–" for f in frequencies)
        lines.append(f"| {b['k_blinn']:g} | {_fmt(b['rmse'])} | {_fmt(b['p999'])} | {_fmt(b['max'])} | {_fmt(b['peak'])} | {ratios} |")
    text = header + "\n".join(lines) + "\n"
    for b in best:
        text += (
            f"\nThe k_blinn closest to Phong reflection in this scene (least RMSE on the exact sphere, "
            f"{b['size']}×{b['size']}) is **{b['k_blinn']:.2f}**, with RMSE {_fmt(b['rmse'])}/255.\n"
        )
    return text


def markdown_same_mesh(rows: Sequence[dict]) -> str:
    """Per frequency, the worst agreement of the GPU with the same-mesh float64 reference."""
    header = "| frequency | points | worst p99.9 | worst max | worst share ≤ 1/255 | all ≥ 99.9 % |\n|---|---:|---:|---:|---:|---|\n"
    lines = []
    for f in dict.fromkeys(r["frequency"] for r in rows):
        chosen = [r for r in rows if r["frequency"] == f and r["same_pixels"] > 0]
        if not chosen:
            continue
        worst_within = min(r["same_within"] for r in chosen)
        lines.append(
            f"| {f} | {len(chosen)} | {_fmt(max(r['same_p999'] for r in chosen))} | {_fmt(max(r['same_max'] for r in chosen))} | "
            f"{worst_within:.3%} | {'yes' if worst_within >= 0.999 else '**no**'} |"
        )
    return header + "\n".join(lines) + "\n"


def headline(study: Study, budget: float = 1.0) -> str:
    """The sentence the docs lead with: the cheapest setting for the budget at the largest size."""
    size = max(study.config.sizes)
    best = cheapest(study.rows, size, budget)
    if best is None:
        return f"For an error budget of {budget:g}/255 at {size}×{size}, no setting in the sweep is good enough."
    phong_same = [r for r in study.rows if r["size"] == size and r["requested"] == best["requested"] and r["frequency"] == "phong" and r["reflection"] == "phong"]
    fastest_phong = cheapest([r for r in study.rows if r["frequency"] == "phong" and r["reflection"] == "phong"], size, budget)
    text = (
        f"For an error budget of {budget:g}/255 (99.9 % of the pixels) at {size}×{size}, the cheapest setting measured is "
        f"**{best['frequency']} shading with {_row_model(best)} reflection on {best['triangles']:,} triangles**: "
        f"{_fmt(best['time_ms'])} ms per frame, p99.9 error {_fmt(best['phong_p999'])}/255"
    )
    if phong_same and phong_same[0] is not best:
        text += f" (Phong shading of the same mesh: {_fmt(phong_same[0]['time_ms'])} ms)"
    if fastest_phong and fastest_phong is not best:
        text += f"; the cheapest Phong-shading setting within budget is {fastest_phong['triangles']:,} triangles at {_fmt(fastest_phong['time_ms'])} ms"
    others = []
    for frequency in study.config.frequencies:
        if frequency == best["frequency"]:
            continue
        own = cheapest([r for r in study.rows if r["frequency"] == frequency and r["reflection"] == "phong"], size, budget)
        if own is None:
            others.append(f"{frequency} shading does not get there even with {max(r['triangles'] for r in study.rows):,} triangles")
        else:
            others.append(f"{frequency} shading needs {own['triangles']:,} triangles ({_fmt(own['time_ms'])} ms)")
    if others:
        text += ". With Phong reflection, " + "; ".join(others)
    return text + "."


def write_csv(rows: Sequence[dict], path: Path) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=ROW_FIELDS)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def _json_ready(value):
    if isinstance(value, float):
        return float(f"{value:.6g}") if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    return value


def generated_blocks(study: Study, image_prefix: str, plot: bool = True) -> dict[str, str]:
    """The generated parts of docs/accuracy.md, by marker name."""
    config = study.config
    largest = max(config.sizes)
    env = study.environment
    blocks = {
        "headline": headline(study) + "\n",
        "cheapest": markdown_cheapest(study.rows, config.sizes),
        "blinn": markdown_blinn(study.blinn, config.frequencies),
        "same-mesh": markdown_same_mesh(study.rows),
        "figures": (
            f"![Flat, Gouraud and Phong shading at three face counts]({image_prefix}seed_figure.png)\n\n"
            f"![Per-pixel error against the exact sphere]({image_prefix}error_maps.png)\n"
        ),
        "pareto": f"![Error against frame time]({image_prefix}pareto.png)\n" if plot else "(not plotted: the run had --no-plot)\n",
        "run": (
            f"Generated by `{study.command or 'run_study()'}` in {_duration(study.seconds)} on {env['cpus']} CPU cores "
            f"({env['cpu']}), {env['device']}; Python {env['python']}, wgpu-py {env['wgpu']}, numpy {env['numpy']}; "
            f"{env['date']}. Load average before the run: {env['load_before']:.2f}.\n"
        ),
    }
    for size in sorted(config.sizes, reverse=True):
        blocks[f"table-{size}"] = markdown_grid(study.rows, size)
    for model, k in config.reflections:
        if model == "blinn-phong":
            blocks[f"table-{largest}-blinn-{k:g}"] = markdown_grid(study.rows, largest, model, k)
    return blocks


def update_markdown(path: Path, blocks: dict[str, str]) -> None:
    """Replace the text between `<!-- accuracy:NAME -->` and `<!-- /accuracy:NAME -->` for every
    block the file has; a file without markers gets them all appended."""
    text = path.read_text() if path.exists() else "# Accuracy and time\n"
    for name, content in blocks.items():
        pattern = re.compile(rf"(<!-- accuracy:{re.escape(name)} -->\n).*?(<!-- /accuracy:{re.escape(name)} -->)", re.S)
        if pattern.search(text):
            text = pattern.sub(lambda m: m.group(1) + content + m.group(2), text)
        else:
            text += f"\n<!-- accuracy:{name} -->\n{content}<!-- /accuracy:{name} -->\n"
    path.write_text(text)


def require_matplotlib():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        from ..errors import install_hint

        raise AccuracyError(f"the Pareto plot needs matplotlib; {install_hint('plots')} (or pass --no-plot)") from None
    return plt


def write_study(study: Study, out_dir: str | os.PathLike, markdown: str | os.PathLike | None = None, plot: bool = True) -> list[Path]:
    """Write results.csv, results.json, table.md, the seed figure, the error maps and (with
    matplotlib) the Pareto plot into out_dir; with `markdown`, fill that file's generated blocks."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    write_csv(study.rows, out / "results.csv")
    document = dict(
        command=study.command, seconds=study.seconds, environment=study.environment,
        config=asdict(study.config), error_unit="1/255", rows=study.rows, blinn=study.blinn,
    )
    (out / "results.json").write_text(json.dumps(_json_ready(document), indent=None, separators=(",", ":")).replace("},{", "},\n{") + "\n")
    written += [out / "results.csv", out / "results.json"]
    blocks = generated_blocks(study, "")
    table = "# Accuracy/time sweep\n\n" + blocks["run"] + "\n" + blocks["headline"] + "\n## Every point\n\n" + markdown_full_table(study.rows)
    table += "\n## Cheapest settings\n\n" + blocks["cheapest"] + "\n## Blinn-Phong against Phong reflection\n\n" + blocks["blinn"]
    table += "\n## GPU against the same-mesh float64 reference\n\n" + blocks["same-mesh"]
    (out / "table.md").write_text(table)
    written.append(out / "table.md")
    if study.frames:
        written.append(_save(seed_figure(study), out / "seed_figure.png"))
    if study.error_maps:
        written.append(_save(error_map_sheet(study), out / "error_maps.png", colors=64))
    if plot:
        written.append(pareto_plot(study, out / "pareto.png"))
    if markdown is not None:
        markdown = Path(markdown)
        prefix = os.path.relpath(out, markdown.parent).replace(os.sep, "/") + "/"
        update_markdown(markdown, generated_blocks(study, prefix, plot))
        written.append(markdown)
    return written


def _save(image: np.ndarray, path: Path, colors: int | None = None) -> Path:
    """PNG; with `colors`, quantized to a palette of that many colours (keeps maps small)."""
    from PIL import Image

    picture = Image.fromarray(image)
    if colors:
        picture = picture.quantize(colors=colors, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    picture.save(path, optimize=True)
    return path


# --------------------------------------------------------------------------- pictures

# Anchors of matplotlib's "inferno" colour map (perceptually uniform, dark = small).
_INFERNO = np.array(
    [
        (0, 0, 4), (40, 11, 84), (101, 21, 110), (159, 42, 99),
        (212, 72, 66), (245, 125, 21), (250, 193, 39), (252, 255, 164),
    ],
    dtype=np.float64,
)
HEAT_RANGE = (0.1, 100.0)  # 1/255 units shown by the error maps (log scale)


def heat_colors(values: np.ndarray, low: float = HEAT_RANGE[0], high: float = HEAT_RANGE[1]) -> np.ndarray:
    """uint8 RGB for errors on a log scale from `low` (black) to `high` (pale yellow)."""
    position = (np.log10(np.clip(values, low, high)) - math.log10(low)) / (math.log10(high) - math.log10(low))
    scaled = position * (len(_INFERNO) - 1)
    index = np.minimum(scaled.astype(int), len(_INFERNO) - 2)
    fraction = (scaled - index)[..., None]
    return np.round(_INFERNO[index] * (1 - fraction) + _INFERNO[index + 1] * fraction).astype(np.uint8)


def contact_sheet(panels: list[list[tuple[str, np.ndarray]]], footer: np.ndarray | None = None) -> np.ndarray:
    """A grid of RGB(A) panels (rows of (label, image), labels may have several lines), each
    labelled underneath, with an optional footer image (a color bar, say)."""
    from PIL import Image, ImageDraw, ImageFont

    height, width = panels[0][0][1].shape[:2]
    lines = max(label.count("\n") + 1 for row in panels for label, _ in row)
    font_size = max(8, min(24, width // 18))  # 14 px under the study's 256-px panels
    line_height = font_size + 3
    label_height = 6 + line_height * lines
    columns = max(len(row) for row in panels)
    footer_height = 0 if footer is None else footer.shape[0] + 8
    sheet = Image.new("RGB", (columns * width, len(panels) * (height + label_height) + footer_height), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    font = ImageFont.load_default(size=font_size)
    for r, row in enumerate(panels):
        for c, (label, image) in enumerate(row):
            x, y = c * width, r * (height + label_height)
            sheet.paste(Image.fromarray(np.ascontiguousarray(image[:, :, :3])), (x, y))
            for k, text in enumerate(label.split("\n")):
                text_width = draw.textlength(text, font=font)
                draw.text((x + (width - text_width) / 2, y + height + 3 + line_height * k), text, fill=(0, 0, 0), font=font)
    if footer is not None:
        sheet.paste(Image.fromarray(footer), ((columns * width - footer.shape[1]) // 2, len(panels) * (height + label_height) + 4))
    return np.asarray(sheet)


def seed_figure(study: Study) -> np.ndarray:
    """Seed 000's 3×3 figure: flat → Gouraud → Phong (rows) at three face counts (columns)."""
    triangles = {r["requested"]: r["triangles"] for r in study.rows}
    points = [n for n in study.config.figure_points if any(key[0] == n for key in study.frames)]
    rows = []
    for frequency in FREQUENCIES:
        rows.append([(f"{frequency}\n{triangles[n]:,} triangles", study.frames[n, frequency]) for n in points if (n, frequency) in study.frames])
    return contact_sheet([row for row in rows if row])


def _color_bar(width: int) -> np.ndarray:
    """A horizontal legend for heat_colors with ticks at the powers of ten."""
    from PIL import Image, ImageDraw, ImageFont

    low, high = HEAT_RANGE
    bar_width, bar_height = min(width - 40, 420), 14
    values = 10 ** np.linspace(math.log10(low), math.log10(high), bar_width)
    image = Image.new("RGB", (bar_width + 40, bar_height + 22), (255, 255, 255))
    image.paste(Image.fromarray(np.repeat(heat_colors(values)[None], bar_height, axis=0)), (20, 0))
    draw = ImageDraw.Draw(image)
    font = ImageFont.load_default(size=12)
    for exponent in range(int(math.log10(low)), int(math.log10(high)) + 1):
        x = 20 + (exponent - math.log10(low)) / (math.log10(high) - math.log10(low)) * (bar_width - 1)
        label = f"{10.0**exponent:g}/255"
        draw.line([(x, bar_height), (x, bar_height + 3)], fill=(0, 0, 0))
        draw.text((x - draw.textlength(label, font=font) / 2, bar_height + 5), label, fill=(0, 0, 0), font=font)
    return np.asarray(image)


def error_map_sheet(study: Study) -> np.ndarray:
    """Per-pixel error against the exact sphere, same grid as the seed figure; pixels left
    out of the comparison (outside the mesh or the silhouette band) are grey."""
    triangles = {r["requested"]: r["triangles"] for r in study.rows}
    points = [n for n in study.config.figure_points if any(key[0] == n for key in study.error_maps)]
    rows = []
    for frequency in FREQUENCIES:
        row = []
        for n in points:
            if (n, frequency) not in study.error_maps:
                continue
            errors, mask = study.error_maps[n, frequency]
            image = heat_colors(errors)
            image[~mask] = (128, 128, 128)
            p999 = np.percentile(errors[mask], 99.9) if mask.any() else float("nan")
            row.append((f"{frequency}, {triangles[n]:,} triangles\np99.9 {_fmt(p999, 1)}/255", image))
        if row:
            rows.append(row)
    width = rows[0][0][1].shape[1] * max(len(r) for r in rows)
    return contact_sheet(rows, footer=_color_bar(width))


_FREQUENCY_MARKERS = {"flat": "s", "gouraud": "^", "phong": "o"}
_FREQUENCY_COLORS = {"flat": "tab:blue", "gouraud": "tab:orange", "phong": "tab:green"}


def pareto_plot(study: Study, path: Path) -> Path:
    """Error (p99.9 against the analytic truth of the variant's own reflection model) against
    median frame time, log axes, one panel per size; lines join the tessellations of one
    variant; the black steps are the Pareto front of the Phong-reflection points."""
    plt = require_matplotlib()
    sizes = sorted(study.config.sizes)
    figure, axes = plt.subplots(1, len(sizes), figsize=(max(5.2 * len(sizes), 8.0), 5.0), squeeze=False, sharey=True)
    shown_models = [("phong", "")] + [("blinn-phong", k) for m, k in study.config.reflections if m == "blinn-phong"][-1:]
    for axis, size in zip(axes[0], sizes):
        for model, k in shown_models:
            for frequency in study.config.frequencies:
                chosen = [r for r in study.rows if r["size"] == size and r["frequency"] == frequency and r["reflection"] == model and (model == "phong" or r["k_blinn"] == k)]
                if not chosen:
                    continue
                x = [r["time_ms"] for r in chosen]
                y = [max(r["p999"], 1e-3) for r in chosen]
                label = f"{frequency} / {'phong' if model == 'phong' else f'blinn k={k:g}'}"
                axis.plot(
                    x, y, linestyle="-" if model == "phong" else ":", marker=_FREQUENCY_MARKERS.get(frequency, "o"),
                    color=_FREQUENCY_COLORS.get(frequency), alpha=1.0 if model == "phong" else 0.55, markersize=5, label=label,
                )
                if model == "phong":
                    for r, xi, yi in zip(chosen, x, y):
                        if r["requested"] in (study.config.triangles[0], study.config.triangles[-1]) or r is chosen[len(chosen) // 2]:
                            axis.annotate(f"{r['triangles']:,}", (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7, color=_FREQUENCY_COLORS.get(frequency))
        phong_rows = [r for r in study.rows if r["size"] == size and r["reflection"] == "phong"]
        points = [(r["time_ms"], max(r["p999"], 1e-3)) for r in phong_rows]
        front = [points[i] for i in pareto_front(points)]
        if front:
            axis.step([p[0] for p in front], [p[1] for p in front], where="post", color="black", linewidth=1, alpha=0.6, label="Pareto front (phong refl.)")
        axis.axhline(1.0, color="red", linewidth=0.8, linestyle="--", label="1/255")
        axis.set_xscale("log")
        axis.set_yscale("log")
        plain = plt.FuncFormatter(lambda value, _: f"{value:g}")
        for which in (axis.xaxis, axis.yaxis):
            which.set_major_formatter(plain)
            which.set_minor_formatter(plt.FuncFormatter(lambda value, _: f"{value:g}" if f"{value:.0e}"[0] in "25" else ""))
        axis.set_xlabel("median frame time, ms (RGBA8, render + readback)")
        axis.set_title(f"{size}×{size}")
        axis.grid(True, which="major", alpha=0.3)
    axes[0][0].set_ylabel("p99.9 error vs exact sphere (1/255)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="lower center", ncol=5, fontsize=8, frameon=False)
    figure.tight_layout(rect=(0, 0.12, 1, 1))
    figure.savefig(path, dpi=90)
    plt.close(figure)
    return path


# --------------------------------------------------------------------------- automatic shading


TIE_FRACTION = 0.05  # frame times this close count as equal in the automatic choice


@dataclass(frozen=True)
class Candidate:
    """One measured candidate of the automatic choice (errors in 1/255 units)."""

    variant: Variant
    time_ms: float
    p999: float
    max: float
    meets: bool


@dataclass(frozen=True)
class AutoChoice:
    """The result of `auto_shading`: the scene with the chosen shading, and what was measured."""

    scene: Scene
    chosen: Candidate
    candidates: tuple[Candidate, ...]
    reference: Variant
    max_error: float
    measure_size: tuple[int, int]

    def summary(self) -> str:
        c = self.chosen
        ref_time = next((x.time_ms for x in self.candidates if x.variant == self.reference), float("nan"))
        text = (
            f"auto shading chose {c.variant.frequency} frequency with {c.variant.reflection_label} reflection: "
            f"p99.9 error {c.p999:.2f}/255 (budget {self.max_error:g}/255) against {self.reference.label}"
        )
        if c.variant != self.reference:
            text += f", {c.time_ms:.1f} ms per frame instead of {ref_time:.1f} ms"
        else:
            text += f", {c.time_ms:.1f} ms per frame"
        return text

    def report(self) -> str:
        width, height = self.measure_size
        lines = [
            f"candidates (errors at {width}×{height} against {self.reference.label}, 1/255 units; "
            f"time: median warm frame at {self.scene.size[0]}×{self.scene.size[1]}):",
            f"  {'':1} {'frequency / reflection':<28} {'p99.9':>7} {'max':>7} {'ms':>8}",
        ]
        for c in sorted(self.candidates, key=lambda c: c.time_ms):
            mark = "*" if c is self.chosen else ("" if c.meets else "✗")
            lines.append(f"  {mark:1} {c.variant.label:<28} {c.p999:7.2f} {c.max:7.2f} {c.time_ms:8.1f}")
        return "\n".join(lines + [self.summary()])


def auto_candidates(shading: Shading) -> tuple[Variant, list[Variant]]:
    """The reference (Phong frequency, the scene's reflection model) and every candidate: the
    three frequencies with the scene's model and with the other model (Phong ↔ Blinn-Phong
    with k = 4, the k for which Blinn-Phong's highlight has Phong's size)."""
    own = Variant("phong", shading.reflection, shading.blinn_exponent_scale if shading.reflection == "blinn-phong" else 1.0)
    other = ("blinn-phong", 4.0) if shading.reflection == "phong" else ("phong", 1.0)
    candidates = [Variant(f, own.reflection, own.k_blinn) for f in FREQUENCIES]
    candidates += [Variant(f, *other) for f in FREQUENCIES]
    return own, candidates


def auto_shading(
    scene: Scene,
    max_error: float = 1.0,
    *,
    renderer=None,
    frames: int = 3,
    measure_size: int = 256,
) -> AutoChoice:
    """Choose the cheapest shading frequency and reflection model whose image stays within
    `max_error` (units of 1/255; p99.9 over the covered pixels) of the most accurate one.

    The rule, operationally: render the scene with every candidate of `auto_candidates` to a
    float32 target at a reduced size (longest side `measure_size`, or the scene's size if
    smaller); measure each one's per-pixel error (max over RGB of the clamped colours)
    against the reference candidate (Phong frequency with the scene's own reflection model)
    over the pixels the reference covers; time each candidate's warm RGBA8 frame at the
    scene's full size (median of `frames`, interleaved); choose the fastest candidate whose
    99.9th-percentile error is at most `max_error`, where frame times within 5 %
    (`TIE_FRACTION`) of the fastest count as equal and the most accurate of those wins. The
    reference always qualifies, so there is always a choice."""
    if not (isinstance(max_error, (int, float)) and math.isfinite(max_error) and max_error >= 0):
        raise AccuracyError(f"--max-error: expected a number >= 0 (units of 1/255), got {max_error!r}")
    if frames < 1:
        raise AccuracyError("frames must be at least 1")
    if renderer is None:
        from ..render.renderer import Renderer

        renderer = Renderer()
    reference, candidates = auto_candidates(scene.shading)
    width, height = scene.size
    scale = min(1.0, measure_size / max(width, height))
    small_size = (max(1, round(width * scale)), max(1, round(height * scale)))
    small = replace(scene, size=small_size)

    def with_variant(base: Scene, variant: Variant) -> Scene:
        return replace(base, shading=variant.shading(scene.shading))

    truth = renderer.render_frame(with_variant(small, reference), float32=True, depth=True)
    covered = np.isfinite(truth.depth)
    errors = {}
    for variant in candidates:
        image = truth.color if variant == reference else renderer.render(with_variant(small, variant), float32=True)
        stats = ErrorStats.of(pixel_error(image, truth.color)[covered])
        errors[variant] = (0.0, 0.0) if stats.pixels == 0 else (stats.p999, stats.max)
    full = [with_variant(scene, v) for v in candidates]
    for s in full:
        renderer.render(s)  # warm-up: pipelines compiled, buffers allocated
    samples = [[] for _ in candidates]
    for _ in range(frames):
        for k, s in enumerate(full):
            start = time.perf_counter()
            renderer.render(s)
            samples[k].append(time.perf_counter() - start)
    measured = tuple(
        Candidate(v, 1e3 * float(np.median(t)), errors[v][0], errors[v][1], errors[v][0] <= max_error)
        for v, t in zip(candidates, samples)
    )
    fitting = [c for c in measured if c.meets]
    fastest = min(c.time_ms for c in fitting)
    # Times within TIE_FRACTION of the fastest are within the noise of a shared machine:
    # of those, take the most accurate.
    chosen = min((c for c in fitting if c.time_ms <= fastest * (1.0 + TIE_FRACTION)), key=lambda c: (c.p999, c.time_ms))
    return AutoChoice(
        scene=with_variant(scene, chosen.variant), chosen=chosen, candidates=measured,
        reference=reference, max_error=float(max_error), measure_size=small_size,
    )
