"""The shadow hard cases (docs/shadows.md#the-hard-cases) as scene builders, for the tests,
the accuracy study, the benchmarks and the docs: `shadow_case(name, ...)` and
`shadow_cases(...)`. Each case is a Scene whose shadows are the hard part, plus its closed
form where one exists (the sphere's elliptic shadow on the plane; the same shapes as
exact spheres and rectangles for `render_analytic_scene`).

Every case can be built at another scale (every length × `scale`: 1e-3 and 1e3 are in the
guarantees), with an orthographic camera (the perspective view's framing at the target),
and at any image size."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ...errors import SceneError
from ...scene import (
    Camera,
    DirectionalLight,
    Material,
    Mesh,
    PositionalLight,
    Scene,
    SceneObject,
    SpotLight,
    cube,
    plane,
    torus,
    uv_sphere,
)
from ..reference import AnalyticRectangle, AnalyticSphere, eye_from_world, window_rays

GROUND = Material(ambient=(0.25, 0.25, 0.25, 1.0), diffuse=(0.75, 0.75, 0.72, 1.0), name="ground")
SHINY = Material(ambient=(0.2, 0.15, 0.1, 1.0), diffuse=(0.8, 0.55, 0.3, 1.0), specular=(0.5, 0.5, 0.5, 1.0),
                 shininess=40.0, name="shiny")
GLOWING = Material(ambient=(0.2, 0.2, 0.3, 1.0), diffuse=(0.4, 0.5, 0.8, 1.0), emission=(0.05, 0.05, 0.1, 1.0), name="glowing")
# The ray cast's sphere: facets within r·(1 − cos(π/128)) ≈ 3e-4·r of the exact sphere.
FINE_SPHERE = dict(slices=256, stacks=128)
ELEVATIONS = (60.0, 30.0, 10.0, 2.0)  # degrees: sphere over a plane, directional light


@dataclass(frozen=True)
class ShadowEllipse:
    """The exact shadow of a sphere on the plane y = 0 under a directional light: centre
    (world), unit major-axis direction (horizontal), semi-axes r/sin(elevation) and r."""

    center: tuple[float, float, float]
    major_direction: tuple[float, float, float]
    semi_major: float
    semi_minor: float

    def contains(self, points: np.ndarray) -> np.ndarray:
        """(N,) bool for world points on the plane: strictly inside the ellipse."""
        offset = np.asarray(points, dtype=np.float64) - np.asarray(self.center)
        major = np.asarray(self.major_direction)
        minor = np.cross((0.0, 1.0, 0.0), major)
        return (offset @ major / self.semi_major) ** 2 + (offset @ minor / self.semi_minor) ** 2 < 1.0

    @property
    def area(self) -> float:
        return math.pi * self.semi_major * self.semi_minor


@dataclass(frozen=True)
class ShadowCase:
    """One hard case: `scene` (its lights cast shadows), what it is about, and its closed
    form where there is one: `ellipse` (the exact shadow on the ground) and `shapes` (the
    same scene as exact spheres and rectangles, in `scene.objects` order)."""

    name: str
    scene: Scene
    about: str
    ellipse: ShadowEllipse | None = None
    shapes: tuple = ()


def plane_points(scene: Scene) -> np.ndarray:
    """(H, W, 3) world points where each pixel's ray meets the plane y = 0 (closed form)."""
    width, height = scene.size
    columns, rows = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    origins, directions = window_rays(scene.camera, scene.size, columns, rows)
    to_world = np.linalg.inv(eye_from_world(scene.camera))
    origins = origins @ to_world[:3, :3].T + to_world[:3, 3]
    directions = directions @ to_world[:3, :3].T
    t = -origins[..., 1] / directions[..., 1]
    return origins + t[..., None] * directions


def ground_view(case: ShadowCase, pixels: int = 160) -> tuple[Scene, float]:
    """The case seen from straight below the plane (orthographic, image rows along the
    shadow's major axis), framing the exact ellipse with a margin; and a pixel's size in
    world units."""
    ellipse = case.ellipse
    center = np.asarray(ellipse.center)
    height = 2.4 * ellipse.semi_major
    width_pixels = max(16, int(round(pixels * ellipse.semi_minor / ellipse.semi_major)) * 2)
    camera = Camera(eye=tuple(center - np.array([0.0, 10.0, 0.0])), target=tuple(center), up=ellipse.major_direction,
                    near=1.0, far=40.0 + 4 * height, projection="orthographic", ortho_height=height)
    return replace(case.scene, camera=camera, size=(int(width_pixels * 1.2), pixels)), height / pixels


