"""Golden-image comparison: is a rendered image the same as a stored reference, within a
tolerance that absorbs lavapipe's differences between Mesa versions and CPUs but not a
real change to the picture?

    from wgpu_shading.golden import Tolerance, compare, check_image

    result = compare(actual, expected)                 # two (H, W, 3|4) uint8 arrays
    assert result.passed, result.message               # names what failed

    outcome = check_image(actual, "golden.png")        # reads the PNG; on failure writes
    print(outcome.report())                            # golden.actual/expected/diff.png

The metric (docs/golden-tests.md has the measurements behind the defaults): per channel
absolute difference in units of 1/255. A pixel *differs* when any channel differs by more
than `Tolerance.threshold`; the images match when at most `Tolerance.max_fraction` of the
pixels differ (and, optionally, no channel differs by more than `max_difference`, and the
mean NVIDIA FLIP error is at most `flip_mean`). Every comparison also reports the maximum
difference and where it is, and the 99.9th percentile of the per-pixel difference.

Pure numpy; imports nothing from the GPU side.
"""

from __future__ import annotations

import itertools
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import WgpuShadingError

CHANNELS = ("red", "green", "blue", "alpha")
DEFAULT_AMPLIFICATION = 10
_SHIFT_RADIUS = 2  # offsets tried when looking for a shift, in pixels
_PERCENTILE = 99.9


class GoldenError(WgpuShadingError, ValueError):
    """A golden-image comparison cannot be made: unreadable or missing reference, bad
    tolerance, an image of the wrong shape or type."""


# --------------------------------------------------------------------------- tolerance


@dataclass(frozen=True)
class Tolerance:
    """How different two images may be and still match.

    threshold:      a pixel differs when any channel differs by more than this many units
                    of 1/255. Default 8: lavapipe's largest difference between CPUs
                    (emulated AVX2/FMA vs SSE2 code paths) is 4; a missing highlight, a
                    moved light or a 1-pixel shift differ by tens to hundreds.
    max_fraction:   the images match when at most this fraction of the pixels differ.
                    Default 0.001 (0.1 %): room for a few edge pixels that a change in
                    rasterization or texture-LOD rounding flips, too little for a 1-pixel
                    shift of an object (its whole outline differs).
    max_difference: if set, no channel of any pixel may differ by more than this (a hard
                    cap on top of the fraction rule). Default None.
    flip_mean:      if set, the mean NVIDIA FLIP error (0..1, perceptual) must be at most
                    this; needs the optional package `flip-evaluator`. Default None.
    """

    threshold: int = 8
    max_fraction: float = 0.001
    max_difference: int | None = None
    flip_mean: float | None = None

    def __post_init__(self) -> None:
        if isinstance(self.threshold, bool) or not isinstance(self.threshold, (int, np.integer)) or not 0 <= self.threshold <= 255:
            raise GoldenError(f"tolerance threshold: expected an integer 0..255 (units of 1/255), got {self.threshold!r}")
        if not isinstance(self.max_fraction, (int, float)) or not 0.0 <= self.max_fraction <= 1.0:
            raise GoldenError(f"tolerance max_fraction: expected a fraction 0..1, got {self.max_fraction!r}")
        if self.max_difference is not None and (
            isinstance(self.max_difference, bool)
            or not isinstance(self.max_difference, (int, np.integer))
            or not 0 <= self.max_difference <= 255
        ):
            raise GoldenError(f"tolerance max_difference: expected an integer 0..255 or None, got {self.max_difference!r}")
        if self.flip_mean is not None and (not isinstance(self.flip_mean, (int, float)) or not 0.0 <= self.flip_mean <= 1.0):
            raise GoldenError(f"tolerance flip_mean: expected a number 0..1 or None, got {self.flip_mean!r}")

    def describe(self) -> str:
        parts = [f"threshold {self.threshold}/255", f"max fraction {_percent(self.max_fraction)}"]
        if self.max_difference is not None:
            parts.append(f"max difference {self.max_difference}/255")
        if self.flip_mean is not None:
            parts.append(f"FLIP mean {self.flip_mean:g}")
        return ", ".join(parts)


# --------------------------------------------------------------------------- result


