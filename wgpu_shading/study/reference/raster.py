"""The float64 reference's rasterizer: eye-space triangles → visible triangle and depth per pixel.

It follows Vulkan's rules as lavapipe implements them: pixel centres, window coordinates
snapped to 1/256 pixel (done here in exact int64 arithmetic, so ties on an edge are decided
exactly by the top-left rule), nearest surface wins. Triangles that cross the near plane or
leave a wide guard band are clipped in eye space first. Coverage is vectorized over
(triangle, candidate pixel) pairs, in chunks, so a mesh with a million triangles renders in
seconds. Shading is not done here: see `shading.py`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...scene import Camera
from .transforms import half_extents, window_coordinates

SUBPIXEL = 256  # lavapipe snaps window coordinates to 1/256 pixel
# Triangles reaching further than this many pixels outside the image are clipped in eye
# space first, so snapped coordinates stay small enough for exact int64 edge functions.
GUARD_BAND_PIXELS = 1 << 20
# How many (triangle, candidate pixel) pairs are tested at once: bounds peak memory.
CANDIDATE_CHUNK = 1 << 21


# --------------------------------------------------------------------------- clipping


def _clip_planes(camera: Camera, size: tuple[int, int]) -> list[tuple[np.ndarray, float]]:
    """Eye-space half-spaces n·p + d >= 0: the near plane and the guard band's four sides."""
    width, height = size
    # |x_ndc| <= gx keeps window x within GUARD_BAND_PIXELS of the image; same for y.
    gx = 1.0 + 2.0 * GUARD_BAND_PIXELS / width
    gy = 1.0 + 2.0 * GUARD_BAND_PIXELS / height
    sx, sy = half_extents(camera, size)
    near = (np.array([0.0, 0.0, -1.0]), -camera.near)  # depth >= near
    if camera.orthographic:  # |x| <= gx·sx, a box
        return [near] + [(np.array(axis), limit) for axis, limit in (
            ([-1.0, 0.0, 0.0], gx * sx), ([1.0, 0.0, 0.0], gx * sx), ([0.0, -1.0, 0.0], gy * sy), ([0.0, 1.0, 0.0], gy * sy))]
    return [
        near,
        (np.array([-1.0, 0.0, -gx * sx]), 0.0),  # x <= gx·sx·depth
        (np.array([1.0, 0.0, -gx * sx]), 0.0),
        (np.array([0.0, -1.0, -gy * sy]), 0.0),
        (np.array([0.0, 1.0, -gy * sy]), 0.0),
    ]


def _clip_polygon(polygon: list[np.ndarray], planes: list[tuple[np.ndarray, float]]) -> list[np.ndarray]:
    """Sutherland–Hodgman: the part of a convex polygon inside every half-space (order kept)."""
    for normal, offset in planes:
        if not polygon:
            break
        clipped = []
        for k, current in enumerate(polygon):
            previous = polygon[k - 1]
            d_current = float(normal @ current + offset)
            d_previous = float(normal @ previous + offset)
            if (d_current >= 0.0) != (d_previous >= 0.0):
                t = d_previous / (d_previous - d_current)
                clipped.append(previous + t * (current - previous))
            if d_current >= 0.0:
                clipped.append(current)
        polygon = clipped
    return polygon


# --------------------------------------------------------------------------- rasterization


@dataclass
class ScreenTriangles:
    """Triangles ready for coverage tests, after clipping (one source triangle may give several).

    fixed:  (n, 3, 2) int64 window coordinates snapped to 1/256 pixel
    window: (n, 3, 2) float64 window coordinates before snapping
    depth:  (n, 3) float64 eye depth of each vertex
    source: (n,) int64 global index of the triangle they come from
    """

    fixed: np.ndarray
    window: np.ndarray
    depth: np.ndarray
    source: np.ndarray


def screen_triangles(eye_corners: np.ndarray, source: np.ndarray, camera: Camera, size: tuple[int, int]) -> ScreenTriangles:
    """Project (n, 3, 3) eye-space triangles; clip the few that cross the near plane or leave
    the guard band, so every vertex that gets snapped is in front of the camera and near the image."""
    width, height = size
    planes = _clip_planes(camera, size)
    needs_clip = np.zeros(len(eye_corners), dtype=bool)
    for normal, offset in planes:
        needs_clip |= (eye_corners @ normal + offset < 0.0).any(axis=1)
    corners = [eye_corners[~needs_clip]]
    sources = [source[~needs_clip]]
    for index in np.flatnonzero(needs_clip):
        polygon = _clip_polygon(list(eye_corners[index]), planes)
        for k in range(1, len(polygon) - 1):  # a fan keeps the winding
            corners.append(np.array([polygon[0], polygon[k], polygon[k + 1]])[None])
            sources.append(source[index : index + 1])
    eye = np.concatenate(corners)
    window = window_coordinates(eye, camera, size)
    fixed = np.rint(window * SUBPIXEL).astype(np.int64)  # round half to even, like lrint
    return ScreenTriangles(fixed=fixed, window=window, depth=-eye[..., 2], source=np.concatenate(sources))


