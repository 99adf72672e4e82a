"""From a job to the Scene it renders: the base scene (what `wgpu-shading render` would draw
for the same file and flags), then the job's camera and orbit, exactly as `render`'s camera
flags move it, so a job's pixels are those of the matching `render` command.

Orbit (the `render` flags --camera-azimuth-angle and --camera-elevation-angle, f3d's and VTK's meaning):
azimuth turns the camera about its up vector through the target (positive: to the viewer's
right, seen from above), then elevation about its right axis (positive: up; the up vector
turns with it). Both are relative to the scene's camera: a bare mesh is framed from 19.3°
above the horizon (FRAMING_ELEVATION), so elevation −19.3 looks at it level. distance
(--camera-distance) then moves the eye along its line of sight to that distance from the target.
For a bare mesh the depth range and the viewer lights (key light + headlight) follow the
moved camera, as in `render`; a scene file keeps its lights where the file put them.
"""

from __future__ import annotations

import math

from ..assets.view_loader import load_source
from ..errors import UsageError
from ..scene import Scene
from ..scene.view.bare_mesh import FRAMING_DIRECTION
from ..scene.view.apply import apply_view_options
from .jobs import Job

__all__ = ["FRAMING_ELEVATION", "MAX_VIEWS", "base_scene", "job_scene", "sphere_views", "turntable_views"]


FRAMING_ELEVATION = math.degrees(math.atan2(FRAMING_DIRECTION[1], FRAMING_DIRECTION[2]))  # ≈ 19.29°


# The views of a mesh are listed up front; beyond this a typo (--views 100000000000) would
# exhaust memory instead of failing (docs/reliability.md).
MAX_VIEWS = 100_000


def _check_count(count: int) -> None:
    if count < 1 or count > MAX_VIEWS:
        raise UsageError(f"views: expected 1 to {MAX_VIEWS} views per mesh, got {count}")


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


def base_scene(job: Job) -> Scene:
    """What the job's source loads to, before the view options that do not change what is
    loaded (assets/view_loader.py load_source). Loads the mesh: call once per load_key()."""
    return load_source(job.source, job.view_options())


def job_scene(base: Scene, job: Job) -> Scene:
    """The base scene with the job's view options applied: the Scene `wgpu-shading render`
    draws for the job's source and the same options (assets/view_loader.py load_view)."""
    return apply_view_options(base, job.view_options())
