"""Holding a GPU image to the exact shadows (docs/shadows.md#testing-shadows).

`ShadowReference(scene)` is the exact answer, in float64: the visibility of every light at
every pixel (ray-cast, study/reference/visibility.py), the shadowless colour, the exact
colour and, for each light that casts shadows, the colour with that light's state flipped.
`measure_shadows(reference, image, shadowless)` classifies each pixel of a GPU image:

- the GPU's own shadowless image I₀ (same scene, shadows off) absorbs what is not about
  shadows (float32, rasterization): the pixel is predicted as I₀ + (exact − shadowless) if
  its state is right and I₀ + (flipped − shadowless) if light i's state is wrong; the
  nearer prediction (max over RGB) is the GPU's state. A GPU visibility (lights, H, W),
  when the renderer exposes one, is used instead (V < 0.5: shadowed);
- a light's state *matters* at a pixel where the two predictions differ by more than
  1/255 (elsewhere — the unlit side, N·L ≤ 0, a faint light — either state shows the same);
- the exact boundary of light i: the midpoints between 4-adjacent covered pixels whose
  exact states differ. The GPU's boundary: the same between pixels where the state matters.

and `check_shadows` asserts the guarantees of docs/shadows.md#guarantees on it:
  1. no pixel farther than 2 px from the exact boundary has the wrong state;
  2. the GPU's boundary is within 1 px of the exact one (p99, both ways);
  3. away from the boundaries (> 2 px), the colour equals the exact colour within 1/255:
     where the exact state is lit that is the shadowless image (and where it is shadowed,
     the shadowless image less that light's terms).
A failure raises ShadowError with the counts and the worst pixel, and writes a picture.
"""

from __future__ import annotations

import itertools
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...scene import Scene, shadowing_lights
from ..reference import RasterizedScene

UNIT = 1.0 / 255.0
MATTERS = UNIT  # a light's state matters where its two colours differ by more than this
WRONG_STATE_BAND = 2.0  # px: guarantee 1
MAX_DISPLACEMENT_P99 = 1.0  # px: guarantee 2
COLOR_TOLERANCE = UNIT  # guarantee 3
# Pixels where the GPU's shadowless image is this far from the reference's shadowless image
# are not about shadows (a silhouette pixel the GPU gives to the neighbour): left out and counted.
UNRELATED = 2.0 * UNIT
MAX_JOINT_LIGHTS = 4  # up to 2⁴ colours per pixel are told apart; more lights: one at a time
MAX_UNRELATED_FRACTION = 0.005


class ShadowError(AssertionError):
    """A GPU image breaks a shadow guarantee; the message has the numbers."""


class ShadowReference:
    """The exact shadows of `scene` in float64 (lights that cast none: V = 1)."""

    def __init__(self, scene: Scene):
        self.scene = scene
        rasterized = RasterizedScene(scene)
        self.covered = rasterized.covered
        self.visibility = rasterized.visibility  # (lights, H, W), 1 lit, 0 shadowed
        self.lights = shadowing_lights(scene)
        self.color = rasterized.shade()
        self.shadowless = rasterized.shade(visibility=np.ones_like(self.visibility))
        # The colour with the states of a set of lights flipped: every set of up to
        # MAX_JOINT_LIGHTS lights (so a pixel wrong for two lights is classified as such),
        # smallest sets first; with more shadowing lights, one light at a time.
        sizes = range(1, len(self.lights) + 1) if len(self.lights) <= MAX_JOINT_LIGHTS else (1,)
        self.variants: dict[tuple[int, ...], np.ndarray] = {(): self.color}
        for flips in (c for size in sizes for c in itertools.combinations(self.lights, size)):
            flipped = self.visibility.copy()
            flipped[list(flips)] = np.where(self.covered, 1.0 - flipped[list(flips)], 1.0)
            self.variants[flips] = rasterized.shade(visibility=flipped)
        self.flipped = {light: self.variants[(light,)] for light in self.lights}

    def shadowed(self, light: int) -> np.ndarray:
        """(H, W) bool: covered pixels in light `light`'s exact shadow."""
        return self.covered & (self.visibility[light] < 0.5)

    def matters(self, light: int) -> np.ndarray:
        """(H, W) bool: pixels where light `light`'s state changes the colour by more than 1/255."""
        return self.covered & (np.abs(self.flipped[light] - self.color)[..., :3].max(axis=-1) > MATTERS)


