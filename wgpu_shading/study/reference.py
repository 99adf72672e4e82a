"""The independent float64 reference renderer (numpy only).

`docs/conventions.md` defines exactly what wgpu-shading draws. The GPU implements it in
WGSL and float32; this module implements it a second time, in float64, from the document
rather than from the shaders, so that a disagreement between the two points at a bug in
one of them. It must not import wgpu or any GPU module of the package: the scene
dataclasses (`scene.py`, `meshes.py`) are only the description of what to draw.

Public API:

    shade(points, normals, to_viewer, scene, material) -> (ambient_diffuse, specular)
    view_vectors(points, normals, local_viewer) -> to_viewer
    combine(ambient_diffuse, specular, material, texel) -> rgba (clamped)
    sample_texture_bilinear(pixels, uv) -> rgba in [0, 1]
    render_reference(scene) -> ReferenceImage        the same meshes, rasterized in float64
    render_analytic_sphere(scene, center, radius, material) -> ReferenceImage
    render_analytic_rectangle(scene, center, half_u, half_v, material) -> ReferenceImage
    sphere_in_world(obj, radius) -> (center, radius) of a sphere mesh placed by a SceneObject

The rasterizer follows Vulkan's rules as lavapipe implements them: pixel centres, window
coordinates snapped to 1/256 pixel (done here in exact int64 arithmetic, so ties on an
edge are decided exactly by the top-left rule), nearest surface wins, perspective-correct
barycentrics. It is vectorized over (triangle, candidate pixel) pairs, so a mesh with a
million triangles renders in seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import SceneError
from ..scene import Camera, DirectionalLight, Material, PositionalLight, Scene, SceneObject, Shading, SpotLight

# --------------------------------------------------------------------------- constants from conventions.md

MIN_LENGTH_SQUARED = 1e-30  # |v|² at or below this is "zero length": normalize falls back
MIN_ATTENUATION_DENOMINATOR = 1e-20  # kc + kl·d + kq·d² is floored here
FALLBACK_NORMAL = np.array([0.0, 0.0, 1.0])  # eye space: faces the viewer
INFINITE_VIEWER = np.array([0.0, 0.0, 1.0])  # V when local_viewer is false

SUBPIXEL = 256  # lavapipe snaps window coordinates to 1/256 pixel
# Triangles reaching further than this many pixels outside the image are clipped in eye
# space first, so snapped coordinates stay small enough for exact int64 edge functions.
GUARD_BAND_PIXELS = 1 << 20
# How many (triangle, candidate pixel) pairs are tested at once: bounds peak memory.
CANDIDATE_CHUNK = 1 << 21


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
    """

    color: np.ndarray
    covered: np.ndarray
    triangle: np.ndarray
    object: np.ndarray
    depth: np.ndarray
    edge_margin: np.ndarray
    texel_footprint: np.ndarray


# --------------------------------------------------------------------------- guarded math


def guarded_power(base: np.ndarray, exponent: float | np.ndarray) -> np.ndarray:
    """max(base, 0)^exponent with the conventions' limits: base <= 0 gives 0 for every
    exponent (0^0 too); otherwise exponent <= 0 gives 1; otherwise min(base, 1)^exponent.
    Continuous in the exponent at 0, so float32 rounding a tiny exponent to 0 changes nothing."""
    base = np.asarray(base, dtype=np.float64)
    exponent = np.broadcast_to(np.asarray(exponent, dtype=np.float64), base.shape)
    positive_base = np.where(base > 0.0, np.minimum(base, 1.0), 1.0)  # 1.0: any safe value
    power = np.where(exponent <= 0.0, 1.0, positive_base**exponent)
    return np.where(base > 0.0, power, 0.0)


