"""`render --shading auto --max-error E`: `auto_shading(scene, max_error)` measures every
candidate shading (a `Variant`: frequency × reflection model) of a scene for error against
the most accurate one and for frame time, and returns the cheapest within the error budget
(`AutoChoice`). docs/accuracy.md says when to use it; the error measure is image_error.py's,
the one the accuracy study (`study/accuracy/`) reports."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from ..errors import AccuracyError
from ..scene import FREQUENCIES, Scene, Shading
from .image_error import ErrorStats, pixel_error


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
        from .renderer import Renderer

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