def _ground(size: float) -> SceneObject:
    return SceneObject(plane(size), GROUND, rotate=(-90.0, 0.0, 0.0))  # y = 0, facing +Y


def _ground_shape(size: float) -> AnalyticRectangle:
    return AnalyticRectangle((0.0, 0.0, 0.0), (size / 2, 0.0, 0.0), (0.0, 0.0, -size / 2), GROUND)


def _travel(elevation: float, azimuth: float = 200.0) -> np.ndarray:
    """Unit direction a directional light travels: down at `elevation`, horizontally at `azimuth` (degrees from +X towards +Z)."""
    e, a = math.radians(elevation), math.radians(azimuth)
    return np.array([math.cos(e) * math.cos(a), -math.sin(e), math.cos(e) * math.sin(a)])


def _sphere_over_plane(elevation: float, height: float, name: str, about: str) -> ShadowCase:
    radius = 1.0
    center = np.array([0.0, height, 0.0])
    travel = _travel(elevation)
    horizontal = np.array([travel[0], 0.0, travel[2]]) / math.hypot(travel[0], travel[2])
    sin_e = math.sin(math.radians(elevation))
    ellipse_center = center + (height / sin_e) * travel
    semi_major = radius / sin_e
    reach = float(np.linalg.norm(ellipse_center)) + semi_major  # from the sphere's foot to the shadow's far tip
    # Seen from above and from the side of the shadow's axis (less from the side, more from
    # behind the sphere, as the shadow grows long: at 2° its far end is a thin sliver).
    side = math.radians(min(75.0, 10.0 + 8.0 * elevation))
    turned = np.array([[math.cos(side), 0, -math.sin(side)], [0, 1, 0], [math.sin(side), 0, math.cos(side)]]) @ horizontal
    span = min(reach, 30.0)
    target = horizontal * (0.4 * span) + np.array([0.0, 0.4 * height, 0.0])
    distance = 4.5 + 1.1 * span
    eye = target - distance * turned + np.array([0.0, 0.6 * distance, 0.0])
    ground = 2.5 * reach + 8.0
    scene = Scene(
        objects=(SceneObject(uv_sphere(radius, **FINE_SPHERE), SHINY, translate=tuple(center)), _ground(ground)),
        lights=(DirectionalLight(direction=tuple(travel), shadows=True),),
        camera=Camera(eye=tuple(eye), target=tuple(target), fov_y=45.0, near=0.05 * distance, far=4.0 * (distance + reach)),
    )
    ellipse = ShadowEllipse(tuple(ellipse_center), tuple(horizontal), semi_major, radius)
    shapes = (AnalyticSphere(tuple(center), radius, SHINY), _ground_shape(ground))
    return ShadowCase(name, scene, about, ellipse, shapes)


def _sphere_over(elevation: float) -> Callable[[], ShadowCase]:
    return lambda: _sphere_over_plane(
        elevation, 2.0, f"sphere_over_plane_{elevation:g}",
        f"a sphere one radius above a plane, directional light at {elevation:g}° elevation: the shadow is an "
        f"ellipse with semi-axes r and r/sin({elevation:g}°) = {1 / math.sin(math.radians(elevation)):.3g}·r",
    )


def _sphere_on_plane() -> ShadowCase:
    return _sphere_over_plane(30.0, 1.0, "sphere_on_plane",
                              "a sphere resting on the plane (light at 30°): the shadow reaches the contact point, no gap, no leak")


def _quad_occluder() -> ShadowCase:
    quad = SceneObject(plane(1.6), SHINY, translate=(0.2, 1.2, -0.1), rotate=(-70.0, 20.0, 0.0))
    return ShadowCase(
        "quad_occluder",
        Scene(
            objects=(quad, _ground(12.0)),
            lights=(SpotLight(position=(1.5, 4.0, 1.0), direction=(-0.35, -1.0, -0.3), cutoff=40.0, exponent=2.0, shadows=True),),
            camera=Camera(eye=(3.5, 4.5, 5.0), target=(0.0, 0.3, -0.5), near=0.5, far=40.0),
        ),
        "a zero-thickness quad (two triangles) under a spot light: it casts from both sides; its own back face is lit by nothing",
    )