def safe_normalize(vectors: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """Rows of `vectors` scaled to unit length; rows with |v|² <= 1e-30 become `fallback`
    (one vector for all rows, or one per row)."""
    vectors = np.asarray(vectors, dtype=np.float64)
    length_squared = np.einsum("ij,ij->i", vectors, vectors)
    usable = length_squared > MIN_LENGTH_SQUARED
    scale = 1.0 / np.sqrt(np.where(usable, length_squared, 1.0))
    return np.where(usable[:, None], vectors * scale[:, None], np.broadcast_to(fallback, vectors.shape))


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot product of (N, 3) arrays (either may broadcast from (3,))."""
    return np.sum(a * b, axis=-1)


# --------------------------------------------------------------------------- transforms


def view_matrix(camera: Camera) -> np.ndarray:
    """gluLookAt, derived here from eye/target/up: rows are the eye-space axes in world space."""
    eye = np.asarray(camera.eye, dtype=np.float64)
    forward = np.asarray(camera.target, dtype=np.float64) - eye
    forward /= np.linalg.norm(forward)
    side = np.cross(forward, np.asarray(camera.up, dtype=np.float64))
    side /= np.linalg.norm(side)
    up = np.cross(side, forward)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = side, up, -forward  # the camera looks down -Z
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def model_matrix(obj: SceneObject) -> np.ndarray:
    """T · Rz · Ry · Rx · S · translate(mesh.origin): the matrix for the mesh's stored
    (origin-relative) positions, derived here from the conventions."""
    ax, ay, az = np.radians(np.asarray(obj.rotate, dtype=np.float64))
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    linear = rz @ ry @ rx @ np.diag(np.asarray(obj.scale, dtype=np.float64))
    model = np.eye(4)
    model[:3, :3] = linear
    model[:3, 3] = np.asarray(obj.translate, dtype=np.float64) + linear @ np.asarray(obj.mesh.origin, dtype=np.float64)
    return model


def normal_matrix(model_view: np.ndarray) -> np.ndarray:
    """Inverse transpose of the upper 3×3: normals stay perpendicular under non-uniform scale."""
    return np.linalg.inv(model_view[:3, :3]).T


def _transform_points(matrix: np.ndarray, points: np.ndarray) -> np.ndarray:
    return points @ matrix[:3, :3].T + matrix[:3, 3]


def sphere_in_world(obj: SceneObject, radius: float = 1.0) -> tuple[np.ndarray, float]:
    """World centre and radius of a sphere mesh of `radius` centred on its model origin
    (meshes.uv_sphere), placed by `obj`, whose scale must be uniform."""
    scale = np.abs(np.asarray(obj.scale, dtype=np.float64))
    if not np.allclose(scale, scale[0], rtol=1e-12, atol=0.0):
        raise ValueError(f"an analytic sphere needs a uniform scale, got {obj.scale}")
    model = model_matrix(obj)
    # The model-space centre (0, 0, 0) is stored as -origin.
    center = _transform_points(model, -np.asarray(obj.mesh.origin, dtype=np.float64)[None])[0]
    return center, float(radius * scale[0])


# --------------------------------------------------------------------------- lights


@dataclass(frozen=True)
class EyeLight:
    """One light in eye space, ready for the lighting equation."""

    kind: str  # directional | positional | spot
    ambient: np.ndarray  # RGB
    diffuse: np.ndarray
    specular: np.ndarray
    to_light: np.ndarray | None = None  # directional: unit vector towards the light
    position: np.ndarray | None = None  # positional, spot
    attenuation: tuple[float, float, float] = (1.0, 0.0, 0.0)
    axis: np.ndarray | None = None  # spot: unit direction the light travels
    cutoff_chord_squared: float = 0.0  # spot: 4·sin²(cutoff/2)
    exponent: float = 0.0  # spot


def lights_in_eye_space(scene: Scene) -> list[EyeLight]:
    """World → eye space once per frame: positions with the full view matrix, directions
    with its rotation only."""
    view = view_matrix(scene.camera)
    rotation = view[:3, :3]
    lights = []
    for light in scene.lights:
        colors = {key: np.asarray(getattr(light, key)[:3], dtype=np.float64) for key in ("ambient", "diffuse", "specular")}
        if isinstance(light, DirectionalLight):
            towards = rotation @ -np.asarray(light.direction, dtype=np.float64)  # light travels along direction
            lights.append(EyeLight("directional", to_light=towards / np.linalg.norm(towards), **colors))
            continue
        position = _transform_points(view, np.asarray(light.position, dtype=np.float64)[None])[0]
        attenuation = tuple(float(c) for c in light.attenuation)
        if isinstance(light, SpotLight):
            axis = rotation @ np.asarray(light.direction, dtype=np.float64)
            lights.append(
                EyeLight(
                    "spot",
                    position=position,
                    attenuation=attenuation,
                    axis=axis / np.linalg.norm(axis),
                    cutoff_chord_squared=4.0 * math.sin(math.radians(light.cutoff) / 2.0) ** 2,
                    exponent=float(light.exponent),
                    **colors,
                )
            )
        elif isinstance(light, PositionalLight):
            lights.append(EyeLight("positional", position=position, attenuation=attenuation, **colors))
    return lights


def attenuation_factor(coefficients: tuple[float, float, float], distance: np.ndarray) -> np.ndarray:
    """1 / max(kc + kl·d + kq·d², 1e-20): finite even for a light at the point with kc = 0."""
    kc, kl, kq = coefficients
    return 1.0 / np.maximum(kc + kl * distance + kq * distance**2, MIN_ATTENUATION_DENOMINATOR)


# --------------------------------------------------------------------------- the lighting equation


def view_vectors(points: np.ndarray, normals: np.ndarray, local_viewer: bool) -> np.ndarray:
    """V: towards the eye at the origin (local viewer; N when the eye is at the point), or
    the constant (0, 0, 1) of OpenGL's infinite viewer."""
    if local_viewer:
        return safe_normalize(-np.asarray(points, dtype=np.float64), normals)
    return np.broadcast_to(INFINITE_VIEWER, np.shape(points)).copy()


def specular_factor(normals, to_light, to_viewer, shininess: float, reflection: str, k_blinn: float) -> np.ndarray:
    """(R·V)^s for Phong reflection, (N·H)^(s·k_blinn) for Blinn-Phong, guarded."""
    if reflection == "phong":
        reflected = 2.0 * _dot(normals, to_light)[:, None] * normals - to_light  # reflect(-L, N)
        return guarded_power(_dot(reflected, to_viewer), shininess)
    # L = -V has no half vector: H = 0 makes N·H = 0, so no highlight.
    half = safe_normalize(to_light + to_viewer, np.zeros(3))
    return guarded_power(_dot(normals, half), shininess * k_blinn)


def shade(
    points: np.ndarray, normals: np.ndarray, to_viewer: np.ndarray, scene: Scene, material: Material
) -> tuple[np.ndarray, np.ndarray]:
    """SPEC §3 at N eye-space points with unit normals and unit view vectors, all (N, 3).

    Returns the ambient+diffuse+emission part and the specular part, (N, 3) each, unclamped
    (textures treat them apart; the clamp comes last, in `combine`).
    """
    points = np.asarray(points, dtype=np.float64)
    normals = np.asarray(normals, dtype=np.float64)
    to_viewer = np.asarray(to_viewer, dtype=np.float64)
    count = len(points)
    m_ambient, m_diffuse, m_specular, m_emission = (
        np.asarray(c[:3], dtype=np.float64) for c in (material.ambient, material.diffuse, material.specular, material.emission)
    )
    ambient_diffuse = np.tile(m_emission + np.asarray(scene.ambient[:3]) * m_ambient, (count, 1))
    specular = np.zeros((count, 3))
    shading = scene.shading
    for light in lights_in_eye_space(scene):
        if light.kind == "directional":
            to_light = np.broadcast_to(light.to_light, points.shape)
            scale = np.ones(count)
        else:
            offset = light.position - points
            # A light exactly at the point has no direction: light it as if from straight above.
            to_light = safe_normalize(offset, normals)
            scale = attenuation_factor(light.attenuation, np.sqrt(_dot(offset, offset)))
            if light.kind == "spot":
                # Open cone, tested as a squared chord between -L and the axis (exact for tiny cutoffs).
                chord = -to_light - light.axis
                inside = _dot(chord, chord) < light.cutoff_chord_squared
                spot = guarded_power(_dot(-to_light, light.axis), light.exponent)
                scale = scale * np.where(inside, spot, 0.0)
        n_dot_l = _dot(normals, to_light)
        ambient_diffuse += scale[:, None] * (
            light.ambient * m_ambient + np.maximum(n_dot_l, 0.0)[:, None] * light.diffuse * m_diffuse
        )
        highlight = specular_factor(
            normals, to_light, to_viewer, material.shininess, shading.reflection, shading.blinn_exponent_scale
        )
        lit_side = n_dot_l > 0.0  # f_i: no highlight where the light does not reach
        specular += np.where(lit_side, scale * highlight, 0.0)[:, None] * light.specular * m_specular
    return ambient_diffuse, specular


def combine(
    ambient_diffuse: np.ndarray, specular: np.ndarray, material: Material, texel: np.ndarray | None = None
) -> np.ndarray:
    """Texture combine (SPEC §5) and the final clamp: (N, 4) RGBA.

    `texel` is the sampled RGBA in [0, 1] (N, 4), or None for an untextured material; the
    mode is material.texture_mode. Alpha is the material's diffuse alpha (× texel alpha).
    """
    alpha = np.full(len(ambient_diffuse), float(material.diffuse[3]))
    if texel is None:
        rgb = ambient_diffuse + specular
    else:
        texel_rgb = texel[:, :3]
        mode = material.texture_mode
        if mode == "modulate":
            rgb = texel_rgb * ambient_diffuse + specular
        elif mode == "modulate_all":
            rgb = texel_rgb * (ambient_diffuse + specular)
        elif mode == "blend":
            rgb = 0.5 * texel_rgb + 0.5 * (ambient_diffuse + specular)
        else:
            raise ValueError(f"unknown texture mode {mode!r}")
        alpha = alpha * texel[:, 3]
    return np.concatenate([np.clip(rgb, 0.0, 1.0), alpha[:, None]], axis=1)


# --------------------------------------------------------------------------- textures


def sample_texture_bilinear(pixels: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Bilinear sample of level 0 with repeat wrap: (N, 4) RGBA in [0, 1].

    `pixels` is an (H, W, 4) uint8 image with row 0 at the top; v = 0 is the bottom row;
    texel (i, j) (j counted from the bottom) has its centre at ((i + 0.5)/W, (j + 0.5)/H).
    """
    image = np.asarray(pixels, dtype=np.float64) / 255.0
    height, width = image.shape[:2]
    uv = np.asarray(uv, dtype=np.float64)
    # Continuous texel coordinates whose integer values are texel centres.
    x = uv[:, 0] * width - 0.5
    y = uv[:, 1] * height - 0.5  # counted from the bottom row
    i0, j0 = np.floor(x), np.floor(y)
    fx, fy = (x - i0)[:, None], (y - j0)[:, None]
    i0, j0 = i0.astype(np.int64), j0.astype(np.int64)
    columns = (np.mod(i0, width), np.mod(i0 + 1, width))
    rows = (height - 1 - np.mod(j0, height), height - 1 - np.mod(j0 + 1, height))  # bottom-up → top-down
    bottom = (1 - fx) * image[rows[0], columns[0]] + fx * image[rows[0], columns[1]]
    top = (1 - fx) * image[rows[1], columns[0]] + fx * image[rows[1], columns[1]]
    return (1 - fy) * bottom + fy * top


# --------------------------------------------------------------------------- pixels and rays


def pixel_rays(camera: Camera, size: tuple[int, int]) -> np.ndarray:
    """(H, W, 3) eye-space directions through the pixel centres, z = -1."""
    if camera.orthographic:  # every path of the reference starts from these rays
        raise SceneError(
            "the float64 reference renders perspective cameras only; camera.projection is 'orthographic'"
        )
    width, height = size
    tan_half = math.tan(math.radians(camera.fov_y) / 2.0)
    aspect = width / height
    x = 2.0 * (np.arange(width) + 0.5) / width - 1.0
    y = 1.0 - 2.0 * (np.arange(height) + 0.5) / height
    rays = np.empty((height, width, 3))
    rays[:, :, 0] = x[None, :] * tan_half * aspect
    rays[:, :, 1] = y[:, None] * tan_half
    rays[:, :, 2] = -1.0
    return rays


def _window_coordinates(eye_points: np.ndarray, camera: Camera, size: tuple[int, int]) -> np.ndarray:
    """Eye space → window coordinates (x right, y down, in pixels); needs depth > 0."""
    width, height = size
    tan_half = math.tan(math.radians(camera.fov_y) / 2.0)
    depth = -eye_points[..., 2]
    x_ndc = eye_points[..., 0] / (depth * tan_half * (width / height))
    y_ndc = eye_points[..., 1] / (depth * tan_half)
    return np.stack([(x_ndc + 1.0) * width / 2.0, (1.0 - y_ndc) * height / 2.0], axis=-1)


# --------------------------------------------------------------------------- clipping


def _clip_planes(camera: Camera, size: tuple[int, int]) -> list[tuple[np.ndarray, float]]:
    """Eye-space half-spaces n·p + d >= 0: the near plane and the guard band's four sides."""
    width, height = size
    tan_half = math.tan(math.radians(camera.fov_y) / 2.0)
    # |x_ndc| <= gx keeps window x within GUARD_BAND_PIXELS of the image; same for y.
    gx = 1.0 + 2.0 * GUARD_BAND_PIXELS / width
    gy = 1.0 + 2.0 * GUARD_BAND_PIXELS / height
    sx = tan_half * width / height
    sy = tan_half
    return [
        (np.array([0.0, 0.0, -1.0]), -camera.near),  # depth >= near
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
class _ScreenTriangles:
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


def _screen_triangles(eye_corners: np.ndarray, source: np.ndarray, camera: Camera, size: tuple[int, int]) -> _ScreenTriangles:
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
    window = _window_coordinates(eye, camera, size)
    fixed = np.rint(window * SUBPIXEL).astype(np.int64)  # round half to even, like lrint
    return _ScreenTriangles(fixed=fixed, window=window, depth=-eye[..., 2], source=np.concatenate(sources))


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


def _signed_area_fixed(fixed: np.ndarray) -> np.ndarray:
    """Twice the signed area in snapped window coordinates (y down). The y flip reverses the
    sign: < 0 is counter-clockwise in NDC (y up), i.e. counter-clockwise as seen in the image."""
    e1 = fixed[:, 1] - fixed[:, 0]
    e2 = fixed[:, 2] - fixed[:, 0]
    return e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]


def _inverse_depth_planes(window: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """Per triangle (a, b, c) with 1/depth = a·x + b·y + c in window coordinates: 1/w is
    affine in screen space, which is what makes perspective-correct interpolation work."""
    p0, p1, p2 = window[:, 0], window[:, 1], window[:, 2]
    inverse = 1.0 / depth
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
class _Visibility:
    """Per pixel (flattened row-major): nearest depth and the screen triangle that has it."""

    depth: np.ndarray
    triangle: np.ndarray  # index into _ScreenTriangles, -1 where uncovered


def _rasterize(tris: _ScreenTriangles, size: tuple[int, int], near: float, far: float) -> _Visibility:
    """Coverage (pixel centres, top-left rule, exact integer edge functions) and a z-buffer on
    eye depth. Ties in depth go to the earlier triangle, as the `greater` depth test does."""
    width, height = size
    best_depth = np.full(width * height, np.inf)
    best_triangle = np.full(width * height, -1, dtype=np.int64)

    fixed = tris.fixed.copy()
    area = _signed_area_fixed(fixed)
    negative = area < 0
    fixed[negative] = fixed[negative][:, [0, 2, 1]]  # wind every triangle so its area is > 0
    col0, col1, row0, row1 = _candidate_boxes(fixed, size)
    keep = (area != 0) & (col0 <= col1) & (row0 <= row1)
    ids = np.flatnonzero(keep)
    if len(ids) == 0:
        return _Visibility(best_depth, best_triangle)
    edge_a, edge_b, edge_c = (e[ids] for e in _edge_coefficients(fixed))
    planes = _inverse_depth_planes(tris.window, tris.depth)[ids]
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
        inverse_depth = planes[tri, 0] * x + planes[tri, 1] * y + planes[tri, 2]
        with np.errstate(divide="ignore"):
            depth = np.where(inverse_depth > 0.0, 1.0 / np.where(inverse_depth > 0.0, inverse_depth, 1.0), np.inf)
        in_range = (depth >= near * (1.0 - 1e-12)) & (depth <= far)  # clip to [near, far]
        tri, depth = tri[in_range], depth[in_range]
        pixel = row[in_range] * width + col[in_range]
        _merge_nearest(best_depth, best_triangle, pixel, depth, ids[tri])
    return _Visibility(best_depth, best_triangle)


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


def _edge_margins(fixed: np.ndarray, columns: np.ndarray, rows: np.ndarray) -> np.ndarray:
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


# --------------------------------------------------------------------------- the same-mesh reference


@dataclass
class _PreparedObject:
    """One object's geometry in eye space."""

    model_view: np.ndarray
    normal_matrix: np.ndarray
    mirrored: bool
    eye_positions: np.ndarray  # (V, 3)
    eye_normals: np.ndarray  # (V, 3) normal matrix · vertex normal, unnormalized
    model_positions: np.ndarray  # (V, 3) stored (origin-relative) positions, float64
    faces: np.ndarray  # (F, 3) int64


def _prepare(scene: Scene, obj: SceneObject) -> _PreparedObject:
    model_view = view_matrix(scene.camera) @ model_matrix(obj)
    normals_to_eye = normal_matrix(model_view)
    model_positions = obj.mesh.positions.astype(np.float64)
    return _PreparedObject(
        model_view=model_view,
        normal_matrix=normals_to_eye,
        # A mirrored transform flips the screen winding of outward-facing triangles.
        mirrored=bool(np.linalg.det(model_view[:3, :3]) < 0.0),
        eye_positions=_transform_points(model_view, model_positions),
        eye_normals=obj.mesh.normals.astype(np.float64) @ normals_to_eye.T,
        model_positions=model_positions,
        faces=obj.mesh.indices.astype(np.int64),
    )


def _ray_barycentrics(corners: np.ndarray, rays: np.ndarray) -> np.ndarray:
    """Perspective-correct barycentrics: where each eye ray meets its triangle's plane,
    expressed in the triangle's (N, 3, 3) eye-space corners. Exact for clipped triangles too."""
    p0, p1, p2 = corners[:, 0], corners[:, 1], corners[:, 2]
    normal = np.cross(p1 - p0, p2 - p0)
    along = _dot(normal, rays)
    safe_along = np.where(along != 0.0, along, 1.0)
    point = rays * (_dot(normal, p0) / safe_along)[:, None]
    twice_area = _dot(normal, normal)
    safe_area = np.where(twice_area > 0.0, twice_area, 1.0)
    b0 = _dot(normal, np.cross(p2 - p1, point - p1)) / safe_area
    b1 = _dot(normal, np.cross(p0 - p2, point - p2)) / safe_area
    weights = np.stack([b0, b1, 1.0 - b0 - b1], axis=1)
    degenerate = (along == 0.0) | (twice_area <= 0.0)  # cannot cover a pixel; guard anyway
    return np.where(degenerate[:, None], 1.0 / 3.0, weights)


def _texel_footprint(obj: SceneObject, prepared: _PreparedObject, faces: np.ndarray, pixels: np.ndarray, scene: Scene) -> np.ndarray:
    """Texels per pixel step at each pixel: how far (u·W, v·H) moves when the ray moves to a
    neighbouring pixel centre, staying on the same triangle's plane (as the GPU's quad
    derivatives do, helper pixels included)."""
    height, width = obj.material.texture.pixels.shape[:2]
    texture_scale = np.array([width, height], dtype=np.float64)
    corners = prepared.eye_positions[faces]
    uvs = obj.mesh.uvs.astype(np.float64)[faces] * texture_scale
    image_width, image_height = scene.size
    rows, columns = np.divmod(pixels, image_width)
    tan_half = math.tan(math.radians(scene.camera.fov_y) / 2.0)

    def texel_position(column_offset, row_offset):
        x = 2.0 * (columns + 0.5 + column_offset) / image_width - 1.0
        y = 1.0 - 2.0 * (rows + 0.5 + row_offset) / image_height
        rays = np.stack([x * tan_half * image_width / image_height, y * tan_half, -np.ones_like(x)], axis=1)
        return np.einsum("nk,nkc->nc", _ray_barycentrics(corners, rays), uvs)

    centre = texel_position(0, 0)
    steps = [texel_position(dx, dy) - centre for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))]
    return np.max([np.linalg.norm(step, axis=1) for step in steps], axis=0)


def _shade_pixels(
    scene: Scene,
    obj: SceneObject,
    prepared: _PreparedObject,
    triangles: np.ndarray,
    weights: np.ndarray,
    front_facing: np.ndarray,
) -> np.ndarray:
    """RGBA of the pixels where `obj` is visible: triangle index, barycentrics (N, 3) and facing."""
    shading = scene.shading
    material = obj.material
    faces = prepared.faces[triangles]
    back = shading.two_sided & ~front_facing  # back faces are lit with -N only when two-sided
    flip = np.where(back, -1.0, 1.0)[:, None]

    def shade_with(points, normals):
        return shade(points, normals, view_vectors(points, normals, shading.local_viewer), scene, material)

    if shading.frequency == "flat":
        # One evaluation per triangle: face normal from the stored positions, at the centroid.
        p = prepared.model_positions[faces]
        face_normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) @ prepared.normal_matrix.T
        normals = safe_normalize(face_normal, FALLBACK_NORMAL) * flip
        centroids = prepared.eye_positions[faces].mean(axis=1)
        ambient_diffuse, specular = shade_with(centroids, normals)
    elif shading.frequency == "gouraud":
        # Light each vertex (front with N, back with -N), then interpolate both parts unclamped.
        vertex_normals = safe_normalize(prepared.eye_normals, FALLBACK_NORMAL)
        used = np.unique(faces)
        front = shade_with(prepared.eye_positions[used], vertex_normals[used])
        back_parts = shade_with(prepared.eye_positions[used], -vertex_normals[used]) if shading.two_sided else front
        slot = np.searchsorted(used, faces)  # (N, 3) rows of `used`
        parts = []
        for k in range(2):
            chosen = np.where(back[:, None, None], back_parts[k][slot], front[k][slot])
            parts.append(np.einsum("nk,nkc->nc", weights, chosen))
        ambient_diffuse, specular = parts
    else:  # phong
        normals = safe_normalize(np.einsum("nk,nkc->nc", weights, prepared.eye_normals[faces]), FALLBACK_NORMAL) * flip
        points = np.einsum("nk,nkc->nc", weights, prepared.eye_positions[faces])
        ambient_diffuse, specular = shade_with(points, normals)

    texel = None
    if material.texture is not None:
        if obj.mesh.uvs is None:
            raise ValueError(f"material {material.name!r} has a texture but mesh {obj.mesh.name!r} has no UVs")
        uv = np.einsum("nk,nkc->nc", weights, obj.mesh.uvs.astype(np.float64)[faces])
        texel = sample_texture_bilinear(material.texture.pixels, uv)
    return combine(ambient_diffuse, specular, material, texel)