@dataclass(frozen=True)
class LightResult:
    """One light's shadow state against the exact one (distances in pixels)."""

    light: int
    matters: int  # pixels where its state changes the colour
    wrong: int  # of those, pixels whose GPU state is wrong
    wrong_far: int  # of those, farther than 2 px from the exact boundary
    worst_pixel: tuple[int, int] | None  # (row, column) of the wrong pixel farthest from the boundary
    worst_distance: float
    displacement_p99: float  # between the GPU's boundary and the exact one, both ways
    displacement_max: float

    @property
    def failures(self) -> list[str]:
        found = []
        if self.wrong_far:
            found.append(
                f"light {self.light}: {self.wrong_far} pixels farther than {WRONG_STATE_BAND:g} px from the exact shadow "
                f"boundary have the wrong state ({self.wrong} wrong in all, of {self.matters} where it matters); worst "
                f"(row, column) {self.worst_pixel}, {self.worst_distance:.2f} px from the boundary"
            )
        if self.displacement_p99 > MAX_DISPLACEMENT_P99:
            found.append(
                f"light {self.light}: the shadow boundary is {self.displacement_p99:.2f} px from the exact one (p99; "
                f"max {self.displacement_max:.2f}), allowed {MAX_DISPLACEMENT_P99:g}"
            )
        return found


@dataclass(frozen=True)
class ShadowReport:
    """What `measure_shadows` found; `failures` lists each broken guarantee in words."""

    name: str
    lights: tuple[LightResult, ...]
    compared: int  # covered pixels compared
    unrelated: int  # covered pixels left out: the GPU's shadowless image differs there
    lit_error: float  # max colour error (1/255 units) where every light is exactly lit, away from the boundaries
    shadowed_error: float  # the same where some light is exactly hidden
    worst_color_pixel: tuple[int, int] | None
    pictures: tuple[str, ...] = field(default=())

    @property
    def failures(self) -> list[str]:
        found = [f for light in self.lights for f in light.failures]
        if self.unrelated > MAX_UNRELATED_FRACTION * max(self.compared + self.unrelated, 1):
            found.append(f"{self.unrelated} covered pixels differ from the reference even without shadows "
                         f"(more than {MAX_UNRELATED_FRACTION:.1%}): the shadowless image is not this scene's")
        for what, error in (("lit", self.lit_error), ("shadowed", self.shadowed_error)):
            if error > COLOR_TOLERANCE * 255.0 + 1e-9:
                found.append(f"where the exact state is {what}, away from the boundaries, the colour is {error:.2f}/255 "
                             f"from the exact colour (allowed 1/255); worst (row, column) {self.worst_color_pixel}")
        return found

    @property
    def passed(self) -> bool:
        return not self.failures

    def summary(self) -> str:
        lights = "; ".join(f"light {r.light}: {r.wrong} wrong ({r.wrong_far} far), boundary p99 {r.displacement_p99:.2f} px"
                           for r in self.lights)
        return (f"{self.name}: {self.compared} pixels, {lights or 'no shadowing light'}; colour error lit "
                f"{self.lit_error:.2f}/255, shadowed {self.shadowed_error:.2f}/255")


def _as_float(image: np.ndarray, shape: tuple[int, int], what: str) -> np.ndarray:
    image = np.asarray(image)
    if image.shape[:2] != shape or image.ndim != 3 or image.shape[2] < 3:
        raise ValueError(f"{what}: expected an (H, W, 3 or 4) image of {shape[1]}×{shape[0]}, got shape {image.shape}")
    return image[..., :3].astype(np.float64) / (255.0 if image.dtype == np.uint8 else 1.0)