def _torus() -> ShadowCase:
    ring = SceneObject(torus(1.0, 0.4, 64, 32), SHINY, translate=(0.0, 1.0, 0.0), rotate=(55.0, 0.0, 20.0))
    return ShadowCase(
        "torus_self_shadow",
        Scene(
            objects=(ring, _ground(12.0)),
            lights=(DirectionalLight(direction=tuple(_travel(35.0, 230.0)), shadows=True),),
            camera=Camera(eye=(0.5, 4.0, 5.0), target=(0.0, 0.7, 0.0), near=0.5, far=40.0),
        ),
        "a tilted torus shadowing itself (the ring's far side on its inner tube) and the plane",
    )


def _terminator() -> ShadowCase:
    ball = SceneObject(uv_sphere(1.0, 12, 7), SHINY, translate=(0.0, 1.2, 0.0), rotate=(10.0, 15.0, 0.0))
    return ShadowCase(
        "low_poly_terminator",
        Scene(
            objects=(ball, _ground(12.0)),
            lights=(DirectionalLight(direction=tuple(_travel(20.0, 170.0)), shadows=True),),
            camera=Camera(eye=(0.3, 2.2, 4.0), target=(0.0, 1.0, 0.0), near=0.5, far=40.0),
        ),
        "a smooth-shaded 12×7 sphere at its terminator: the facets hide the light before the normals turn away "
        "(the ray cast's teeth), and nothing more",
    )


def _ring_of_boxes() -> ShadowCase:
    boxes = tuple(
        SceneObject(cube(0.6), SHINY, translate=(2.0 * math.cos(a), 0.3, 2.0 * math.sin(a)), rotate=(0.0, math.degrees(-a), 0.0))
        for a in np.radians(np.arange(0.0, 360.0, 40.0) + 7.0)
    )
    return ShadowCase(
        "ring_of_boxes",
        Scene(
            objects=boxes + (_ground(16.0),),
            lights=(PositionalLight(position=(0.1, 0.8, -0.05), attenuation=(1.0, 0.0, 0.02), shadows=True),),
            camera=Camera(eye=(0.5, 9.0, 3.0), target=(0.0, 0.0, 0.0), near=1.0, far=40.0),
        ),
        "a positional light inside a ring of nine boxes: shadows in every direction, continuous across the cube map's faces",
    )


def _two_lights() -> ShadowCase:
    case = _sphere_over_plane(35.0, 1.8, "two_lights", "")
    first = case.scene.lights[0]
    second = PositionalLight(position=(3.0, 5.0, -2.5), diffuse=(0.6, 0.5, 0.4, 1.0), specular=(0.3, 0.3, 0.3, 1.0),
                             ambient=(0.05, 0.05, 0.05, 1.0), attenuation=(1.0, 0.02, 0.0), shadows=True)
    objects = (replace(case.scene.objects[0], material=GLOWING),) + case.scene.objects[1:]
    scene = replace(case.scene, lights=(first, second), objects=objects)
    return ShadowCase(
        "two_lights", scene,
        "two lights, each casting: where one is hidden the pixel is exactly ambient + emission + the other light",
        None, (replace(case.shapes[0], material=GLOWING), case.shapes[1]),
    )


def _light_past_a_cube_corner() -> ShadowCase:
    # Found by the random scenes (seed 24): a positional light far away along a diagonal
    # sees the scene across three cube faces, each needing a corner of its own; one window
    # shared by the faces then covers every face whole, and the torus got a handful of texels.
    ring = SceneObject(torus(0.35, 0.15, 40, 20), SHINY, translate=(0.0, 0.65, 0.0), rotate=(70.0, -149.0, 0.0))
    return ShadowCase(
        "light_past_a_cube_corner",
        Scene(
            objects=(ring, _ground(20.0)),
            lights=(PositionalLight(position=(30.5, 31.3, -31.1), shadows=True),),
            camera=Camera(eye=(-0.6, 3.2, 1.4), target=(-0.3, 0.3, -0.7), fov_y=50.0, near=0.1, far=60.0),
        ),
        "a positional light 54 units away along a diagonal: its view of the scene straddles three cube faces; "
        "one perspective view aimed at the scene covers it",
    )


