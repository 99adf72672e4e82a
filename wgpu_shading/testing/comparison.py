"""The comparison of two images and its metrics: `compare` → `Comparison`, and the optional
NVIDIA FLIP metric.

The metric (docs/golden-tests.md has the measurements behind the defaults): per channel
absolute difference in units of 1/255. A pixel *differs* when any channel differs by more
than `Tolerance.threshold`; the images match when at most `Tolerance.max_fraction` of the
pixels differ (and, optionally, no channel differs by more than `max_difference`, and the
mean NVIDIA FLIP error is at most `flip_mean`). Every comparison also reports the maximum
difference and where it is, and the 99.9th percentile of the per-pixel difference; a
failed one also says what the difference looks like (diagnosis.py).

Pure numpy; imports nothing from the GPU side.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .diagnosis import CHANNELS, diagnose
from .images import as_rgba8, size_text
from .tolerance import GoldenError, Tolerance, percent

_PERCENTILE = 99.9


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
            f"{self.over_count} pixels ({percent(self.over_fraction)}) of {self.pixel_count} differ by more than "
            f"{t.threshold}/255 (allowed: {percent(t.max_fraction)}); max {self.max_difference}/255"
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


def compare(actual, expected, tolerance: Tolerance | None = None) -> Comparison:
    """Compare two images (uint8, or float in [0, 1]; 1, 3 or 4 channels; RGB counts as opaque)."""
    tolerance = tolerance or Tolerance()
    if not isinstance(tolerance, Tolerance):
        raise GoldenError(f"tolerance: expected a Tolerance, got {type(tolerance).__name__}")
    a = as_rgba8(actual, "actual image")
    e = as_rgba8(expected, "expected image")
    height, width = e.shape[:2]
    if a.shape != e.shape:
        text = f"sizes differ: actual {size_text(a)}, expected {size_text(e)}"
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
    allowed = tolerance.allowed_count(pixel_count)
    if over_count > allowed:
        failures.append(
            f"{over_count} pixels ({percent(over_count / pixel_count)}) differ by more than {tolerance.threshold}/255; "
            f"at most {allowed} ({percent(tolerance.max_fraction)}) may"
        )
    if tolerance.max_difference is not None and max_difference > tolerance.max_difference:
        failures.append(f"max difference {max_difference}/255 exceeds the cap of {tolerance.max_difference}/255")
    flip_value = None
    if tolerance.flip_mean is not None:
        flip_value = flip_mean(a, e)
        if flip_value > tolerance.flip_mean:
            failures.append(f"mean FLIP error {flip_value:.4f} exceeds {tolerance.flip_mean:g}")
    passed = not failures
    diagnosis = () if passed else tuple(diagnose(a, e, delta, over, tolerance.threshold))
    return Comparison(
        passed=passed, tolerance=tolerance, shape=(height, width), pixel_count=pixel_count,
        over_count=over_count, max_difference=max_difference, max_location=(row, col),
        max_channel=max_channel, percentile=percentile, channel_max=channel_max,
        flip_mean=flip_value, failures=tuple(failures), diagnosis=diagnosis,
    )


def flip_mean(actual, expected) -> float:
    """Mean NVIDIA FLIP error (LDR, sRGB inputs, default 67 pixels per degree) of the RGB
    channels; 0 = identical, 1 = maximal. Needs the [flip] extra (flip-evaluator)."""
    return float(_flip(actual, expected)[1])


def flip_error_map(actual, expected) -> np.ndarray:
    """FLIP's per-pixel error, colored with its magma map, as (H, W, 4) uint8."""
    error_map = _flip(actual, expected)[0]
    return as_rgba8(np.clip(error_map, 0.0, 1.0), "FLIP error map")


def _flip(actual, expected):
    try:
        import flip_evaluator
    except ImportError:
        from ..errors import install_hint

        raise GoldenError(f"the FLIP metric needs the optional package flip-evaluator; {install_hint('flip')}") from None
    a = as_rgba8(actual, "actual image")[:, :, :3].astype(np.float32) / 255.0
    e = as_rgba8(expected, "expected image")[:, :, :3].astype(np.float32) / 255.0
    if a.shape != e.shape:
        raise GoldenError(f"FLIP: sizes differ ({size_text(a)} vs {size_text(e)})")
    return flip_evaluator.evaluate(e, a, "LDR")
