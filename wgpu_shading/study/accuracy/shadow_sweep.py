"""The shadow part of the accuracy/time study (docs/accuracy.md#shadows): map size × filter ×
bias on the shadow hard cases (study/shadows/cases.py), each point measured against the
exact ray-cast visibility with `measure_shadows` (misclassified pixels, boundary
displacement, colour error) and timed: the median warm RGBA8 frame that draws its shadow
maps (the casting lights turn by a millionth of a radian between frames, as in an
animation: an unchanged frame would reuse its maps), in CPU time of the process (lavapipe's
threads included: what the frame costs, which a busy machine does not inflate as it does
wall time) and in wall time.

    from wgpu_shading.study.accuracy import shadow_grid, run_shadow_study, cheapest_shadow_setting
    points = run_shadow_study(renderer, shadow_grid())          # needs GPU shadows
    print(cheapest_shadow_setting(points))                      # what `auto` should be

It needs a renderer that draws shadows (`gpu_draws_shadows()`); until then
`run_shadow_study` raises AccuracyError saying so. Everything else (the grid, the rule,
the table) works on any list of points.
"""

from __future__ import annotations

import itertools
import math
import statistics
import time
from dataclasses import dataclass, fields, replace
from typing import Callable, Iterable

import numpy as np

from ...errors import AccuracyError
from ...scene import SHADOW_FILTERS, ShadowSettings
from ..shadows import SHADOW_CASE_NAMES, ShadowReference, measure_shadows, shadow_case

MAP_SIZES = (256, 512, 1024, 2048, 4096)
# Shadow-map texels. Planes need none beyond rounding (the comparison follows the receiver's
# own plane, docs/shadows.md); concave folds and contacts need a few.
BIASES = (0.5, 1.0, 2.0, 3.0, 4.0)
# Every hard case (grazing light, contact, zero thickness, self-shadowing, the terminator,
# the cube map, two lights) in the four variants tests/test_shadows_gpu.py holds to the
# guarantees: scales 1e-3, 1 and 1e3, perspective and orthographic.
VARIANTS = ((1.0, "perspective"), (1.0, "orthographic"), (1e-3, "perspective"), (1e3, "orthographic"))
STUDY_CASES = tuple((name, scale, projection) for name in SHADOW_CASE_NAMES for scale, projection in VARIANTS)


# `bench accuracy --shadows --quick`: a look in a minute, not a choice for `auto`.
QUICK_SHADOW_CASES = (
    ("sphere_over_plane_10", 1.0, "perspective"),
    ("torus_self_shadow", 1.0, "orthographic"),
    ("ring_of_boxes", 1.0, "perspective"),
)


@dataclass(frozen=True, order=True)
class ShadowSetting:
    """One point of the grid: what ShadowSettings would hold, every field explicit."""

    map_size: int
    filter: str
    bias: float

    def settings(self) -> ShadowSettings:
        return ShadowSettings(map_size=self.map_size, filter=self.filter, bias=self.bias)

    @property
    def label(self) -> str:
        return f"{self.map_size} {self.filter} bias {self.bias:g}"


@dataclass(frozen=True)
class ShadowPoint:
    """One setting on one case: errors against the exact shadows, and the frame time."""

    case: str
    setting: ShadowSetting
    wrong: int  # pixels with the wrong state (all lights)
    wrong_far: int  # of those, farther than 2 px from the exact boundary: acne and leaks
    displacement_p99: float  # px, the worst light's
    lit_error: float  # 1/255, where exactly lit, away from the boundaries
    shadowed_error: float  # 1/255, where exactly shadowed, away from the boundaries
    frame_ms: float  # median warm RGBA8 frame drawing its maps, wall time
    cpu_ms: float = 0.0  # the same frames in CPU time of the process (0: not measured)

    @property
    def color_error(self) -> float:
        return max(self.lit_error, self.shadowed_error)

    @property
    def cost_ms(self) -> float:
        """What `auto` weighs: CPU time where measured, else wall time."""
        return self.cpu_ms or self.frame_ms


def shadow_grid(map_sizes: Iterable[int] = MAP_SIZES, filters: Iterable[str] = SHADOW_FILTERS,
                biases: Iterable[float] = BIASES) -> tuple[ShadowSetting, ...]:
    """Every combination, validated as ShadowSettings would validate it."""
    grid = tuple(ShadowSetting(int(m), f, float(b)) for m, f, b in itertools.product(map_sizes, filters, biases))
    for setting in grid:
        setting.settings()  # a SceneError names a bad value
    return grid


