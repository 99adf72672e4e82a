"""Where each casting light's shadow maps look (docs/shadows.md#shadow-maps), in float64.

A map only answers for the receivers the camera sees (visible_regions.py), and of those only
for the ones some caster can shadow: a receiver point outside every caster's silhouette as
the light sees it is lit, so each view's window is where a caster's silhouette overlaps a
visible receiver lying behind it (casters outside the view included; a flat object does
not shadow itself). Points outside the window read V = 1 (wgsl/chunks/shadows/lookup.wgsl).

- a directional light: one orthographic view, rotated to the smallest rectangle around
  those casters, its depth range from the nearest such caster to the farthest receiver;
- a spot light: one perspective view from the light, the window inside its cone; a window
  reaching beyond MAX_SINGLE_VIEW_TAN from the axis is a cube map instead;
- a positional light: one perspective view aimed at the visible receivers when all it can
  shadow lies within MAX_SINGLE_VIEW_TAN of that direction (a light far from the scene); else
  a cube map, six views along the world axes, each widened by a guard
  band of `margin` texels so that a filter near a face's edge reads texels of that face (no
  seams); a face whose pyramid holds no visible receiver a caster can shadow is skipped, and
  the faces share one window, the union of what each needs (a far light's cube spends its
  texels on the few degrees the scene takes up).

Depth is stored reversed (1 near, 0 far or nothing), as in the colour pass: orthographic
views linearly between their fitted near and far planes, perspective views as near / t
(an infinitely far plane: float32 keeps the same relative precision at every distance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...scene import DirectionalLight, Scene, SpotLight
from ...scene.geometry.vertex_arrays import column_bounds
from .visible_regions import visible_receivers, world_box

# A spot whose window reaches beyond this tangent (about 68°) from its axis is drawn into a
# cube map: a single perspective view that wide wastes most of its texels at the edges.
MAX_SINGLE_VIEW_TAN = 2.5
# Perspective near planes at this fraction of the distance to the farthest visible receiver:
# reversed depth near / t has the same relative precision for any near, so only casters
# closer to the light than that are lost.
NEAR_FRACTION = 1e-6
# Cube faces by index: the axis a face looks along, and its up.
CUBE_FACES = (
    ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
    ((-1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
    ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    ((0.0, -1.0, 0.0), (0.0, 0.0, -1.0)),
    ((0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
    ((0.0, 0.0, -1.0), (0.0, -1.0, 0.0)),
)


@dataclass(frozen=True)
class ShadowView:
    """One layer of the shadow maps: a light's view of the receivers it may shadow.

    light_from_world: rigid, float64; the view looks along its −z axis.
    window: (x0, y0, x1, y1) of what the map covers, in the view's x and y (orthographic), or
            in x/t and y/t with t = −z the distance along the axis (perspective).
    near, far: the depth range along the axis (perspective: far is infinite)."""

    light: int  # index into scene.lights
    orthographic: bool
    light_from_world: np.ndarray
    window: tuple[float, float, float, float]
    near: float
    far: float

    def clip_from_light(self) -> np.ndarray:
        """The projection the shadow pass draws with (float64, reversed depth)."""
        x0, y0, x1, y1 = self.window
        width, height = x1 - x0, y1 - y0
        if self.orthographic:
            return np.array([
                [2.0 / width, 0.0, 0.0, -(x0 + x1) / width],
                [0.0, 2.0 / height, 0.0, -(y0 + y1) / height],
                [0.0, 0.0, 1.0 / (self.far - self.near), self.far / (self.far - self.near)],
                [0.0, 0.0, 0.0, 1.0],
            ])
        return np.array([
            [2.0 / width, 0.0, (x0 + x1) / width, 0.0],
            [0.0, 2.0 / height, (y0 + y1) / height, 0.0],
            [0.0, 0.0, 0.0, self.near],
            [0.0, 0.0, -1.0, 0.0],
        ])

    def texel_size(self, size: int) -> float:
        """The longer side of a texel: world units (orthographic) or units of x/t (perspective)."""
        x0, y0, x1, y1 = self.window
        return max(x1 - x0, y1 - y0) / size


@dataclass(frozen=True)
class LightShadow:
    """The views of one casting light: one (None: nothing visible it can shadow), or a cube
    map's six faces (None where skipped) with the cube's frame."""

    light: int
    views: tuple[ShadowView | None, ...]
    cube_from_world: np.ndarray | None = None  # world axes, origin at the light


# ----------------------------------------------------------------------------- bounds in a view


@dataclass(frozen=True)
class _Bounds:
    """An object's points as a view sees them: (x, y) bounds in window units, the depth
    range along the axis, and whether the object is flat (cannot shadow itself)."""

    owner: int
    lower: np.ndarray
    upper: np.ndarray
    near: float
    far: float
    flat: bool


def _bounds(owner: int, local: np.ndarray, orthographic: bool, limit: float, flat: bool) -> _Bounds:
    """Bounds of points in a view's space: x, y (orthographic), or x/t and y/t clamped to
    ±limit, all of ±limit when a point is not in front of the light, and empty when none
    is (perspective)."""
    distance = -local[:, 2]
    if orthographic:
        lower, upper = column_bounds(local[:, :2])
    elif (distance <= 0.0).all():  # wholly behind the light: nothing of it in the view
        lower, upper = np.full(2, np.inf), np.full(2, -np.inf)
    elif (distance > 1e-9 * float(np.linalg.norm(local, axis=1).max())).all():
        lower, upper = column_bounds(local[:, :2] / distance[:, None])
        lower, upper = np.maximum(lower, -limit), np.minimum(upper, limit)
    else:
        lower, upper = np.full(2, -limit), np.full(2, limit)
    return _Bounds(owner, lower, upper, float(distance.min()), float(distance.max()), flat)


def _shadowed_window(receivers: list[_Bounds], casters: list[_Bounds], clip: float = math.inf) -> tuple[np.ndarray, np.ndarray, list[_Bounds]] | None:
    """The bounds of every (caster ∩ receiver) where the caster can lie in front of the
    receiver, and the casters that do, within ±clip (a cube face's own pyramid: a receiver
    in it is shadowed only by what lies in it too); None when no caster can shadow a
    visible receiver."""
    lower, upper, active = np.full(2, np.inf), np.full(2, -np.inf), {}
    for caster in casters:
        for receiver in receivers:
            if caster.near >= receiver.far or (caster.flat and caster.owner == receiver.owner):
                continue
            low = np.maximum(np.maximum(caster.lower, receiver.lower), -clip)
            high = np.minimum(np.minimum(caster.upper, receiver.upper), clip)
            if (low <= high).all():
                lower, upper = np.minimum(lower, low), np.maximum(upper, high)
                active[caster.owner] = caster
    return (lower, upper, list(active.values())) if active else None


def _is_flat(obj) -> bool:
    """A mesh whose bounding box has no thickness along an axis of its own: a plane."""
    lower, upper = obj.mesh.bounds()
    return bool((upper - lower == 0.0).any())


@dataclass(frozen=True)
class _Scene:
    """The points of what may be shadowed (visible receivers) and of what may cast (every
    caster's world box), by object index."""

    receivers: dict[int, np.ndarray]
    casters: dict[int, tuple[np.ndarray, bool]]

    @classmethod
    def of(cls, scene: Scene) -> "_Scene":
        casters = {index: (world_box(obj), _is_flat(obj)) for index, obj in enumerate(scene.objects) if obj.cast_shadows}
        return cls(visible_receivers(scene), casters)

    def window(self, light_from_world: np.ndarray, orthographic: bool, limit: float = math.inf, clip: float = math.inf):
        """_shadowed_window in the view of light_from_world."""
        def local(points):
            return points @ light_from_world[:3, :3].T + light_from_world[:3, 3]
        receivers = [_bounds(i, local(p), orthographic, limit, False) for i, p in self.receivers.items()]
        casters = [_bounds(i, local(p), orthographic, limit, flat) for i, (p, flat) in self.casters.items()]
        found = _shadowed_window(receivers, casters, clip)
        return None if found is None else (*found, receivers)

    def farthest(self, position: np.ndarray) -> float:
        return max(float(np.linalg.norm(p - position, axis=1).max()) for p in self.receivers.values())


# ----------------------------------------------------------------------------- per light kind


def _basis_along(forward: np.ndarray) -> np.ndarray:
    """A rotation (rows: the view's x, y, z axes in world space) whose −z is `forward`."""
    z = -forward / np.linalg.norm(forward)
    helper = np.array([0.0, 1.0, 0.0]) if abs(z[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.array([x, np.cross(z, x), z])


def _rigid(rotation: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """light_from_world: the rotation (rows: the view's axes) about `origin`."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = -rotation @ origin
    return matrix


def _turn(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """> 0 when a → b → c turns counter-clockwise (the 2D cross product of b − a and c − a)."""
    return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def _hull(points: np.ndarray) -> np.ndarray:
    """The 2D convex hull, counter-clockwise (Andrew's monotone chain)."""
    unique = np.unique(points, axis=0)
    if len(unique) < 3:
        return unique

    def half(sequence):
        chain: list = []
        for p in sequence:
            while len(chain) >= 2 and _turn(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        return chain[:-1]

    return np.array(half(unique) + half(unique[::-1]))


def smallest_rectangle_angle(points: np.ndarray) -> float:
    """The turn (radians) that makes the axis-aligned box of 2D points smallest: one of the
    convex hull's edge directions (Freeman & Shapira, "Determining the minimum-area encasing
    rectangle for an arbitrary closed curve", CACM 18(7), 1975;
    https://apps.dtic.mil/sti/html/tr/ADA008844/index.html)."""
    hull = _hull(points)
    if len(hull) < 3:
        return 0.0
    edges = np.roll(hull, -1, axis=0) - hull
    best, best_area = 0.0, math.inf
    for angle in np.arctan2(edges[:, 1], edges[:, 0]):
        c, s = math.cos(angle), math.sin(angle)
        turned = hull @ np.array([[c, -s], [s, c]])
        area = float(np.prod(np.ptp(turned, axis=0)))
        if area < best_area:
            best, best_area = float(angle), area
    return best


def _padded(low: float, high: float, size: int, margin: float, minimum: float) -> tuple[float, float]:
    """[low, high] widened so that `margin` texels of a `size`-texel map lie outside it."""
    extent = max(high - low, minimum)
    centre = (low + high) / 2.0
    half = extent / 2.0 * size / (size - 2.0 * margin)
    return centre - half, centre + half


def _directional(index: int, light: DirectionalLight, fit: _Scene, size: int, margin: float) -> ShadowView | None:
    basis = _basis_along(np.asarray(light.direction, dtype=np.float64))
    found = fit.window(_rigid(basis, np.zeros(3)), True)
    if found is None:
        return None
    corners = np.concatenate([fit.casters[caster.owner][0] for caster in found[2]]) @ basis.T
    angle = smallest_rectangle_angle(corners[:, :2])
    c, s = math.cos(angle), math.sin(angle)
    basis = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]) @ basis
    lower, upper, active, receivers = fit.window(_rigid(basis, np.zeros(3)), True)
    t_near = min(caster.near for caster in active)
    t_far = max(receiver.far for receiver in receivers)
    minimum = 1e-9 * max(float(np.abs(np.concatenate([lower, upper])).max()), abs(t_near), abs(t_far), 1e-300)
    x0, x1 = _padded(lower[0], upper[0], size, margin, minimum)
    y0, y1 = _padded(lower[1], upper[1], size, margin, minimum)
    pad = 1e-3 * max(t_far - t_near, minimum)
    t_near, t_far = t_near - pad, t_far + pad
    # The view's origin on its near plane at the window's centre: small numbers in the shader.
    origin = basis.T @ np.array([(x0 + x1) / 2.0, (y0 + y1) / 2.0, -t_near])
    half_x, half_y = (x1 - x0) / 2.0, (y1 - y0) / 2.0
    return ShadowView(index, True, _rigid(basis, origin), (-half_x, -half_y, half_x, half_y), 0.0, t_far - t_near)


def _perspective(index: int, position: np.ndarray, forward: np.ndarray, fit: _Scene, size: int, margin: float,
                 cone: float = math.inf) -> ShadowView | None | str:
    """One perspective view from `position` along `forward`, its window inside `cone` (a
    tangent); None if it shadows nothing visible, "cube" if the window is too wide."""
    light_from_world = _rigid(_basis_along(forward), position)
    found = fit.window(light_from_world, False, cone)
    if found is None:
        return None
    lower, upper = found[0], found[1]
    if not (np.abs(np.concatenate([lower, upper])) <= MAX_SINGLE_VIEW_TAN).all():
        return "cube"
    x0, x1 = _padded(lower[0], upper[0], size, margin, 1e-6)
    y0, y1 = _padded(lower[1], upper[1], size, margin, 1e-6)
    return ShadowView(index, False, light_from_world, (x0, y0, x1, y1), NEAR_FRACTION * fit.farthest(position), math.inf)


def _spot(index: int, light: SpotLight, fit: _Scene, size: int, margin: float) -> ShadowView | None | str:
    """The spot's single view, None if it shadows nothing visible, "cube" if too wide."""
    cone = math.tan(math.radians(light.cutoff)) if light.cutoff < 89.0 else math.inf
    return _perspective(index, np.asarray(light.position, dtype=np.float64), np.asarray(light.direction, dtype=np.float64),
                        fit, size, margin, cone)


def _aimed(index: int, light, fit: _Scene, size: int, margin: float) -> ShadowView | None | str:
    """A positional light's single view aimed at the middle of the visible receivers, when
    all it can shadow lies within MAX_SINGLE_VIEW_TAN of that direction (a light far from the
    scene: near a cube's corner, three faces would each spend a whole face on a corner of
    it); else "cube"."""
    position = np.asarray(light.position, dtype=np.float64)
    points = np.concatenate(list(fit.receivers.values()))
    lower, upper = column_bounds(points)
    forward = (lower + upper) / 2.0 - position
    # Every receiver in front of the view: one behind it (which the light does reach, unlike
    # a spot's) would be outside the window, read as lit.
    if not np.linalg.norm(forward) > 0.0 or not ((points - position) @ forward > 0.0).all():
        return "cube"
    return _perspective(index, position, forward, fit, size, margin)


def cube_guard(size: int, margin: float) -> float:
    """A cube face's half-width in x/t: 1, plus `margin` texels of the face itself."""
    return size / (size - 2.0 * margin)


def face_rotation(face: int) -> np.ndarray:
    forward, up = (np.array(v) for v in CUBE_FACES[face])
    z = -forward
    x = np.cross(up, z)
    return np.array([x, np.cross(z, x), z])


def _face_reaches(light_from_world: np.ndarray, guard: float, regions: list[np.ndarray]) -> bool:
    """Whether some region may lie in the face's pyramid: skipped only when every point of
    every region is outside one of its planes."""
    for points in regions:
        local = points @ light_from_world[:3, :3].T + light_from_world[:3, 3]
        t = -local[:, 2]
        if (t <= 0.0).all():
            continue
        if not any((local[:, axis] * sign > guard * t).all() for axis in (0, 1) for sign in (1.0, -1.0)):
            return True
    return False


def _cube(index: int, light, fit: _Scene, size: int, margin: float) -> LightShadow:
    """The cube's faces that can reach a visible receiver a caster shadows, all with one
    window: the union of what each needs in its own x/t, y/t (the faces are alike, so one
    texel mapping serves them all), padded by `margin` texels and never wider than the face
    and its guard band. A light far from the scene sees it under a small angle: a window as
    wide as the face would spread its texels over directions nothing visible lies in."""
    position = np.asarray(light.position, dtype=np.float64)
    guard = cube_guard(size, margin)
    near = NEAR_FRACTION * fit.farthest(position)
    needed, lower, upper = [], np.full(2, np.inf), np.full(2, -np.inf)
    for face in range(6):
        light_from_world = _rigid(face_rotation(face), position)
        reaches = _face_reaches(light_from_world, guard, list(fit.receivers.values()))
        found = fit.window(light_from_world, False, guard, clip=1.0) if reaches else None
        if found is not None and isinstance(light, SpotLight):  # the face's pyramid meets the cone
            axis = np.asarray(light.direction, dtype=np.float64)
            cosine = float(np.clip(-light_from_world[2, :3] @ axis / np.linalg.norm(axis), -1.0, 1.0))
            if math.degrees(math.acos(cosine)) - math.degrees(math.atan(guard * math.sqrt(2.0))) >= light.cutoff:
                found = None
        needed.append(light_from_world if found is not None else None)
        if found is not None:
            lower, upper = np.minimum(lower, found[0]), np.maximum(upper, found[1])
    if not any(view is not None for view in needed):
        return LightShadow(index, (None,) * 6, _rigid(np.eye(3), position))
    x0, x1 = _padded(lower[0], upper[0], size, margin, 1e-6)
    y0, y1 = _padded(lower[1], upper[1], size, margin, 1e-6)
    window = (max(x0, -guard), max(y0, -guard), min(x1, guard), min(y1, guard))
    views = tuple(ShadowView(index, False, view, window, near, math.inf) if view is not None else None for view in needed)
    return LightShadow(index, views, _rigid(np.eye(3), position))


def fit_shadow_views(scene: Scene, size: int, margin: float) -> tuple[LightShadow, ...]:
    """The views of every casting light of `scene`, in scene order, for `size`-texel maps
    with `margin` texels around what the receivers need (a filter's reach)."""
    fit = _Scene.of(scene)
    shadows = []
    for index, light in enumerate(scene.lights):
        if not light.shadows:
            continue
        if not fit.receivers:
            shadows.append(LightShadow(index, (None,)))
        elif isinstance(light, DirectionalLight):
            shadows.append(LightShadow(index, (_directional(index, light, fit, size, margin),)))
        else:
            single = (_spot if isinstance(light, SpotLight) else _aimed)(index, light, fit, size, margin)
            shadows.append(_cube(index, light, fit, size, margin) if single == "cube" else LightShadow(index, (single,)))
    return tuple(shadows)