def _off_centre_mesh() -> ShadowCase:
    # Found by the random scenes (seed 41, the fandisk): a mesh stored away from its own
    # origin (most files: Mesh keeps positions relative to the centre of their box, and its
    # model matrix puts that origin back) had its shadow maps fitted one origin away from it.
    case = _sphere_over_plane(30.0, 2.0, "off_centre_mesh", "")
    sphere = uv_sphere(1.0, **FINE_SPHERE)
    offset = np.array([40.0, 10.0, -25.0])
    moved = Mesh.from_arrays(sphere.positions.astype(np.float64) + offset, sphere.indices, sphere.normals, name="off-centre sphere")
    ball = replace(case.scene.objects[0], mesh=moved, translate=tuple(np.asarray(case.scene.objects[0].translate) - offset))
    return replace(case, scene=replace(case.scene, objects=(ball,) + case.scene.objects[1:]),
                   about="the sphere over a plane at 30°, its mesh's points stored 50 units from its own origin: the maps "
                         "must be fitted where the model matrix puts it")


def _light_by_a_sphere() -> ShadowCase:
    # Found by the random scenes (seed 57): a positional light beside a closed mesh, inside
    # its bounding box but outside the solid. The faces turned from the light meet the lit
    # ones at a grazing angle, where the map cannot tell them apart; the closed-surface rule
    # (docs/shadows.md#closed-surfaces) must still hold, so "inside" is the solid, not its box.
    ball = SceneObject(uv_sphere(1.0, 33, 16), SHINY, translate=(0.0, 1.3, 0.0), rotate=(20.0, 35.0, 0.0))
    light = PositionalLight(position=(0.72, 2.05, 0.45), attenuation=(1.0, 0.0, 0.05), shadows=True)
    return ShadowCase(
        "light_by_a_sphere",
        Scene(
            objects=(ball, _ground(12.0)),
            lights=(light,),
            camera=Camera(eye=(-1.2, 2.8, 4.2), target=(0.0, 1.2, 0.0), fov_y=40.0, near=0.5, far=40.0),
        ),
        "a positional light beside a 33×16 sphere, inside its bounding box but not in it: the terminator is the "
        "facets' edges, sharp, with no teeth (a convex solid cannot shadow a facet facing the light)",
    )


def _far_positional_light() -> ShadowCase:
    # Found by the random scenes (docs/shadows.md#random-scenes, seed 22): a positional light
    # 40 units away sees the scene under a few degrees; a cube face 90° wide gave the box a
    # handful of texels, and at 4° elevation each spans ~20 pixels of ground.
    box = SceneObject(cube(1.0), SHINY, translate=(0.3, 0.3, -1.3), rotate=(0.0, 126.0, 0.0), scale=(1.0, 0.3, 0.8))
    light = PositionalLight(position=tuple(np.array([0.3, 0.0, -1.3]) + 40.0 * np.array([0.92, 0.07, -0.37])),
                            shadows=True)
    return ShadowCase(
        "far_positional_light",
        Scene(
            objects=(box, _ground(24.0)),
            lights=(light,),
            camera=Camera(eye=(-7.5, 4.4, -0.5), target=(0.5, 0.4, -0.9), fov_y=60.0, near=0.2, far=60.0),
        ),
        "a positional light 40 units away at 4° elevation: its cube map must spend its texels on the few degrees the scene takes up",
    )


