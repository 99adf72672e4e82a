"""How far one image is from another, in 8-bit steps: the error measure that `--shading auto`
(auto_shading.py) chooses by and the accuracy study (`study/accuracy/`, docs/accuracy.md)
reports. Per pixel, the largest absolute difference over R, G and B of the colours clamped
to [0, 1], in units of 1/255; `ErrorStats` summarises the errors of the compared pixels."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ERROR_UNIT = 1.0 / 255.0  # errors are reported in multiples of one 8-bit step


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
