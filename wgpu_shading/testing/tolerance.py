"""How different two images may be and still match (`Tolerance`), and the error every
golden-image module raises (`GoldenError`). The measurements behind the defaults are in
docs/golden-tests.md.

Pure numpy; the bottom of the golden-image modules (imports none of them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import WgpuShadingError


class GoldenError(WgpuShadingError, ValueError):
    """A golden-image comparison cannot be made: unreadable or missing reference, bad
    tolerance, an image of the wrong shape or type."""


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

    def allowed_count(self, pixel_count: int) -> int:
        """How many of `pixel_count` pixels may differ by more than the threshold."""
        return math.floor(self.max_fraction * pixel_count + 1e-9)

    def describe(self) -> str:
        parts = [f"threshold {self.threshold}/255", f"max fraction {percent(self.max_fraction)}"]
        if self.max_difference is not None:
            parts.append(f"max difference {self.max_difference}/255")
        if self.flip_mean is not None:
            parts.append(f"FLIP mean {self.flip_mean:g}")
        return ", ".join(parts)


def percent(fraction: float) -> str:
    """A fraction as a percentage for messages: small ones keep their digits."""
    value = fraction * 100.0
    if value == 0:
        return "0 %"
    if value < 0.01:
        return f"{value:.3f} %"
    return f"{value:.2f} %"