class RasterizedScene:
    """The scene's meshes rasterized once in float64: which triangle (and object) covers each
    pixel, its perspective-correct barycentrics and its facing. Shading is a separate step
    (`shade`), so one rasterization — most of the reference's cost on large meshes — serves
    any number of shading settings (the accuracy study renders 12 per mesh)."""

    def __init__(self, scene: Scene):
        self.scene = scene
        width, height = scene.size
        camera = scene.camera
        self._prepared = [_prepare(scene, obj) for obj in scene.objects]

        # Every object's triangles in one list, in draw order (objects, then faces).
        face_counts = np.array([len(p.faces) for p in self._prepared], dtype=np.int64)
        first_face = np.concatenate([[0], np.cumsum(face_counts)])
        if self._prepared:
            eye_corners = np.concatenate([p.eye_positions[p.faces] for p in self._prepared])
        else:
            eye_corners = np.zeros((0, 3, 3))
        tris = _screen_triangles(eye_corners, np.arange(len(eye_corners)), camera, scene.size)
        visibility = _rasterize(tris, scene.size, camera.near, camera.far)

        covered_flat = visibility.triangle >= 0
        pixels = np.flatnonzero(covered_flat)
        screen_triangle = visibility.triangle[pixels]
        source = tris.source[screen_triangle]
        self._pixels = pixels
        self._object_index = np.searchsorted(first_face, source, side="right") - 1
        self._local_triangle = source - first_face[self._object_index]
        rows, columns = np.divmod(pixels, width)

        # Facing from the winding on screen: counter-clockwise in NDC is front, flipped for mirrored objects.
        ccw_in_ndc = _signed_area_fixed(tris.fixed[screen_triangle]) < 0
        mirrored = np.array([p.mirrored for p in self._prepared], dtype=bool)
        self._front_facing = ccw_in_ndc != mirrored[self._object_index]

        rays = pixel_rays(camera, scene.size).reshape(-1, 3)[pixels]
        self._weights = _ray_barycentrics(eye_corners[source], rays)

        self.covered = covered_flat.reshape(height, width)
        self.triangle = self._image(self._local_triangle, -1, np.int64)
        self.object = self._image(self._object_index, -1, np.int64)
        self.depth = visibility.depth.reshape(height, width)
        self.edge_margin = self._image(_edge_margins(tris.fixed[screen_triangle], columns, rows), np.inf, np.float64)

    def _image(self, values: np.ndarray, fill, dtype) -> np.ndarray:
        width, height = self.scene.size
        result = np.full(height * width, fill, dtype=dtype)
        result[self._pixels] = values
        return result.reshape(height, width)

    def shade(self, shading: Shading | None = None) -> np.ndarray:
        """(H, W, 4) float64 color with the scene's shading, or with `shading` instead."""
        scene = self.scene if shading is None else replace(self.scene, shading=shading)
        width, height = scene.size
        color = np.broadcast_to(np.asarray(scene.background, dtype=np.float64), (height * width, 4)).copy()
        for index, (obj, geometry) in enumerate(zip(scene.objects, self._prepared)):
            mine = self._object_index == index
            if mine.any():
                color[self._pixels[mine]] = _shade_pixels(
                    scene, obj, geometry, self._local_triangle[mine], self._weights[mine], self._front_facing[mine]
                )
        return color.reshape(height, width, 4)

    def texel_footprint(self) -> np.ndarray:
        """Texels per pixel step of each textured pixel (0 elsewhere): < 1 means magnified."""
        width, height = self.scene.size
        footprint = np.zeros(height * width)
        for index, (obj, geometry) in enumerate(zip(self.scene.objects, self._prepared)):
            mine = self._object_index == index
            if mine.any() and obj.material.texture is not None:
                faces = geometry.faces[self._local_triangle[mine]]
                footprint[self._pixels[mine]] = _texel_footprint(obj, geometry, faces, self._pixels[mine], self.scene)
        return footprint.reshape(height, width)