def boundary_midpoints(state: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """(K, 2) (row, column) midpoints between 4-adjacent valid pixels whose state differs."""
    across = valid[:, 1:] & valid[:, :-1] & (state[:, 1:] != state[:, :-1])
    down = valid[1:, :] & valid[:-1, :] & (state[1:, :] != state[:-1, :])
    rows, cols = np.nonzero(across)
    rows2, cols2 = np.nonzero(down)
    return np.concatenate([np.stack([rows, cols + 0.5], 1), np.stack([rows2 + 0.5, cols2], 1)]).astype(np.float64)


def _nearest(points: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Distance from each point to the nearest target (inf without targets), in chunks."""
    if len(targets) == 0:
        return np.full(len(points), np.inf)
    result = np.empty(len(points))
    for start in range(0, len(points), 512):
        chunk = points[start : start + 512]
        result[start : start + 512] = np.sqrt(((chunk[:, None, :] - targets[None, :, :]) ** 2).sum(-1).min(axis=1))
    return result


def pixels_near(shape: tuple[int, int], midpoints: np.ndarray, radius: float) -> np.ndarray:
    """(H, W) bool: pixel centres within `radius` of a midpoint."""
    mask = np.zeros(shape, dtype=bool)
    reach = int(np.ceil(radius + 0.5))
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            rows = np.floor(midpoints[:, 0]).astype(int) + dr
            cols = np.floor(midpoints[:, 1]).astype(int) + dc
            inside = (rows >= 0) & (rows < shape[0]) & (cols >= 0) & (cols < shape[1])
            close = np.hypot(rows - midpoints[:, 0], cols - midpoints[:, 1]) <= radius
            mask[rows[inside & close], cols[inside & close]] = True
    return mask


def _gpu_states(reference: ShadowReference, image: np.ndarray, shadowless: np.ndarray,
                visibility: np.ndarray | None) -> dict[int, np.ndarray]:
    """Each shadowing light's state in the GPU image, (H, W) bool shadowed: from the GPU's
    visibility if given, else the set of flipped lights whose predicted colour is nearest."""
    if visibility is not None:
        return {light: np.asarray(visibility)[light] < 0.5 for light in reference.lights}
    flips = list(reference.variants)
    errors = np.stack([np.abs(image - (shadowless + (reference.variants[f] - reference.shadowless)[..., :3])).max(-1)
                       for f in flips])
    best = np.argmin(errors, axis=0)  # ties: the first, i.e. the fewest flipped lights
    states = {}
    for light in reference.lights:
        flipped = np.isin(best, [k for k, f in enumerate(flips) if light in f])
        states[light] = reference.shadowed(light) != flipped
    return states


def measure_shadows(reference: ShadowReference, image: np.ndarray, shadowless: np.ndarray, *,
                    visibility: np.ndarray | None = None, name: str = "") -> ShadowReport:
    """Classify every pixel of a GPU `image` (H, W, 3|4; uint8 or float in [0, 1]) against
    the exact shadows, given the GPU's `shadowless` image of the same scene; see the module."""
    shape = reference.covered.shape
    image, shadowless = _as_float(image, shape, "image"), _as_float(shadowless, shape, "shadowless")
    unrelated = reference.covered & (np.abs(shadowless - reference.shadowless[..., :3]).max(-1) > UNRELATED)
    compared = reference.covered & ~unrelated
    exact_prediction = shadowless + (reference.color - reference.shadowless)[..., :3]
    near_any = np.zeros(shape, dtype=bool)
    results = []
    gpu_states = _gpu_states(reference, image, shadowless, visibility)
    for light in reference.lights:
        exact_state = reference.shadowed(light)
        matters = reference.matters(light) & compared
        gpu_state = gpu_states[light]
        wrong = matters & (gpu_state != exact_state)
        exact_boundary = boundary_midpoints(exact_state, reference.covered)
        near_any |= pixels_near(shape, exact_boundary, WRONG_STATE_BAND)
        wrong_pixels = np.argwhere(wrong)
        distance = _nearest(wrong_pixels.astype(np.float64), exact_boundary)
        far = distance > WRONG_STATE_BAND
        worst = int(np.argmax(distance)) if len(distance) else None
        gpu_boundary = boundary_midpoints(gpu_state, matters)
        exact_where_it_matters = boundary_midpoints(exact_state, matters)
        both_ways = np.concatenate([_nearest(gpu_boundary, exact_boundary), _nearest(exact_where_it_matters, gpu_boundary)])
        finite = np.where(np.isfinite(both_ways), both_ways, float(max(shape)))
        results.append(LightResult(
            light=light, matters=int(matters.sum()), wrong=int(wrong.sum()), wrong_far=int(far.sum()),
            worst_pixel=None if worst is None else tuple(int(v) for v in wrong_pixels[worst]),
            worst_distance=0.0 if worst is None else float(distance[worst]),
            displacement_p99=float(np.percentile(finite, 99)) if len(finite) else 0.0,
            displacement_max=float(finite.max()) if len(finite) else 0.0,
        ))
    color_error = np.abs(image - exact_prediction).max(-1) * 255.0
    away = compared & ~near_any
    lit = away & (reference.visibility >= 0.5).all(axis=0)
    shadowed = away & ~(reference.visibility >= 0.5).all(axis=0)
    worst_color = np.argmax(np.where(away, color_error, -1.0))
    return ShadowReport(
        name=name or "shadows", lights=tuple(results), compared=int(compared.sum()), unrelated=int(unrelated.sum()),
        lit_error=float(color_error[lit].max()) if lit.any() else 0.0,
        shadowed_error=float(color_error[shadowed].max()) if shadowed.any() else 0.0,
        worst_color_pixel=tuple(int(v) for v in np.unravel_index(worst_color, shape)) if away.any() else None,
    )


def failure_picture(reference: ShadowReference, image: np.ndarray, shadowless: np.ndarray,
                    visibility: np.ndarray | None = None) -> np.ndarray:
    """(H, 3W, 3) uint8: the GPU image | the exact image | where they disagree: grey =
    exactly shadowed from some light, white = exact boundary band, red = wrong state farther
    than 2 px, yellow = wrong state near the boundary, magenta = colour off by > 1/255."""
    shape = reference.covered.shape
    gpu = _as_float(image, shape, "image")
    base = _as_float(shadowless, shape, "shadowless")
    exact = base + (reference.color - reference.shadowless)[..., :3]
    marks = np.zeros(shape + (3,))
    marks[reference.covered] = 0.15
    for light in reference.lights:
        marks[reference.shadowed(light)] = 0.4
    band = np.zeros(shape, dtype=bool)
    for light in reference.lights:
        band |= pixels_near(shape, boundary_midpoints(reference.shadowed(light), reference.covered), WRONG_STATE_BAND)
    marks[band] = 0.8
    color_off = reference.covered & (np.abs(gpu - exact).max(-1) > COLOR_TOLERANCE)
    marks[color_off & ~band] = (1.0, 0.0, 1.0)
    gpu_states = _gpu_states(reference, gpu, base, visibility)
    for light in reference.lights:
        exact_state = reference.shadowed(light)
        wrong = reference.matters(light) & (gpu_states[light] != exact_state)
        near = pixels_near(shape, boundary_midpoints(exact_state, reference.covered), WRONG_STATE_BAND)
        marks[wrong & near] = (1.0, 1.0, 0.0)
        marks[wrong & ~near] = (1.0, 0.0, 0.0)
    picture = np.concatenate([gpu, np.clip(exact, 0.0, 1.0), marks], axis=1)
    return np.round(np.clip(picture, 0.0, 1.0) * 255.0).astype(np.uint8)


def check_shadows(reference: ShadowReference, image: np.ndarray, shadowless: np.ndarray, *,
                  visibility: np.ndarray | None = None, name: str = "", picture_dir: str | os.PathLike | None = None) -> ShadowReport:
    """`measure_shadows`, then raise ShadowError naming every broken guarantee; on failure
    NAME.shadows.png (failure_picture) is written to `picture_dir` (default: the folder in
    $WGPU_SHADING_FAILURES, else the current folder's `shadow-failures/`)."""
    report = measure_shadows(reference, image, shadowless, visibility=visibility, name=name)
    if report.passed:
        return report
    from ...assets.image_writers import write_image

    folder = Path(picture_dir or os.environ.get("WGPU_SHADING_FAILURES") or "shadow-failures")
    folder.mkdir(parents=True, exist_ok=True)
    stem = "".join(c if c.isalnum() or c in "-_." else "_" for c in report.name)
    path = folder / f"{stem}.shadows.png"
    write_image(path, failure_picture(reference, image, shadowless, visibility))
    raise ShadowError("\n".join([report.summary(), *report.failures, f"picture (GPU | exact | disagreement): {path}"]))
