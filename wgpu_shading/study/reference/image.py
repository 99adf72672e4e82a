"""What a render of the float64 reference returns: `ReferenceImage`, the colour plus what the
tests need to know about each pixel (coverage, visible triangle and object, depth, distance
to an edge, texel footprint). Both the same-mesh reference (`shading.py`) and the
analytic shapes (`analytic.py`) produce one."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ReferenceImage:
    """A float64 render plus what the tests need to know about each pixel.

    color:       (H, W, 4) float64, RGB clamped to [0, 1]; the background where uncovered
    covered:     (H, W) bool, some surface covers the pixel centre
    triangle:    (H, W) int64, index of the visible triangle in its object's mesh, -1 if none
    object:      (H, W) int64, index of the visible object in scene.objects, -1 if none
    depth:       (H, W) float64, eye-space distance along the view axis (-z), inf if none
    edge_margin: (H, W) float64, distance in pixels from the pixel centre to the nearest edge
                 of the visible (snapped) triangle, or to the silhouette for analytic shapes;
                 inf where uncovered. Small margins are where float32 rounding on the GPU
                 may legitimately hand the pixel to a neighbour.
    texel_footprint: (H, W) float64, texels per pixel step where a texture is sampled (the
                 largest change of (u·W, v·H) towards any of the four neighbouring pixel
                 centres, on the visible triangle's plane); 0 elsewhere. The reference samples
                 level 0 only, which is what the GPU does where this is below 1 (magnified).
    visibility:  (lights, H, W) float64, the exact V_i of each light at the pixel's surface
                 point: 0 where the segment towards light i meets a shadow
                 caster, else 1 (lights without shadows, objects that receive none and
                 uncovered pixels: 1). None where the renderer computed no shadows.
    """

    color: np.ndarray
    covered: np.ndarray
    triangle: np.ndarray
    object: np.ndarray
    depth: np.ndarray
    edge_margin: np.ndarray
    texel_footprint: np.ndarray
    visibility: np.ndarray | None = None

    def shadow_mask(self, light: int) -> np.ndarray:
        """(H, W) bool: covered pixels whose surface point is in light `light`'s exact shadow."""
        if self.visibility is None:
            return np.zeros(self.covered.shape, dtype=bool)
        return self.covered & (self.visibility[light] < 1.0)