def _edge_coefficients(fixed: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Integer edge functions E_k(x, y) = a·x + b·y + c for triangles wound so that the
    interior is where every E_k > 0 (window coordinates, y down). Top-left edges get +1 in c,
    so `E > 0` includes a pixel centre exactly on them and excludes it on the other edges.

    Returns a, b, c, each (n, 3) int64.
    """
    start = fixed
    end = np.roll(fixed, -1, axis=1)  # edge k runs from vertex k to vertex k+1
    dx = end[..., 0] - start[..., 0]
    dy = end[..., 1] - start[..., 1]
    # With y down and positive area, a top edge is horizontal running right (dy = 0, dx > 0),
    # and a left edge runs upwards (dy < 0).
    top_left = (dy < 0) | ((dy == 0) & (dx > 0))
    a = -dy
    b = dx
    c = dy * start[..., 0] - dx * start[..., 1] + top_left.astype(np.int64)
    return a, b, c


def signed_area_fixed(fixed: np.ndarray) -> np.ndarray:
    """Twice the signed area in snapped window coordinates (y down). The y flip reverses the
    sign: < 0 is counter-clockwise in NDC (y up), i.e. counter-clockwise as seen in the image."""
    e1 = fixed[:, 1] - fixed[:, 0]
    e2 = fixed[:, 2] - fixed[:, 0]
    return e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]


def _depth_planes(window: np.ndarray, depth: np.ndarray, orthographic: bool) -> np.ndarray:
    """Per triangle (a, b, c) with f(depth) = a·x + b·y + c in window coordinates, f the
    function of depth that is affine in screen space: 1/depth for a perspective camera
    (which is what makes perspective-correct interpolation work), depth itself for an
    orthographic one."""
    p0, p1, p2 = window[:, 0], window[:, 1], window[:, 2]
    inverse = depth if orthographic else 1.0 / depth
    e1, e2 = p1 - p0, p2 - p0
    area = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    safe_area = np.where(area != 0.0, area, 1.0)  # zero float area: the triangle is dropped anyway
    d1, d2 = inverse[:, 1] - inverse[:, 0], inverse[:, 2] - inverse[:, 0]
    a = (d1 * e2[:, 1] - d2 * e1[:, 1]) / safe_area
    b = (d2 * e1[:, 0] - d1 * e2[:, 0]) / safe_area
    c = inverse[:, 0] - a * p0[:, 0] - b * p0[:, 1]
    return np.stack([a, b, c], axis=1)


def _candidate_boxes(fixed: np.ndarray, size: tuple[int, int]) -> tuple[np.ndarray, ...]:
    """The pixels whose centres lie in each triangle's snapped bounding box, clipped to the image:
    first/last column and row (inclusive)."""
    width, height = size
    half = SUBPIXEL // 2  # pixel centre c sits at c·256 + 128
    low = fixed.min(axis=1) - half
    high = fixed.max(axis=1) - half
    first = -((-low) // SUBPIXEL)  # ceil division
    last = high // SUBPIXEL
    col0 = np.maximum(first[:, 0], 0)
    col1 = np.minimum(last[:, 0], width - 1)
    row0 = np.maximum(first[:, 1], 0)
    row1 = np.minimum(last[:, 1], height - 1)
    return col0, col1, row0, row1


@dataclass
class Visibility:
    """Per pixel (flattened row-major): nearest depth and the screen triangle that has it."""

    depth: np.ndarray
    triangle: np.ndarray  # index into ScreenTriangles, -1 where uncovered


def rasterize(tris: ScreenTriangles, size: tuple[int, int], near: float, far: float, orthographic: bool = False) -> Visibility:
    """Coverage (pixel centres, top-left rule, exact integer edge functions) and a z-buffer on
    eye depth. Ties in depth go to the earlier triangle, as the `greater` depth test does."""
    width, height = size
    best_depth = np.full(width * height, np.inf)
    best_triangle = np.full(width * height, -1, dtype=np.int64)

    fixed = tris.fixed.copy()
    area = signed_area_fixed(fixed)
    negative = area < 0
    fixed[negative] = fixed[negative][:, [0, 2, 1]]  # wind every triangle so its area is > 0
    col0, col1, row0, row1 = _candidate_boxes(fixed, size)
    keep = (area != 0) & (col0 <= col1) & (row0 <= row1)
    ids = np.flatnonzero(keep)
    if len(ids) == 0:
        return Visibility(best_depth, best_triangle)
    edge_a, edge_b, edge_c = (e[ids] for e in _edge_coefficients(fixed))
    planes = _depth_planes(tris.window, tris.depth, orthographic)[ids]
    col0, row0 = col0[ids], row0[ids]
    box_width = col1[ids] - col0 + 1
    counts = box_width * (row1[ids] - row0 + 1)
    ends = np.cumsum(counts)
    starts = ends - counts

    for chunk_start in range(0, int(ends[-1]), CANDIDATE_CHUNK):
        chunk_end = min(int(ends[-1]), chunk_start + CANDIDATE_CHUNK)
        # The triangles whose candidate ranges meet this chunk, and how many of theirs it holds.
        first = int(np.searchsorted(ends, chunk_start, side="right"))
        last = int(np.searchsorted(ends, chunk_end, side="left"))
        local = np.arange(first, last + 1)
        in_chunk = np.minimum(ends[local], chunk_end) - np.maximum(starts[local], chunk_start)
        tri = np.repeat(local, in_chunk)
        k = np.arange(chunk_start, chunk_end) - starts[tri]
        col = col0[tri] + k % box_width[tri]
        row = row0[tri] + k // box_width[tri]
        px = col * SUBPIXEL + SUBPIXEL // 2
        py = row * SUBPIXEL + SUBPIXEL // 2
        inside = np.ones(len(tri), dtype=bool)
        for e in range(3):
            inside &= edge_a[tri, e] * px + edge_b[tri, e] * py + edge_c[tri, e] > 0
        tri, col, row = tri[inside], col[inside], row[inside]
        # Eye depth at the pixel centre from the unsnapped plane of 1/depth.
        x, y = col + 0.5, row + 0.5
        interpolated = planes[tri, 0] * x + planes[tri, 1] * y + planes[tri, 2]
        if orthographic:
            depth = interpolated
        else:
            with np.errstate(divide="ignore"):
                depth = np.where(interpolated > 0.0, 1.0 / np.where(interpolated > 0.0, interpolated, 1.0), np.inf)
        in_range = (depth >= near * (1.0 - 1e-12)) & (depth <= far)  # clip to [near, far]
        tri, depth = tri[in_range], depth[in_range]
        pixel = row[in_range] * width + col[in_range]
        _merge_nearest(best_depth, best_triangle, pixel, depth, ids[tri])
    return Visibility(best_depth, best_triangle)


def _merge_nearest(best_depth, best_triangle, pixel, depth, triangle) -> None:
    """Fold fragments into the z-buffer: per pixel the smallest depth, then the lowest triangle."""
    if len(pixel) == 0:
        return
    order = np.lexsort((triangle, depth, pixel))
    pixel, depth, triangle = pixel[order], depth[order], triangle[order]
    first = np.ones(len(pixel), dtype=bool)
    first[1:] = pixel[1:] != pixel[:-1]
    pixel, depth, triangle = pixel[first], depth[first], triangle[first]
    current_depth = best_depth[pixel]
    # Triangles arrive in draw order, so on equal depth the one already stored was drawn first.
    nearer = depth < current_depth
    best_depth[pixel[nearer]] = depth[nearer]
    best_triangle[pixel[nearer]] = triangle[nearer]


def edge_margins(fixed: np.ndarray, columns: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Distance in pixels from pixel centres to the nearest edge of their (snapped) triangle."""
    px = (columns + 0.5) * SUBPIXEL
    py = (rows + 0.5) * SUBPIXEL
    start = fixed.astype(np.float64)
    end = np.roll(start, -1, axis=1)
    d = end - start
    cross = d[..., 0] * (py[:, None] - start[..., 1]) - d[..., 1] * (px[:, None] - start[..., 0])
    length = np.hypot(d[..., 0], d[..., 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        distance = np.where(length > 0, np.abs(cross) / np.where(length > 0, length, 1.0), 0.0)
    return distance.min(axis=1) / SUBPIXEL