@dataclass(frozen=True)
class Comparison:
    """The outcome of `compare`. Differences are in units of 1/255; a pixel's difference
    is the largest of its channels'."""

    passed: bool
    tolerance: Tolerance
    shape: tuple[int, int]  # (height, width) of the expected image
    pixel_count: int
    over_count: int  # pixels differing by more than the threshold
    max_difference: int
    max_location: tuple[int, int] | None  # (row, col) of the largest difference
    max_channel: str | None  # the channel of the largest difference
    percentile: int  # 99.9th percentile of the per-pixel difference
    channel_max: dict[str, int] = field(default_factory=dict)
    flip_mean: float | None = None
    failures: tuple[str, ...] = ()  # which rule failed, one line each
    diagnosis: tuple[str, ...] = ()  # what the difference looks like, when it failed
    size_mismatch: str | None = None

    @property
    def over_fraction(self) -> float:
        return self.over_count / self.pixel_count if self.pixel_count else 0.0

    def summary(self) -> str:
        """One line of metrics."""
        if self.size_mismatch:
            return self.size_mismatch
        t = self.tolerance
        text = (
            f"{self.over_count} pixels ({_percent(self.over_fraction)}) of {self.pixel_count} differ by more than "
            f"{t.threshold}/255 (allowed: {_percent(t.max_fraction)}); max {self.max_difference}/255"
        )
        if self.max_location is not None and self.max_difference > 0:
            row, col = self.max_location
            text += f" at (row {row}, col {col}, {self.max_channel})"
        text += f"; 99.9th percentile {self.percentile}/255"
        if self.flip_mean is not None:
            text += f"; FLIP mean {self.flip_mean:.4f}"
        return text

    @property
    def message(self) -> str:
        """The summary, then (on failure) which rules failed and what the difference looks like."""
        lines = [("match: " if self.passed else "MISMATCH: ") + self.summary()]
        if not self.passed:
            lines += [f"failed: {failure}" for failure in self.failures if not self.size_mismatch]
            lines += [f"looks like: {note}" for note in self.diagnosis]
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.message


# --------------------------------------------------------------------------- images


def as_rgba8(image, what: str = "image") -> np.ndarray:
    """An (H, W, 4) uint8 copy of a uint8 image with 1, 3 or 4 channels, or of a float image
    in [0, 1] (rounded like the renderer's 8-bit target)."""
    array = np.asarray(image)
    if array.ndim == 2:
        array = array[:, :, None]
    if array.ndim != 3 or array.shape[2] not in (1, 3, 4) or array.shape[0] == 0 or array.shape[1] == 0:
        raise GoldenError(f"{what}: expected an (height, width, 1|3|4) image, got shape {array.shape}")
    if array.dtype == np.uint8:
        pass
    elif np.issubdtype(array.dtype, np.floating):
        if not np.isfinite(array).all():
            raise GoldenError(f"{what}: float image holds NaN or infinity")
        array = np.round(np.clip(array, 0.0, 1.0) * 255.0).astype(np.uint8)
    else:
        raise GoldenError(f"{what}: expected uint8 or float pixels, got {array.dtype}")
    if array.shape[2] == 1:
        array = np.repeat(array, 3, axis=2)
    if array.shape[2] == 3:
        array = np.concatenate([array, np.full(array.shape[:2] + (1,), 255, np.uint8)], axis=2)
    return np.ascontiguousarray(array)


def read_image(path: str | os.PathLike[str]) -> np.ndarray:
    """An 8-bit PNG (or another image format Pillow reads) as (H, W, 4) uint8."""
    import imageio.v3 as iio

    path = Path(path)
    if not path.is_file():
        raise GoldenError(f"reference {str(path)!r} does not exist")
    try:
        image = iio.imread(path, plugin="pillow")
    except Exception as error:  # imageio raises many kinds
        raise GoldenError(f"reference {str(path)!r} cannot be read as an image: {error}") from None
    if image.dtype != np.uint8:
        raise GoldenError(f"reference {str(path)!r}: expected 8-bit pixels, got {image.dtype}")
    return as_rgba8(image, f"reference {str(path)!r}")


def write_image(path: str | os.PathLike[str], image) -> Path:
    """Write an image as an 8-bit RGBA PNG, creating the folder."""
    import imageio.v3 as iio

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    iio.imwrite(path, as_rgba8(image), extension=".png")
    return path