def quick_shadow_grid() -> tuple["ShadowSetting", ...]:
    return shadow_grid((512, 2048), ("nearest", "pcf3"), (1.0, 3.0))


def gpu_draws_shadows() -> bool:
    """Whether this renderer has shadow passes (its FeatureSet has a shadow field)."""
    from ...render.features import FeatureSet

    return any("shadow" in f.name for f in fields(FeatureSet))


def turned_lights(scene, angle: float = 1e-6):
    """The scene with every casting light turned (directional, spot) or moved (positional)
    by `angle` radians about the scene's origin: the same picture to within float32, but new
    shadow maps (a frame of an animation)."""
    c, s = math.cos(angle), math.sin(angle)
    turn = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])

    def turned(light):
        if not light.shadows:
            return light
        changes = {}
        for name in ("direction", "position"):
            if hasattr(light, name):
                changes[name] = tuple(turn @ np.asarray(getattr(light, name), dtype=np.float64))
        return replace(light, **changes)

    return replace(scene, lights=tuple(turned(light) for light in scene.lights))


def _median_frame_ms(renderer, scene, frames: int) -> tuple[float, float]:
    """(wall, CPU) medians of `frames` warm frames, alternating with a turned light so that
    every frame draws its shadow maps."""
    other = turned_lights(scene)
    renderer.render_frame(scene)  # warm: pipelines, uploads, the maps' texture
    renderer.render_frame(other)
    wall, cpu = [], []
    for k in range(frames):
        start, start_cpu = time.perf_counter(), time.process_time()
        renderer.render_frame(other if k % 2 else scene)
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return 1000.0 * statistics.median(wall), 1000.0 * statistics.median(cpu)


def run_shadow_study(renderer, grid: tuple[ShadowSetting, ...], cases=STUDY_CASES, size: tuple[int, int] = (256, 256),
                     frames: int = 3, progress: Callable[[int, int], None] | None = None) -> tuple[ShadowPoint, ...]:
    """Measure every setting of `grid` on every case (name, scale, projection). A frame's cost
    does not depend on the bias (one number in a uniform block), so each case is timed once
    per map size and filter, and that time stands for every bias."""
    if not gpu_draws_shadows():
        raise AccuracyError("the shadow study needs a renderer that draws shadows; this one has no shadow passes yet")
    points, done, total = [], 0, len(grid) * len(cases)
    for name, scale, projection in cases:
        case = shadow_case(name, size, scale=scale, projection=projection)
        reference = ShadowReference(case.scene)
        no_shadows = replace(case.scene, lights=tuple(replace(light, shadows=False) for light in case.scene.lights))
        shadowless = renderer.render_frame(no_shadows, float32=True).color
        timed: dict[tuple[int, str], tuple[float, float]] = {}
        for setting in grid:
            scene = replace(case.scene, shadows=setting.settings())
            report = measure_shadows(reference, renderer.render_frame(scene, float32=True).color, shadowless, name=case.name)
            key = (setting.map_size, setting.filter)
            if key not in timed:
                timed[key] = _median_frame_ms(renderer, scene, frames)
            wall, cpu = timed[key]
            points.append(ShadowPoint(
                case=case.name, setting=setting,
                wrong=sum(r.wrong for r in report.lights), wrong_far=sum(r.wrong_far for r in report.lights),
                displacement_p99=max((r.displacement_p99 for r in report.lights), default=0.0),
                lit_error=report.lit_error, shadowed_error=report.shadowed_error,
                frame_ms=wall, cpu_ms=cpu,
            ))
            done += 1
            if progress is not None:
                progress(done, total)
    return tuple(points)


def shadow_table(points: Iterable[ShadowPoint]) -> str:
    """Markdown: one row per setting, the worst case's errors and the median frame time."""
    by_setting: dict[ShadowSetting, list[ShadowPoint]] = {}
    for point in points:
        by_setting.setdefault(point.setting, []).append(point)
    lines = ["| map | filter | bias | wrong far (max) | boundary p99 px (max) | colour /255 (max) | ms (median) | CPU ms (median) |",
             "|---:|---|---:|---:|---:|---:|---:|---:|"]
    for setting in sorted(by_setting):
        rows = by_setting[setting]
        lines.append(
            f"| {setting.map_size} | {setting.filter} | {setting.bias:g} | {max(r.wrong_far for r in rows)} | "
            f"{max(r.displacement_p99 for r in rows):.2f} | {max(r.color_error for r in rows):.2f} | "
            f"{statistics.median(r.frame_ms for r in rows):.2f} | {statistics.median(r.cpu_ms for r in rows):.2f} |"
        )
    return "\n".join(lines)