def render_reference(scene: Scene) -> ReferenceImage:
    """Rasterize and shade the scene's own meshes in float64 (see the module docstring)."""
    rasterized = RasterizedScene(scene)
    return ReferenceImage(
        color=rasterized.shade(),
        covered=rasterized.covered,
        triangle=rasterized.triangle,
        object=rasterized.object,
        depth=rasterized.depth,
        edge_margin=rasterized.edge_margin,
        texel_footprint=rasterized.texel_footprint(),
    )


# --------------------------------------------------------------------------- analytic ground truth


def _analytic_image(
    scene: Scene,
    hit: np.ndarray,
    points: np.ndarray,
    normals: np.ndarray,
    margins: np.ndarray,
    material: Material,
) -> ReferenceImage:
    """Shade analytic hits (flattened pixel mask, eye points, outward unit normals) per pixel,
    as Phong shading converges to when the tessellation is refined."""
    width, height = scene.size
    shading = scene.shading
    if material.texture is not None:
        raise ValueError("analytic shapes take untextured materials")
    depth = -points[:, 2]
    # A surface seen from behind is back-facing; two-sided lighting then uses -N.
    facing_viewer = _dot(normals, -points) > 0.0
    if shading.two_sided:
        normals = np.where(facing_viewer[:, None], normals, -normals)
    ambient_diffuse, specular = shade(
        points, normals, view_vectors(points, normals, shading.local_viewer), scene, material
    )
    color = np.broadcast_to(np.asarray(scene.background, dtype=np.float64), (height * width, 4)).copy()
    color[hit] = combine(ambient_diffuse, specular, material)

    def image(values, fill, dtype):
        result = np.full(height * width, fill, dtype=dtype)
        result[hit] = values
        return result.reshape(height, width)

    return ReferenceImage(
        color=color.reshape(height, width, 4),
        covered=hit.reshape(height, width),
        triangle=image(-1, -1, np.int64),
        object=image(0, -1, np.int64),
        depth=image(depth, np.inf, np.float64),
        edge_margin=image(margins, np.inf, np.float64),
        texel_footprint=np.zeros((height, width)),
    )


