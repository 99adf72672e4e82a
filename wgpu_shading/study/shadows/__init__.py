"""Shadows, proved: the hard-case catalogue (`cases.py`) and the check that holds a GPU
image to the exact shadows of the float64 reference (`check.py`, docs/shadows.md#testing-shadows).

    from wgpu_shading.study.shadows import shadow_case, check_shadows, ShadowReference
    case = shadow_case("sphere_over_plane_10", (128, 128), scale=1e3, projection="orthographic")
    exact = ShadowReference(case.scene)                  # float64, ray-cast visibility
    report = check_shadows(exact, image, shadowless)     # raises ShadowError with a picture
"""

from __future__ import annotations

from .check import (
    ShadowError,
    ShadowReference,
    ShadowReport,
    LightResult,
    check_shadows,
    failure_picture,
    measure_shadows,
)
from .cases import ELEVATIONS, PROJECTIONS, SCALES, SHADOW_CASE_NAMES, ShadowCase, ShadowEllipse, ground_view, plane_points, shadow_case, shadow_cases

__all__ = [
    "LightResult", "ShadowError", "ShadowReference", "ShadowReport", "check_shadows", "failure_picture", "measure_shadows",
    "ELEVATIONS", "PROJECTIONS", "SCALES", "SHADOW_CASE_NAMES", "ShadowCase", "ShadowEllipse", "ground_view", "plane_points",
    "shadow_case", "shadow_cases",
]
