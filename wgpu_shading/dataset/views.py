"""From a job to the Scene it renders: the base scene (what `wgpu-shading render` would draw
for the same file and flags), then the job's camera and orbit, exactly as `render`'s camera
flags move it, so a job's pixels are those of the matching `render` command.

Orbit (the `render` flags --camera-azimuth-angle and --camera-elevation-angle, f3d's and VTK's meaning):
azimuth turns the camera about its up vector through the target (positive: to the viewer's
right, seen from above), then elevation about its right axis (positive: up; the up vector
turns with it). Both are relative to the scene's camera: a bare mesh is framed from 19.3°
above the horizon (FRAMING_ELEVATION), so elevation −19.3 looks at it level. distance (no
`render` flag) then moves the eye along its line of sight to that distance from the target.
For a bare mesh the depth range and the viewer lights (key light + headlight) follow the
moved camera, as in `render`; a scene file keeps its lights where the file put them.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from pyglm import glm

from ..errors import SceneError
from ..scene import Camera, Scene, material
from ..scene.framing import FRAMING_DIRECTION, object_depth_range
from ..scene.viewer_lights import viewer_lights
from .jobs import Job

DEFAULT_SIZE = (512, 512)  # what `wgpu-shading render MESH` uses


FRAMING_ELEVATION = math.degrees(math.atan2(FRAMING_DIRECTION[1], FRAMING_DIRECTION[2]))  # ≈ 19.29°


# The views of a mesh are listed up front; beyond this a typo (--views 100000000000) would
# exhaust memory instead of failing (docs/reliability.md).
MAX_VIEWS = 100_000


def _check_count(count: int) -> None:
    if count < 1 or count > MAX_VIEWS:
        raise SceneError(f"views: expected 1 to {MAX_VIEWS} views per mesh, got {count}")


def turntable_views(count: int, elevation: float | None = None) -> list[dict[str, float]]:
    """`count` azimuths 360°/count apart (the first is the scene's own view), at the scene's
    elevation or turned by `elevation` degrees (render's --camera-elevation-angle)."""
    _check_count(count)
    views = [{"azimuth": 360.0 * i / count} for i in range(count)]
    if elevation is not None:
        for view in views:
            view["elevation"] = elevation
    return views


def sphere_views(count: int, base_elevation: float = FRAMING_ELEVATION) -> list[dict[str, float]]:
    """`count` directions spread evenly over the sphere (a Fibonacci lattice: equal-area
    bands in elevation, azimuth stepped by the golden angle; never exactly at a pole), as
    turns of a camera `base_elevation` degrees above the horizon (a bare mesh's framing)."""
    _check_count(count)
    golden_angle = 180.0 * (3.0 - math.sqrt(5.0))
    views = []
    for i in range(count):
        height = 1.0 - (2 * i + 1) / count  # sin(elevation above the horizon), inside (-1, 1)
        views.append({"azimuth": (golden_angle * i) % 360.0, "elevation": math.degrees(math.asin(height)) - base_elevation})
    return views


def is_bare_mesh(job: Job) -> bool:
    return not job.source.lower().endswith(".toml")


def base_scene(job: Job) -> Scene:
    """The scene `wgpu-shading render SOURCE --size W×H --material M` draws (before the
    shading overrides and the view). Loads the mesh: call once per load_key()."""
    from ..assets.mesh_scene import mesh_scene
    from ..assets.scenefile import load_scene

    chosen = job.overrides.get("material")
    if not is_bare_mesh(job):
        scene = load_scene(job.source)
        if job.size is not None:
            scene = replace(scene, size=job.size)
        if chosen:
            picked = material(chosen)
            scene = replace(scene, objects=tuple(replace(o, material=picked) for o in scene.objects))
        return scene
    return mesh_scene(job.source, job.size or DEFAULT_SIZE, chosen)


def job_scene(base: Scene, job: Job) -> Scene:
    """The base scene with the job's shading overrides, camera and orbit (as render applies
    its flags: camera keys, then azimuth and elevation, then the bare mesh's depth range
    and lights for the moved camera)."""
    overrides: dict[str, Any] = {
        key: job.overrides[key] for key in ("frequency", "reflection", "blinn_exponent_scale") if key in job.overrides
    }
    if job.overrides.get("infinite_viewer"):
        overrides["local_viewer"] = False
    if job.overrides.get("two_sided"):
        overrides["two_sided"] = True
    scene = replace(base, shading=replace(base.shading, **overrides)) if overrides else base
    camera = scene.camera
    if job.camera:
        camera = replace(camera, **job.camera)
    if job.orbit:
        camera = camera.orbited(job.orbit.get("azimuth", 0.0), job.orbit.get("elevation", 0.0))
        if "distance" in job.orbit:
            camera = at_distance(camera, job.orbit["distance"])
    if camera is scene.camera:
        return scene
    if not is_bare_mesh(job):
        return replace(scene, camera=camera)
    near, far = object_depth_range(camera.eye, scene.objects[0])
    camera = replace(camera, near=job.camera.get("near", near), far=job.camera.get("far", far))
    return replace(scene, camera=camera, lights=viewer_lights(camera))


def at_distance(camera: Camera, distance: float) -> Camera:
    """The camera moved along its line of sight to `distance` from its target."""
    if not (distance > 0.0 and math.isfinite(distance)):
        raise SceneError(f"distance: expected a positive number, got {distance:g}")
    target = glm.dvec3(*camera.target)
    offset = glm.dvec3(*camera.eye) - target
    return replace(camera, eye=tuple(target + offset * (distance / glm.length(offset))))