def render_analytic_sphere(scene: Scene, center, radius: float, material: Material) -> ReferenceImage:
    """Ray-cast an exact sphere (world-space centre and radius) through every pixel centre,
    with the exact normal; the nearest intersection in [near, far] is shaded.

    edge_margin is the angle between the pixel's ray and the silhouette cone, in pixels (as
    at the image centre), so tests can leave the rim out."""
    camera = scene.camera
    view = view_matrix(camera)
    c = _transform_points(view, np.asarray(center, dtype=np.float64)[None])[0]
    rays = pixel_rays(camera, scene.size).reshape(-1, 3)
    # |t·d − c|² = r²  →  (d·d) t² − 2 (d·c) t + (c·c − r²) = 0
    a = _dot(rays, rays)
    b = rays @ c
    discriminant = b * b - a * (c @ c - radius * radius)
    root = np.sqrt(np.maximum(discriminant, 0.0))
    # The rays have z = −1, so the parameter t of a hit t·d is also its eye depth.
    near_t, far_t = (b - root) / a, (b + root) / a
    use_near = (near_t >= camera.near) & (near_t <= camera.far)
    t = np.where(use_near, near_t, far_t)
    hit = (discriminant > 0.0) & (t >= camera.near) & (t <= camera.far)
    points = rays[hit] * t[hit, None]
    normals = (points - c) / radius
    # Angle between the ray and the silhouette cone, converted to pixels on the image plane.
    distance_to_center = np.linalg.norm(c)
    ray_unit = rays[hit] / np.sqrt(a[hit])[:, None]
    angle_to_center = np.arccos(np.clip(ray_unit @ c / distance_to_center, -1.0, 1.0))
    silhouette_angle = math.asin(min(radius / distance_to_center, 1.0))
    pixels_per_radian = scene.size[1] / (2.0 * math.tan(math.radians(camera.fov_y) / 2.0))
    margins = (silhouette_angle - angle_to_center) * pixels_per_radian
    return _analytic_image(scene, hit, points, normals, margins, material)