def diff_image(actual, expected, amplification: float = DEFAULT_AMPLIFICATION) -> np.ndarray:
    """The amplified difference as an opaque RGB(A) image: each color channel is
    |actual − expected| × amplification (clipped to 255), so black means identical and the
    hue says which channel differs; an alpha difference shows in all three (gray/white)."""
    a = as_rgba8(actual, "actual").astype(np.int16)
    e = as_rgba8(expected, "expected").astype(np.int16)
    if a.shape != e.shape:
        raise GoldenError(f"diff image: sizes differ ({_size(a)} vs {_size(e)})")
    delta = np.abs(a - e)
    rgb = np.maximum(delta[:, :, :3], delta[:, :, 3:4])
    amplified = np.clip(np.round(rgb * float(amplification)), 0, 255).astype(np.uint8)
    return np.concatenate([amplified, np.full(amplified.shape[:2] + (1,), 255, np.uint8)], axis=2)


# --------------------------------------------------------------------------- comparison


def compare(actual, expected, tolerance: Tolerance | None = None) -> Comparison:
    """Compare two images (uint8, or float in [0, 1]; 1, 3 or 4 channels; RGB counts as opaque)."""
    tolerance = tolerance or Tolerance()
    if not isinstance(tolerance, Tolerance):
        raise GoldenError(f"tolerance: expected a Tolerance, got {type(tolerance).__name__}")
    a = as_rgba8(actual, "actual image")
    e = as_rgba8(expected, "expected image")
    height, width = e.shape[:2]
    if a.shape != e.shape:
        text = f"sizes differ: actual {_size(a)}, expected {_size(e)}"
        return Comparison(
            passed=False, tolerance=tolerance, shape=(height, width), pixel_count=height * width,
            over_count=height * width, max_difference=255, max_location=None, max_channel=None,
            percentile=255, failures=(text,), size_mismatch=text,
        )
    delta = np.abs(a.astype(np.int16) - e.astype(np.int16))  # (H, W, 4)
    per_pixel = delta.max(axis=2)
    over = per_pixel > tolerance.threshold
    over_count = int(over.sum())
    pixel_count = height * width
    max_difference = int(per_pixel.max())
    flat_index = int(np.argmax(per_pixel))
    row, col = divmod(flat_index, width)
    max_channel = CHANNELS[int(np.argmax(delta[row, col]))]
    percentile = int(np.percentile(per_pixel, _PERCENTILE, method="higher"))
    channel_max = {name: int(delta[:, :, index].max()) for index, name in enumerate(CHANNELS)}

    failures = []
    allowed = math.floor(tolerance.max_fraction * pixel_count + 1e-9)
    if over_count > allowed:
        failures.append(
            f"{over_count} pixels ({_percent(over_count / pixel_count)}) differ by more than {tolerance.threshold}/255; "
            f"at most {allowed} ({_percent(tolerance.max_fraction)}) may"
        )
    if tolerance.max_difference is not None and max_difference > tolerance.max_difference:
        failures.append(f"max difference {max_difference}/255 exceeds the cap of {tolerance.max_difference}/255")
    flip_value = None
    if tolerance.flip_mean is not None:
        flip_value = flip_mean(a, e)
        if flip_value > tolerance.flip_mean:
            failures.append(f"mean FLIP error {flip_value:.4f} exceeds {tolerance.flip_mean:g}")
    passed = not failures
    diagnosis = () if passed else tuple(_diagnose(a, e, delta, over, tolerance.threshold))
    return Comparison(
        passed=passed, tolerance=tolerance, shape=(height, width), pixel_count=pixel_count,
        over_count=over_count, max_difference=max_difference, max_location=(row, col),
        max_channel=max_channel, percentile=percentile, channel_max=channel_max,
        flip_mean=flip_value, failures=tuple(failures), diagnosis=diagnosis,
    )


def flip_mean(actual, expected) -> float:
    """Mean NVIDIA FLIP error (LDR, sRGB inputs, default 67 pixels per degree) of the RGB
    channels; 0 = identical, 1 = maximal. Needs `pip install flip-evaluator`."""
    return float(_flip(actual, expected)[1])


def flip_error_map(actual, expected) -> np.ndarray:
    """FLIP's per-pixel error, colored with its magma map, as (H, W, 4) uint8."""
    error_map = _flip(actual, expected)[0]
    return as_rgba8(np.clip(error_map, 0.0, 1.0), "FLIP error map")


