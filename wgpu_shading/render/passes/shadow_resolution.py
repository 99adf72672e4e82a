"""How many texels an "auto" shadow map needs (docs/shadows.md#auto): as many as make a
texel no wider than 1/AUTO_TEXELS_PER_PIXEL of a pixel of the image wherever the map may
shadow a visible receiver.

The accuracy study chose AUTO_MAP_SIZE on its hard cases, small images of wide casters. A
caster thinner than a texel as the light sees it (a quad nearly edge-on to the light, a thin
part of a model) casts a shadow a pixel or two wide whose edges the map draws up to half a
texel off: wherever such an edge passes that close to a pixel's point, the pixel takes the
wrong state, an isolated speck or gap along the thin shadow, several pixels from where the
exact states change (random scenes 290, 270, 229; the hard case sliver_shadow:
docs/shadows.md#what-the-random-scenes-find). Fewer specks need finer texels than pixels, so
the map is doubled from AUTO_MAP_SIZE until its texels are that fine on every receiver point
inside some view's window, up to AUTO_MAP_SIZE_LIMIT.

A texel of a view is `view.texel_size(size)` wide across the light (orthographic), or that
times the distance t along its axis (perspective); a pixel is 2·w / (P[1][1]·H) wide at a
point whose clip w is w (its depth for a perspective camera, 1 for an orthographic one).
Their ratio is affine over affine in the point, so its largest value over a convex region
is at one of its vertices: those of (receiver's box ∩ camera's view volume ∩ the view's
window), visible_regions.common_points.
"""

from __future__ import annotations

import math

import numpy as np

from ...scene import Scene
from ...scene.shadows import AUTO_MAP_SIZE, AUTO_MAP_SIZE_LIMIT, AUTO_TEXELS_PER_PIXEL
from ..shaders.uniforms import clip_from_eye
from .shadow_views import LightShadow, ShadowView
from .visible_regions import camera_frustum, common_points, visible_receivers, world_box


def _window_solid(view: ShadowView, far: float) -> np.ndarray:
    """(8, 3) world corners of what a view's window covers, from its near plane to `far`
    along its axis, indexed 4x + 2y + z."""
    x0, y0, x1, y1 = view.window
    local = []
    for x in (x0, x1):
        for y in (y0, y1):
            for t in (far, view.near):
                local.append((x, y, -t) if view.orthographic else (x * t, y * t, -t))
    world_from_light = np.linalg.inv(view.light_from_world)
    return np.asarray(local) @ world_from_light[:3, :3].T + world_from_light[:3, 3]


def texels_per_pixel(scene: Scene, shadows: tuple[LightShadow, ...], size: int) -> float:
    """The widest texel of `size`-texel maps, in pixels of the image, on the visible
    receivers inside the views' windows (0 where no view covers one)."""
    width, height = scene.size
    eye_from_world = scene.camera.eye_from_world()
    projection = clip_from_eye(scene.camera, width / height)
    clip_from_world = projection @ eye_from_world
    frustum = camera_frustum(scene)
    boxes = [world_box(scene.objects[index]) for index in visible_receivers(scene)]
    widest = 0.0
    for view in (view for shadow in shadows for view in shadow.views if view is not None):
        corners = np.concatenate(boxes) @ view.light_from_world[:3, :3].T + view.light_from_world[:3, 3]
        far = view.far if view.orthographic else float((-corners[:, 2]).max())
        if not far > view.near:
            continue
        solid = _window_solid(view, far)
        for box in boxes:
            points = common_points(box, frustum, solid)
            if not len(points):
                continue
            w = np.abs(points @ clip_from_world[3, :3] + clip_from_world[3, 3])
            pixel = 2.0 * w / (projection[1, 1] * height)
            texel = view.texel_size(size)
            if not view.orthographic:
                texel = texel * -(points @ view.light_from_world[2, :3] + view.light_from_world[2, 3])
            widest = max(widest, float((texel / np.maximum(pixel, 1e-300)).max()))
    return widest


def auto_map_size(scene: Scene, shadows: tuple[LightShadow, ...]) -> int:
    """AUTO_MAP_SIZE doubled until its texels are no wider than 1/AUTO_TEXELS_PER_PIXEL of a
    pixel (`shadows`: the views fitted for AUTO_MAP_SIZE), at most AUTO_MAP_SIZE_LIMIT."""
    ratio = texels_per_pixel(scene, shadows, AUTO_MAP_SIZE) * AUTO_TEXELS_PER_PIXEL
    if not ratio > 1.0:
        return AUTO_MAP_SIZE
    doublings = math.ceil(math.log2(ratio) - 1e-9)
    return int(min(AUTO_MAP_SIZE << max(doublings, 0), AUTO_MAP_SIZE_LIMIT))