def render_analytic_rectangle(scene: Scene, center, half_u, half_v, material: Material) -> ReferenceImage:
    """Ray-cast the rectangle {center + s·half_u + t·half_v : |s|, |t| <= 1} (world space,
    half_u ⟂ half_v) with normal normalize(half_u × half_v), shaded per pixel."""
    camera = scene.camera
    view = view_matrix(camera)
    c = _transform_points(view, np.asarray(center, dtype=np.float64)[None])[0]
    u = view[:3, :3] @ np.asarray(half_u, dtype=np.float64)
    v = view[:3, :3] @ np.asarray(half_v, dtype=np.float64)
    normal = np.cross(u, v)
    normal /= np.linalg.norm(normal)
    rays = pixel_rays(camera, scene.size).reshape(-1, 3)
    along = rays @ normal
    t = np.where(along != 0.0, (c @ normal) / np.where(along != 0.0, along, 1.0), -1.0)
    points = rays * t[:, None]
    s = (points - c) @ u / (u @ u)
    r = (points - c) @ v / (v @ v)
    hit = (along != 0.0) & (t >= camera.near) & (t <= camera.far) & (np.abs(s) <= 1.0) & (np.abs(r) <= 1.0)
    # Margin: distance to the rectangle's border measured on the image plane (pixels), by
    # scaling the in-plane distance with the local magnification (focal / depth).
    focal_pixels = scene.size[1] / (2.0 * math.tan(math.radians(camera.fov_y) / 2.0))
    in_plane = np.minimum((1.0 - np.abs(s[hit])) * np.linalg.norm(u), (1.0 - np.abs(r[hit])) * np.linalg.norm(v))
    margins = in_plane * focal_pixels / t[hit]
    return _analytic_image(scene, hit, points[hit], np.broadcast_to(normal, (int(hit.sum()), 3)), margins, material)