def _flip(actual, expected):
    try:
        import flip_evaluator
    except ImportError:
        raise GoldenError(
            "the FLIP metric needs the optional package flip-evaluator: pip install 'wgpu-shading[flip]'"
        ) from None
    a = as_rgba8(actual, "actual image")[:, :, :3].astype(np.float32) / 255.0
    e = as_rgba8(expected, "expected image")[:, :, :3].astype(np.float32) / 255.0
    if a.shape != e.shape:
        raise GoldenError(f"FLIP: sizes differ ({_size(a)} vs {_size(e)})")
    return flip_evaluator.evaluate(e, a, "LDR")


# --------------------------------------------------------------------------- diagnosis


def _diagnose(a: np.ndarray, e: np.ndarray, delta: np.ndarray, over: np.ndarray, threshold: int) -> list[str]:
    """Plain-language guesses at what the difference is; each guess is tested, not assumed."""
    notes: list[str] = []
    if not over.any():
        return notes
    swapped = _channel_permutation(a, e, threshold, int(over.sum()))
    if swapped:
        notes.append(swapped)
    shift = _shift(a, e, threshold)
    if shift:
        notes.append(shift)
    notes.append(_channels(delta, over))
    notes.append(_brightness(a, e, over))
    highlight = _highlight(a, e, over)
    if highlight and not shift and not swapped:
        notes.append(highlight)
    notes.append(_region(over))
    return notes


def _channels(delta: np.ndarray, over: np.ndarray) -> str:
    totals = delta[over].astype(np.float64).sum(axis=0)  # per channel, over the differing pixels
    share = totals / max(totals.sum(), 1e-12)
    order = np.argsort(-share)
    first, second = int(order[0]), int(order[1])
    if share[first] >= 0.6:
        return f"the largest differences are in the {CHANNELS[first]} channel ({share[first]:.0%} of the total)"
    if share[first] + share[second] >= 0.85:
        return f"the differences are in the {CHANNELS[first]} and {CHANNELS[second]} channels ({share[first] + share[second]:.0%} of the total)"
    if share[3] < 0.1:
        return "the differences are spread over the red, green and blue channels alike"
    return "the differences are spread over all channels, alpha included"


def _brightness(a: np.ndarray, e: np.ndarray, over: np.ndarray) -> str:
    signed = a[over][:, :3].astype(np.float64) - e[over][:, :3].astype(np.float64)  # (n, 3)
    channel_mean = signed.mean(axis=0)
    per_pixel = signed.mean(axis=1)
    if not np.abs(signed).any():
        return "only alpha differs"
    changes = ", ".join(f"{CHANNELS[i]} {channel_mean[i]:+.0f}" for i in range(3))
    signs = {int(np.sign(round(v))) for v in channel_mean} - {0}
    if len(signs) > 1:
        return f"a change of hue, not of brightness: mean change over the differing pixels {changes} (/255)"
    mean = per_pixel.mean()
    if abs(mean) >= 0.6 * np.abs(per_pixel).mean():
        word = "brighter" if mean > 0 else "darker"
        return f"the actual image is {word} there: mean change over the differing pixels {changes} (/255)"
    brighter = float((per_pixel > 0).mean())
    return f"mixed: {brighter:.0%} of the differing pixels are brighter, {1 - brighter:.0%} darker"


def _highlight(a: np.ndarray, e: np.ndarray, over: np.ndarray) -> str | None:
    """Did the brightest spot of one image (a specular highlight, most often) dim or appear?"""
    count = max(4, int(0.002 * over.size))
    luminance_e = e[:, :, :3].astype(np.float64) @ (0.2126, 0.7152, 0.0722)
    luminance_a = a[:, :, :3].astype(np.float64) @ (0.2126, 0.7152, 0.0722)
    for image, other, word in ((luminance_e, luminance_a, "dimmed or gone"), (luminance_a, luminance_e, "new")):
        top = np.argsort(image, axis=None)[-count:]
        hit = over.reshape(-1)[top]
        drop = image.reshape(-1)[top] - other.reshape(-1)[top]
        # Only a large change of the brightest spot counts: at least 25/255 and 15 % of its level.
        if hit.mean() >= 0.5 and np.median(drop) >= max(25.0, 0.15 * np.median(image.reshape(-1)[top])):
            if word == "new":
                return f"a bright spot (highlight?) in the actual image is not in the expected one: its brightest pixels are {np.median(drop):.0f}/255 brighter"
            return f"the expected image's brightest spot (highlight?) is {word}: {np.median(drop):.0f}/255 darker in the actual image"
    return None


