"""Helpers shared by the tests that compare the GPU with the float64 reference."""

from __future__ import annotations

import numpy as np

from wgpu_shading.study import reference as ref
from wgpu_shading.scene import Texture

TOLERANCE = 1.0 / 255.0
REQUIRED_FRACTION = 0.999
# Same-mesh comparisons: a pixel centre within this many pixels of an edge of its triangle
# may change hands on the GPU (float32 window coordinates, then 1/256-pixel snapping).
EDGE_BAND = 1.0 / 16.0
# Analytic shapes: the tessellated silhouette differs from the exact one; leave the rim out.
SILHOUETTE_BAND = 1.0


def compare(
    gpu_frame,
    reference: ref.ReferenceImage,
    band: float,
    what: str,
    depth_tolerance: float = 2e-5,
    min_compared: float = 0.8,
) -> tuple[float, float]:
    """Assert the acceptance criterion; returns (max abs error, fraction within 1/255).

    depth_tolerance: relative; float32 rounding for the same mesh, the tessellation's
    distance from the exact surface for analytic shapes. min_compared: the share of covered
    pixels that must lie outside the edge band (small, finely tessellated objects have less)."""
    gpu_covered = np.isfinite(gpu_frame.depth)
    compared = reference.covered & (reference.edge_margin >= band)
    assert compared.sum() >= min_compared * reference.covered.sum(), f"{what}: too few pixels compared"
    # The reference samples texture level 0 only: the scene must magnify its textures.
    assert reference.texel_footprint[compared].max() < 1.0, f"{what}: a texture is minified; the GPU would use mipmaps"
    missing = compared & ~gpu_covered
    assert not missing.any(), f"{what}: the GPU leaves {missing.sum()} pixels uncovered, first {np.argwhere(missing)[:3].tolist()}"
    # Coverage may differ only on the edge band.
    stray = (gpu_covered != reference.covered) & ~(reference.covered & (reference.edge_margin < band))
    stray_outside = stray & ~reference.covered
    # A pixel the GPU covers and the reference does not must touch the reference's coverage.
    near_coverage = np.zeros_like(reference.covered)
    padded = np.pad(reference.covered, 1)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            near_coverage |= padded[dy : dy + reference.covered.shape[0], dx : dx + reference.covered.shape[1]]
    assert not (stray_outside & ~near_coverage).any(), f"{what}: the GPU covers pixels far from any reference coverage"
    error = np.abs(gpu_frame.color.astype(np.float64) - reference.color).max(axis=-1)[compared]
    max_error = float(error.max())
    fraction = float((error <= TOLERANCE).mean())
    assert fraction >= REQUIRED_FRACTION, (
        f"{what}: {fraction:.5%} of {compared.sum()} pixels within 1/255 (need {REQUIRED_FRACTION:.1%}); "
        f"max error {max_error * 255:.3f}/255 at {np.argwhere(compared)[np.argmax(error)].tolist()}"
    )
    depth_error = np.abs(gpu_frame.depth[compared] / reference.depth[compared] - 1.0).max()
    assert depth_error < depth_tolerance, f"{what}: depth differs by {depth_error:.2e} (relative)"
    return max_error, fraction


# --------------------------------------------------------------------------- scenes


def smooth_texture() -> Texture:
    """A low-contrast periodic 8×8 texture, seamless under repeat wrap.

    lavapipe filters rgba8 textures in 8-bit fixed point (the filtered texel is rounded to a
    multiple of 1/255 and the weights have 8 bits), so its texels may be ~1/255 off the exact
    bilinear value; small steps between neighbours keep that within the rounding error."""
    i, j = np.meshgrid(np.arange(8), np.arange(8), indexing="xy")
    phase_u, phase_v = 2 * np.pi * i / 8, 2 * np.pi * j / 8
    pixels = np.stack(
        [
            150 + 40 * np.sin(phase_u),
            140 + 40 * np.cos(phase_v),
            120 + 30 * np.sin(phase_u + phase_v),
            225 + 30 * np.cos(phase_u),
        ],
        axis=-1,
    )
    return Texture(np.round(pixels).astype(np.uint8), name="smooth")
