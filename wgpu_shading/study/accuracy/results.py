"""The accuracy study's results: `Study` (one row per size × tessellation × variant, with the
columns of `ROW_FIELDS`) and the answers derived from its rows: the `cheapest` setting
within an error budget and the `pareto_front` of time against error."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

from .config import StudyConfig


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