def _region(over: np.ndarray) -> str:
    rows = np.flatnonzero(over.any(axis=1))
    cols = np.flatnonzero(over.any(axis=0))
    r0, r1, c0, c1 = int(rows[0]), int(rows[-1]), int(cols[0]), int(cols[-1])
    height, width = over.shape
    box = (r1 - r0 + 1) * (c1 - c0 + 1)
    where = f"rows {r0}–{r1}, cols {c0}–{c1}"
    share = box / (height * width)
    if share <= 0.1:
        return f"a local difference: all differing pixels lie within {where} ({share:.1%} of the image)"
    return f"differing pixels spread over {where} ({share:.0%} of the image)"


def _shift(a: np.ndarray, e: np.ndarray, threshold: int) -> str | None:
    """Does moving the actual image by a few pixels make it match much better?"""
    r = _SHIFT_RADIUS
    height, width = e.shape[:2]
    if height <= 4 * r or width <= 4 * r:
        return None
    core = e[r : height - r, r : width - r].astype(np.int16)

    def count(dy: int, dx: int) -> int:
        # actual[y + dy, x + dx] against expected[y, x]: content moved by (dx, dy) in the actual image
        window = a[r + dy : height - r + dy, r + dx : width - r + dx].astype(np.int16)
        return int((np.abs(window - core).max(axis=2) > threshold).sum())

    base = count(0, 0)
    if base == 0:
        return None
    best = min(((count(dy, dx), dy, dx) for dy in range(-r, r + 1) for dx in range(-r, r + 1) if (dy, dx) != (0, 0)))
    best_count, dy, dx = best
    if best_count > 0.2 * base:
        return None
    moves = []
    if dx:
        moves.append(f"{abs(dx)} pixel{'s' if abs(dx) > 1 else ''} {'right' if dx > 0 else 'left'}")
    if dy:
        moves.append(f"{abs(dy)} pixel{'s' if abs(dy) > 1 else ''} {'down' if dy > 0 else 'up'}")
    return (
        f"a shift: the actual image is the expected one moved {' and '.join(moves)} "
        f"(that offset leaves {best_count} of {base} differing pixels)"
    )


def _channel_permutation(a: np.ndarray, e: np.ndarray, threshold: int, base: int) -> str | None:
    """Does reordering the actual image's color channels make it match much better?"""
    best = None
    for perm in itertools.permutations(range(3)):
        if perm == (0, 1, 2):
            continue
        permuted = a[:, :, list(perm) + [3]].astype(np.int16)
        count = int((np.abs(permuted - e.astype(np.int16)).max(axis=2) > threshold).sum())
        if best is None or count < best[0]:
            best = (count, perm)
    if best is None or best[0] > 0.2 * base:
        return None
    perm = best[1]
    moved = [i for i in range(3) if perm[i] != i]
    if len(moved) == 2:
        i, j = moved
        return f"swapped color channels: {CHANNELS[i]} and {CHANNELS[j]} are exchanged (swapping them back leaves {best[0]} differing pixels)"
    # perm[i] = j: expected channel i holds what the actual image has in channel j
    mapping = ", ".join(f"actual {CHANNELS[perm[i]]} → {CHANNELS[i]}" for i in range(3))
    return f"rotated color channels ({mapping} would match; leaves {best[0]} differing pixels)"


def _percent(fraction: float) -> str:
    value = fraction * 100.0
    if value == 0:
        return "0 %"
    if value < 0.01:
        return f"{value:.3f} %"
    return f"{value:.2f} %"


def _size(image: np.ndarray) -> str:
    return f"{image.shape[1]}×{image.shape[0]}"


# --------------------------------------------------------------------------- check against a file