def _sliver_shadow() -> ShadowCase:
    # Found by the random scenes (seeds 290, 270, 229): a quad 0.23° from edge-on to the light
    # casts a shadow a pixel wide, thinner than a 512-texel map's texel; the map draws its
    # edges half a texel off, so pixels near them took the wrong state, specks and gaps along
    # the line. "auto" now sizes the map from the image's pixels (render/passes/shadow_resolution.py).
    travel = _travel(59.0)
    across = np.cross(travel, (0.0, 1.0, 0.0))
    across /= np.linalg.norm(across)
    along = travel + 0.004 * np.cross(across, travel)
    along /= np.linalg.norm(along)
    centre = np.array([0.0, 1.0, 0.0])
    corners = [centre + a * 1.6 * across + b * 0.6 * along for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    normal = np.cross(across, along)
    quad = Mesh.from_arrays(np.array(corners), np.array([[0, 1, 2], [0, 2, 3]]), np.tile(normal, (4, 1)), name="sliver quad")
    return ShadowCase(
        "sliver_shadow",
        Scene(objects=(SceneObject(quad, SHINY), _ground(12.0)), lights=(DirectionalLight(direction=tuple(travel), shadows=True),),
              camera=Camera(eye=(2.0, 3.5, 3.0), target=(-0.6, 0.0, -0.2), fov_y=45.0, near=0.2, far=40.0)),
        "a quad 0.23° from edge-on to a directional light at 59°: its shadow is a line about a pixel wide, "
        "thinner than a texel of a 512-texel map",
    )


_BUILDERS: dict[str, Callable[[], ShadowCase]] = {
    **{f"sphere_over_plane_{e:g}": _sphere_over(e) for e in ELEVATIONS},
    "sphere_on_plane": _sphere_on_plane,
    "quad_occluder": _quad_occluder,
    "torus_self_shadow": _torus,
    "low_poly_terminator": _terminator,
    "ring_of_boxes": _ring_of_boxes,
    "two_lights": _two_lights,
    "far_positional_light": _far_positional_light,
    "off_centre_mesh": _off_centre_mesh,
    "light_by_a_sphere": _light_by_a_sphere,
    "light_past_a_cube_corner": _light_past_a_cube_corner,
    "sliver_shadow": _sliver_shadow,
}
SHADOW_CASE_NAMES: tuple[str, ...] = tuple(_BUILDERS)
SCALES = (1e-3, 1.0, 1e3)
PROJECTIONS = ("perspective", "orthographic")


def _scaled_camera(camera: Camera, scale: float, projection: str) -> Camera:
    height = camera.view_height() * scale if projection == "orthographic" else None
    return Camera(eye=tuple(scale * np.asarray(camera.eye)), target=tuple(scale * np.asarray(camera.target)), up=camera.up,
                  fov_y=camera.fov_y, near=camera.near * scale, far=camera.far * scale, projection=projection, ortho_height=height)


def scaled_scene(scene: Scene, scale: float) -> Scene:
    """The scene with every length × scale: object and light positions, object scales,
    attenuation per unit distance, the camera (its framing kept, for either projection)."""
    def light(l):
        if not hasattr(l, "position"):
            return l
        # Attenuation is per unit distance: kl/scale and kq/scale² keep the picture.
        return replace(l, position=tuple(scale * np.asarray(l.position)),
                       attenuation=(l.attenuation[0], l.attenuation[1] / scale, l.attenuation[2] / scale**2))
    objects = tuple(replace(o, translate=tuple(scale * np.asarray(o.translate)), scale=tuple(scale * np.asarray(o.scale)))
                    for o in scene.objects)
    camera = _scaled_camera(scene.camera, scale, scene.camera.projection)
    return replace(scene, objects=objects, lights=tuple(light(l) for l in scene.lights), camera=camera)


def _scaled(case: ShadowCase, scale: float) -> ShadowCase:
    """Every length × scale: the scene (its camera is scaled by shadow_case) and the closed forms."""
    ellipse = case.ellipse and replace(case.ellipse, center=tuple(scale * np.asarray(case.ellipse.center)),
                                       semi_major=case.ellipse.semi_major * scale, semi_minor=case.ellipse.semi_minor * scale)
    shapes = tuple(
        replace(s, center=tuple(scale * np.asarray(s.center)), radius=s.radius * scale) if isinstance(s, AnalyticSphere)
        else replace(s, center=tuple(scale * np.asarray(s.center)), half_u=tuple(scale * np.asarray(s.half_u)),
                     half_v=tuple(scale * np.asarray(s.half_v)))
        for s in case.shapes
    )
    scene = replace(scaled_scene(case.scene, scale), camera=case.scene.camera)
    return replace(case, scene=scene, ellipse=ellipse, shapes=shapes)


def shadow_case(name: str, size: tuple[int, int] = (128, 128), *, scale: float = 1.0,
                projection: str = "perspective") -> ShadowCase:
    """One hard case by name (SHADOW_CASE_NAMES), at `size`, every length × `scale`, seen
    with a perspective or an orthographic camera (the same framing at the target)."""
    if name not in _BUILDERS:
        raise SceneError(f"shadow case: unknown name {name!r}; expected one of {', '.join(SHADOW_CASE_NAMES)}")
    if projection not in PROJECTIONS:
        raise SceneError(f"shadow case: projection must be one of {', '.join(PROJECTIONS)}, got {projection!r}")
    case = _BUILDERS[name]()
    case = _scaled(case, scale) if scale != 1.0 else case
    camera = _scaled_camera(case.scene.camera, scale, projection)
    suffix = ("" if scale == 1.0 else f"@{scale:g}") + ("" if projection == "perspective" else "/ortho")
    return replace(case, name=case.name + suffix, scene=replace(case.scene, camera=camera, size=size))


def shadow_cases(size: tuple[int, int] = (128, 128), *, scales=(1.0,), projections=("perspective",)) -> tuple[ShadowCase, ...]:
    """Every hard case at every scale and projection asked for."""
    return tuple(shadow_case(n, size, scale=s, projection=p) for n in SHADOW_CASE_NAMES for s in scales for p in projections)
