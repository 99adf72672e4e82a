"""The camera: gluLookAt + gluPerspective (or glOrtho), validated."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from pyglm import glm

from ..errors import SceneError
from .values import MAX_COORDINATE, Vec3, set_fields, choice, direction, number, vec3

PROJECTIONS: tuple[str, ...] = ("perspective", "orthographic")

# The projection matrix goes to the GPU in float32: its terms focal, near/(far-near) and
# near·far/(far-near) must be normal float32 numbers (not denormal, not infinite), and
# focal × eye-space coordinates (<= 1e18, see Scene) must stay finite.
MIN_FOV_Y = 1e-6  # degrees: focal length 1/tan(fov_y/2) up to ~1e8
MIN_NEAR = 1e-20
MAX_FAR_OVER_NEAR = 1e30
# glOrtho's scale 2/ortho_height, times eye-space coordinates up to 1e18 (see Scene), must
# stay finite in float32 (3.4e38): 1e-12 leaves a wide margin, like MIN_FOV_Y's focal 1e8.
MIN_ORTHO_HEIGHT = 1e-12


@dataclass(frozen=True)
class Camera:
    """A camera at `eye` looking at `target` (gluLookAt), with a perspective projection
    (gluPerspective: `fov_y`) or an orthographic one (glOrtho: `ortho_height` world units
    from the bottom to the top of the image; None = the perspective view's height at the
    target's distance, so switching projection keeps the framing)."""

    eye: Vec3 = (0.0, 0.0, 3.0)
    target: Vec3 = (0.0, 0.0, 0.0)
    up: Vec3 = (0.0, 1.0, 0.0)
    fov_y: float = 45.0  # degrees, vertical
    near: float = 0.1
    far: float = 100.0
    projection: str = "perspective"  # perspective | orthographic
    ortho_height: float | None = None

    def __post_init__(self) -> None:
        eye = vec3(self.eye, "camera.eye")
        target = vec3(self.target, "camera.target")
        up = direction(self.up, "camera.up")
        fov_y = number(self.fov_y, "camera.fov_y", 0.0, 180.0, low_open=True)
        if fov_y >= 180.0:
            raise SceneError(f"camera.fov_y: expected less than 180 degrees, got {fov_y}")
        if fov_y < MIN_FOV_Y:
            raise SceneError(f"camera.fov_y: expected at least {MIN_FOV_Y:g} degrees (float32 projection), got {fov_y:g}")
        near = number(self.near, "camera.near", 0.0, math.inf, low_open=True)
        far = number(self.far, "camera.far", 0.0, math.inf, low_open=True)
        if near < MIN_NEAR:
            raise SceneError(f"camera.near: expected at least {MIN_NEAR:g} (float32 depth), got {near:g}")
        if not far > near:
            raise SceneError(f"camera.far ({far:g}) must be greater than camera.near ({near:g})")
        if far / near > MAX_FAR_OVER_NEAR:
            raise SceneError(
                f"camera.far / camera.near = {far / near:.3g} exceeds {MAX_FAR_OVER_NEAR:g} "
                f"(float32 depth cannot resolve it): near = {near:g}, far = {far:g}"
            )
        forward = glm.dvec3(*target) - glm.dvec3(*eye)
        distance = glm.length(forward)
        scale = max(max(abs(v) for v in eye), max(abs(v) for v in target), 1.0)
        if distance <= 1e-12 * scale:
            raise SceneError(f"camera: eye {list(eye)} and target {list(target)} coincide; the view direction is undefined")
        if glm.length(glm.cross(forward / distance, glm.normalize(glm.dvec3(*up)))) < 1e-9:
            raise SceneError(f"camera.up {list(up)} is parallel to the view direction; pick an up vector that is not")
        projection = choice(self.projection, "camera.projection", PROJECTIONS)
        ortho_height = self.ortho_height
        if ortho_height is not None:
            ortho_height = number(ortho_height, "camera.ortho_height", 0.0, MAX_COORDINATE, low_open=True)
            if ortho_height < MIN_ORTHO_HEIGHT:
                raise SceneError(
                    f"camera.ortho_height: expected at least {MIN_ORTHO_HEIGHT:g} (float32 projection), got {ortho_height:g}"
                )
            if projection != "orthographic":  # would be silently ignored
                raise SceneError(
                    f"camera.ortho_height ({ortho_height:g}) needs projection = \"orthographic\" (projection is {projection!r})"
                )
        set_fields(self, eye=eye, target=target, up=up, fov_y=fov_y, near=near, far=far,
             projection=projection, ortho_height=ortho_height)

    @property
    def orthographic(self) -> bool:
        return self.projection == "orthographic"

    def view_height(self) -> float:
        """World units from the bottom to the top of the image at the target's distance:
        `ortho_height` if set, else the perspective view's (2·distance·tan(fov_y/2))."""
        if self.ortho_height is not None:
            return self.ortho_height
        distance = glm.length(glm.dvec3(*self.target) - glm.dvec3(*self.eye))
        return 2.0 * distance * math.tan(math.radians(self.fov_y) / 2.0)

    def orbited(self, azimuth: float = 0.0, elevation: float = 0.0) -> "Camera":
        """The camera moved around its target (VTK's/f3d's Azimuth then Elevation, degrees):
        azimuth turns the eye about the up vector (positive: to the viewer's right, seen from
        above), elevation about the camera's right axis (positive: up); the up vector turns
        with it, so elevation past 90 degrees does not degenerate."""
        if not azimuth and not elevation:
            return self
        eye, target, up = glm.dvec3(*self.eye), glm.dvec3(*self.target), glm.dvec3(*self.up)
        offset = eye - target
        if azimuth:
            offset = glm.dmat3(glm.rotate(math.radians(azimuth), glm.normalize(up))) * offset
        if elevation:
            right = glm.normalize(glm.cross(-offset, up))  # view direction × up
            turn = glm.dmat3(glm.rotate(math.radians(elevation), -right))
            offset, up = turn * offset, turn * up
        return replace(self, eye=tuple(target + offset), up=tuple(up))

    def eye_from_world(self) -> np.ndarray:
        """The view matrix (gluLookAt, right-handed) as a float64 4x4 numpy array (column
        vectors: p_eye = M @ p_world). Double precision matters: camera-relative rendering
        forms model-view in float64 before anything is rounded to float32."""
        return np.array(glm.lookAtRH(glm.dvec3(*self.eye), glm.dvec3(*self.target), glm.dvec3(*self.up)))

    def view_matrix(self) -> glm.dmat4:
        """Deprecated: `glm.dmat4(camera.eye_from_world())` (one name per matrix)."""
        import warnings

        warnings.warn("Camera.view_matrix() is deprecated; use Camera.eye_from_world()", DeprecationWarning, stacklevel=2)
        return glm.dmat4(self.eye_from_world())

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit right, up and backward (eye-space +x, +y, +z) axes in world space, float64:
        the rows of the view matrix's rotation."""
        view = self.eye_from_world()
        return view[0, :3], view[1, :3], view[2, :3]