@dataclass(frozen=True)
class CheckResult:
    """The outcome of `check_image`.

    status: "passed" (matches the reference), "failed" (differs; images written),
            "created" (no reference existed; written with update=True),
            "updated" (differed; rewritten with update=True)
    """

    status: str
    reference: Path
    comparison: Comparison | None = None
    written: tuple[Path, ...] = ()

    @property
    def passed(self) -> bool:
        return self.status != "failed"

    def report(self) -> str:
        """What a person needs: the verdict, the metrics, what failed, the files written."""
        ref = str(self.reference)
        if self.status == "created":
            return f"created reference {ref}"
        lines = []
        if self.status == "updated":
            lines.append(f"updated reference {ref} (it differed: {self.comparison.summary()})")
        elif self.status == "passed":
            lines.append(f"PASS {ref}: {self.comparison.summary()}")
        else:
            lines.append(f"FAIL {ref}: {self.comparison.summary()}")
            lines += [f"  failed: {f}" for f in self.comparison.failures if not self.comparison.size_mismatch]
            lines += [f"  looks like: {note}" for note in self.comparison.diagnosis]
            if self.written:
                lines.append("  wrote " + ", ".join(str(p) for p in self.written))
        return "\n".join(lines)


def failure_paths(reference: str | os.PathLike[str], output_dir: str | os.PathLike[str] | None = None) -> dict[str, Path]:
    """Where `check_image` writes the images of a failure: NAME.actual.png, NAME.expected.png
    and NAME.diff.png next to the reference, or in output_dir."""
    reference = Path(reference)
    folder = Path(output_dir) if output_dir is not None else reference.parent
    stem = reference.stem
    return {kind: folder / f"{stem}.{kind}.png" for kind in ("actual", "expected", "diff")}


def remove_failure_images(reference, output_dir=None) -> None:
    """Delete the images an earlier failure left for this reference (exactly those names)."""
    paths = failure_paths(reference, output_dir)
    flip_path = paths["diff"].with_name(paths["diff"].name.replace(".diff.png", ".flip.png"))
    for path in (*paths.values(), flip_path):
        if path.is_file():
            path.unlink()


def write_failure_images(
    actual, expected, reference, output_dir=None, amplification: float = DEFAULT_AMPLIFICATION, flip: bool = False
) -> tuple[Path, ...]:
    """Write actual, expected (when there is one) and the amplified diff (same sizes only);
    with flip=True also FLIP's error map as NAME.flip.png."""
    paths = failure_paths(reference, output_dir)
    remove_failure_images(reference, output_dir)  # no stale diff from an earlier run
    written = [write_image(paths["actual"], actual)]
    if expected is not None:
        written.append(write_image(paths["expected"], expected))
        if as_rgba8(actual).shape == as_rgba8(expected).shape:
            written.append(write_image(paths["diff"], diff_image(actual, expected, amplification)))
            if flip:
                flip_path = paths["diff"].with_name(paths["diff"].name.replace(".diff.png", ".flip.png"))
                written.append(write_image(flip_path, flip_error_map(actual, expected)))
    return tuple(written)


def check_image(
    actual,
    reference: str | os.PathLike[str],
    tolerance: Tolerance | None = None,
    *,
    update: bool = False,
    output_dir: str | os.PathLike[str] | None = None,
    amplification: float = DEFAULT_AMPLIFICATION,
) -> CheckResult:
    """Compare an image with a reference PNG.

    Missing reference: written when update=True, else GoldenError. Mismatch: with
    update=True the reference is rewritten; otherwise NAME.actual.png, NAME.expected.png and
    NAME.diff.png are written next to the reference (or in output_dir) and the result says
    "failed". A reference that matches within the tolerance is never rewritten, so updating
    does not churn files with noise.
    """
    reference = Path(reference)
    actual = as_rgba8(actual, "actual image")
    if not reference.exists():
        if update:
            write_image(reference, actual)
            return CheckResult("created", reference, written=(reference,))
        raise GoldenError(f"reference {str(reference)!r} does not exist; create it with --update (CLI) or --update-golden (pytest)")
    expected = read_image(reference)
    comparison = compare(actual, expected, tolerance)
    if comparison.passed:
        remove_failure_images(reference, output_dir)
        return CheckResult("passed", reference, comparison)
    if update:
        remove_failure_images(reference, output_dir)
        write_image(reference, actual)
        return CheckResult("updated", reference, comparison, written=(reference,))
    written = write_failure_images(
        actual, expected, reference, output_dir, amplification, flip=comparison.flip_mean is not None
    )
    return CheckResult("failed", reference, comparison, written=written)


__all__: Sequence[str] = (
    "CheckResult",
    "Comparison",
    "GoldenError",
    "Tolerance",
    "as_rgba8",
    "check_image",
    "compare",
    "diff_image",
    "failure_paths",
    "flip_error_map",
    "flip_mean",
    "read_image",
    "remove_failure_images",
    "write_failure_images",
    "write_image",
)
