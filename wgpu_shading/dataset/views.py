"""From a job to the Scene it renders: the base scene (what `wgpu-shading render` would draw
for the same file and flags), then the job's camera or orbit.

Orbit: the camera moves on a sphere around its target. The pole is the base camera's up
vector; azimuth 0 is the side the base camera looks from, positive azimuth turns the camera
counter-clockwise seen from above (from +up); elevation is the angle above the plane through
the target perpendicular to up (a bare mesh's default view has elevation atan(0.35) ≈ 19.3°);
distance is from the target (default: the base camera's). The scene's lights move with the
camera as one rig, so every view is lit like the base view (the object seems to turn, as in
`wgpu-shading turntable`). Explicit camera keys (eye, target, ...) move only the camera.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from pyglm import glm

from ..errors import SceneError
from ..scene import DirectionalLight, PositionalLight, Scene, SpotLight, material
from .jobs import Job

DEFAULT_SIZE = (512, 512)  # what `wgpu-shading render MESH` uses


def turntable_views(count: int, elevation: float | None = None) -> list[dict[str, float]]:
    """`count` azimuths 360°/count apart (the first is the base view's side), at the base
    view's elevation unless given."""
    if count < 1:
        raise SceneError(f"views: expected at least 1, got {count}")
    views = [{"azimuth": 360.0 * i / count} for i in range(count)]
    if elevation is not None:
        for view in views:
            view["elevation"] = elevation
    return views


def sphere_views(count: int) -> list[dict[str, float]]:
    """`count` directions spread evenly over the sphere (a Fibonacci lattice: equal-area
    bands in elevation, azimuth stepped by the golden angle); never exactly at a pole."""
    if count < 1:
        raise SceneError(f"views: expected at least 1, got {count}")
    golden_angle = 180.0 * (3.0 - math.sqrt(5.0))
    views = []
    for i in range(count):
        height = 1.0 - (2 * i + 1) / count  # sin(elevation), strictly inside (-1, 1)
        views.append({"azimuth": (golden_angle * i) % 360.0, "elevation": math.degrees(math.asin(height))})
    return views


def base_scene(job: Job) -> Scene:
    """The scene `wgpu-shading render SOURCE --size W×H --material M` draws (before the
    shading overrides and the view). Loads the mesh: call once per load_key()."""
    from ..assets.mesh_scene import mesh_scene
    from ..assets.scenefile import load_scene

    chosen = job.overrides.get("material")
    if job.source.lower().endswith(".toml"):
        scene = load_scene(job.source)
        if job.size is not None:
            scene = replace(scene, size=job.size)
        if chosen:
            picked = material(chosen)
            scene = replace(scene, objects=tuple(replace(o, material=picked) for o in scene.objects))
        return scene
    return mesh_scene(job.source, job.size or DEFAULT_SIZE, chosen)


def job_scene(base: Scene, job: Job) -> Scene:
    """The base scene with the job's shading overrides, camera and orbit."""
    overrides: dict[str, Any] = {
        key: job.overrides[key] for key in ("frequency", "reflection", "blinn_exponent_scale") if key in job.overrides
    }
    if job.overrides.get("infinite_viewer"):
        overrides["local_viewer"] = False
    if job.overrides.get("two_sided"):
        overrides["two_sided"] = True
    scene = replace(base, shading=replace(base.shading, **overrides)) if overrides else base
    if job.camera:
        scene = replace(scene, camera=replace(scene.camera, **job.camera))
    if job.orbit:
        scene = orbited(scene, **job.orbit)
    return scene


def orbit_of(scene: Scene) -> tuple[float, float]:
    """(elevation in degrees, distance) of the scene's camera in the orbit convention."""
    camera = scene.camera
    up = glm.normalize(glm.dvec3(*camera.up))
    offset = glm.dvec3(*camera.eye) - glm.dvec3(*camera.target)
    distance = glm.length(offset)
    return math.degrees(math.asin(max(-1.0, min(1.0, glm.dot(offset, up) / distance)))), distance


def orbited(scene: Scene, azimuth: float = 0.0, elevation: float | None = None, distance: float | None = None) -> Scene:
    """The scene seen from the orbit position (see the module doc); lights move with the camera."""
    camera = scene.camera
    if azimuth % 360.0 == 0.0 and elevation is None and distance is None:
        return scene  # the base view itself: exactly the camera `render` uses, no rounding
    base_elevation, base_distance = orbit_of(scene)
    elevation = base_elevation if elevation is None else elevation
    distance = base_distance if distance is None else distance
    if not -90.0 < elevation < 90.0:
        raise SceneError(f"elevation: expected strictly between -90 and 90 degrees, got {elevation:g}")
    if not distance > 0.0:
        raise SceneError(f"distance: expected a positive number, got {distance:g}")
    up = glm.normalize(glm.dvec3(*camera.up))
    target = glm.dvec3(*camera.target)
    offset = glm.dvec3(*camera.eye) - target
    horizontal = offset - glm.dot(offset, up) * up
    if glm.length(horizontal) < 1e-9 * glm.length(offset):  # looking straight down the pole
        horizontal = glm.cross(up, glm.dvec3(1.0, 0.0, 0.0))
        if glm.length(horizontal) < 1e-9:
            horizontal = glm.cross(up, glm.dvec3(0.0, 0.0, 1.0))
    front = glm.normalize(horizontal)
    side = glm.cross(up, front)
    a, e = math.radians(azimuth), math.radians(elevation)
    direction = math.cos(e) * (math.cos(a) * front + math.sin(a) * side) + math.sin(e) * up
    eye = target + distance * direction
    # Near and far keep their distances from the target (the framing of a bare mesh).
    near = max(camera.near + distance - base_distance, distance * 1e-3)
    far = camera.far + distance - base_distance
    new_camera = replace(camera, eye=tuple(eye), near=near, far=max(far, near * 1.001))
    # The rig's motion: world → old eye space → new world (lights keep their place in the view).
    motion = glm.inverse(new_camera.view_matrix()) * camera.view_matrix()
    rotation = glm.dmat3(motion)

    def point(p) -> tuple[float, float, float]:
        return tuple(glm.dvec3(motion * glm.dvec4(glm.dvec3(*p), 1.0)))

    def turned(d) -> tuple[float, float, float]:
        return tuple(rotation * glm.dvec3(*d))

    lights = []
    for light in scene.lights:
        if isinstance(light, DirectionalLight):
            lights.append(replace(light, direction=turned(light.direction)))
        elif isinstance(light, SpotLight):
            lights.append(replace(light, position=point(light.position), direction=turned(light.direction)))
        elif isinstance(light, PositionalLight):
            lights.append(replace(light, position=point(light.position)))
        else:  # pragma: no cover - Scene validates its lights
            raise SceneError(f"cannot move a {type(light).__name__}")
    return replace(scene, camera=new_camera, lights=tuple(lights))
