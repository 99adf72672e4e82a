"""Which of an object's triangles a frame leaves out: those turned away from the camera, when
the frame is one where no triangle turned away can show. Two ways, for a closed surface:

- the rasterizer culls every triangle turned away (back-face culling) when the mesh is small
  enough to be checked before its first frame (`culls_turned_away`). That is the same
  picture as drawing them, except at the silhouette pixels where drawing them let one win
  the depth test by float32 rounding (a speckle in the colour of the far side;
  docs/conventions.md, "Closed surfaces"), and it spares their vertices, binning and
  fragments: a frame's overdraw from behind.
- the colour pass leaves out whole clusters wholly turned away (gpu/clusters.py, bigger
  meshes, built on a worker), the same pixels as drawing them.

That needs, besides a closed surface (the upload made clusters only for one):
- every triangle part opaque: a masked part's holes or a blended part would show the
  surface behind it, and a part asked to be lit from both sides (double_sided, two_sided)
  is drawn as the user wants it, whatever it hides;
- the camera outside the surface with nothing of it in front of the near plane: the
  corners of its bounding box all beyond the near plane (a near plane cutting it would
  open it to the eye);
- no `--edges`: their depth offset moves the surfaces' depths per triangle slope.
"""

from __future__ import annotations

import numpy as np
from pyglm import glm

from ...scene import Scene, SceneObject
from ...scene.geometry.mesh import Mesh
from ..gpu.mesh_uploads import GpuMesh, clusters_enabled

# Meshes up to this many triangles are checked for a closed surface (Mesh.exact_solid: ~0.4
# µs a triangle, 25 ms at 64K, once per mesh) when first drawn, and culled where they may
# be. A bigger mesh is never culled, even once the check has run for its clusters on the
# worker: a frame's pixels must not depend on whether a check has finished (a dataset's
# frames are those of single renders: docs/datasets.md).
CULLED_MAX_TRIANGLES = 1 << 16


def eye_outside(scene: Scene, obj: SceneObject, materials, model_view: glm.dmat4) -> tuple[np.ndarray, bool] | None:
    """Where the camera is in the object's mesh coordinates (the stored, origin-relative ones
    model_view maps to the eye), and whether it is orthographic (then the direction towards
    the camera), when this frame is one where no triangle turned away from it can show
    (above); None when it is not."""
    if scene.shading.edges or scene.shading.two_sided:
        return None
    for part, material in zip(obj.mesh.parts, materials):
        if part.primitive == "triangles" and (material.alpha_mode != "opaque" or material.double_sided):
            return None
    if abs(glm.determinant(model_view)) < 1e-300:
        return None
    lower, upper = obj.mesh.relative_bounds
    limit = -scene.camera.near * (1.0 + 1e-9)
    for x in (lower[0], upper[0]):
        for y in (lower[1], upper[1]):
            for z in (lower[2], upper[2]):
                if not (model_view * glm.dvec4(x, y, z, 1.0)).z < limit:
                    return None
    orthographic = scene.camera.projection == "orthographic"
    # The eye point, or (orthographic) the direction towards the camera: eye space's +z.
    eye = glm.inverse(model_view) * (glm.dvec4(0.0, 0.0, 1.0, 0.0) if orthographic else glm.dvec4(0.0, 0.0, 0.0, 1.0))
    return np.array([eye.x, eye.y, eye.z]), orthographic


def culls_turned_away(view: tuple[np.ndarray, bool] | None, mesh: Mesh) -> bool:
    """Whether the frame culls the mesh's triangles turned away from `view` (eye_outside) in
    the rasterizer: a closed surface, wound counter-clockwise seen from outside, with no
    crack even where corners are repeated (their positions identical: the rasterizer's
    coverage is watertight there), of at most CULLED_MAX_TRIANGLES triangles."""
    return view is not None and mesh.triangle_count <= CULLED_MAX_TRIANGLES and mesh.exact_solid == 1


def turned_away(view: tuple[np.ndarray, bool] | None, gpu_mesh: GpuMesh) -> np.ndarray | None:
    """(C,) bool over the upload's clusters, True for those this frame leaves out, seen from
    `view` (eye_outside); None when the frame draws every triangle."""
    clusters = gpu_mesh.order.clusters if gpu_mesh.order is not None else None
    if view is None or clusters is None or not clusters_enabled():
        return None
    return clusters.facing_away(*view)
