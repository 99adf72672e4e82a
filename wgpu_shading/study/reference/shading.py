"""The same-mesh reference: the scene's own triangles, transformed to eye space, rasterized once
in float64 (`RasterizedScene`, on `raster.py`) and shaded per pixel at any shading
frequency and reflection model (flat, Gouraud or Phong, through `lighting.py`) with
perspective-correct barycentrics; `render_reference` does both for the scene's own shading."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...scene import Scene, SceneObject, Shading, has_shadows
from .image import ReferenceImage
from .lighting import FALLBACK_NORMAL, dot, clamp_vertex_colors, combine, safe_normalize, shade, view_vectors
from .map_sampling import color_map, combine_factors, is_linear, lighting_factors, perturb, perturb_with_tangents, tangent_normal
from .raster import edge_margins, rasterize, screen_triangles, signed_area_fixed
from .transforms import eye_from_world, normal_matrix, transform_points, window_rays, world_from_model
from .visibility import ShadowRays


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
    model_view = eye_from_world(scene.camera) @ world_from_model(obj)
    normals_to_eye = normal_matrix(model_view)
    model_positions = obj.mesh.positions.astype(np.float64)
    return _PreparedObject(
        model_view=model_view,
        normal_matrix=normals_to_eye,
        # A mirrored transform flips the screen winding of outward-facing triangles.
        mirrored=bool(np.linalg.det(model_view[:3, :3]) < 0.0),
        eye_positions=transform_points(model_view, model_positions),
        eye_normals=obj.mesh.normals.astype(np.float64) @ normals_to_eye.T,
        model_positions=model_positions,
        faces=obj.mesh.indices.astype(np.int64),
    )


def _ray_barycentrics(corners: np.ndarray, origins: np.ndarray, rays: np.ndarray) -> np.ndarray:
    """Perspective-correct barycentrics: where each eye ray meets its triangle's plane,
    expressed in the triangle's (N, 3, 3) eye-space corners. Exact for clipped triangles too."""
    p0, p1, p2 = corners[:, 0], corners[:, 1], corners[:, 2]
    normal = np.cross(p1 - p0, p2 - p0)
    along = dot(normal, rays)
    safe_along = np.where(along != 0.0, along, 1.0)
    point = origins + rays * (dot(normal, p0 - origins) / safe_along)[:, None]
    twice_area = dot(normal, normal)
    safe_area = np.where(twice_area > 0.0, twice_area, 1.0)
    b0 = dot(normal, np.cross(p2 - p1, point - p1)) / safe_area
    b1 = dot(normal, np.cross(p0 - p2, point - p2)) / safe_area
    weights = np.stack([b0, b1, 1.0 - b0 - b1], axis=1)
    degenerate = (along == 0.0) | (twice_area <= 0.0)  # cannot cover a pixel; guard anyway
    return np.where(degenerate[:, None], 1.0 / 3.0, weights)


def _texel_footprint(obj: SceneObject, prepared: _PreparedObject, faces: np.ndarray, pixels: np.ndarray, scene: Scene) -> np.ndarray:
    """Texels per pixel step at each pixel: how far (u·W, v·H) moves when the ray moves to a
    neighbouring pixel centre, staying on the same triangle's plane (as the GPU's quad
    derivatives do, helper pixels included)."""
    height, width = obj.surface_material.texture.pixels.shape[:2]
    texture_scale = np.array([width, height], dtype=np.float64)
    corners = prepared.eye_positions[faces]
    uvs = obj.mesh.uvs.astype(np.float64)[faces] * texture_scale
    rows, columns = np.divmod(pixels, scene.size[0])

    def texel_position(column_offset, row_offset):
        origins, rays = window_rays(scene.camera, scene.size, columns + 0.5 + column_offset, rows + 0.5 + row_offset)
        return np.einsum("nk,nkc->nc", _ray_barycentrics(corners, origins, rays), uvs)

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
    visibility: np.ndarray | None = None,
) -> np.ndarray:
    """RGBA of the pixels where `obj` is visible: triangle index, barycentrics (N, 3) and
    facing; `visibility` (lights, N) is each light's V_i at those pixels (None: all lit)."""
    shading = scene.shading
    material = obj.surface_material
    faces = prepared.faces[triangles]
    # back faces are lit with -N only when two-sided (the scene's, or a glTF doubleSided material's)
    two_sided = shading.two_sided or material.double_sided is True
    back = two_sided & ~front_facing
    flip = np.where(back, -1.0, 1.0)[:, None]

    uvs = None
    if material.texture is not None or material.maps:
        if obj.mesh.uvs is None:
            raise ValueError(f"material {material.name!r} has a texture or maps but mesh {obj.mesh.name!r} has no UVs")
        uvs = obj.mesh.uvs.astype(np.float64)

    def shade_with(points, normals, uv=None, light_visibility=None):
        return shade(points, normals, view_vectors(points, normals, shading.local_viewer), scene, material,
                     **lighting_factors(material, uv), visibility=light_visibility)

    def vertex_color(points, normals, uv=None, lights_on=None):  # what the vertex stage passes on (flat, Gouraud)
        # lights_on (lights,): a constant V_i for every vertex (None: all 1)
        light_visibility = None if lights_on is None else np.repeat(lights_on[:, None], len(points), axis=1)
        parts = shade_with(points, normals, uv, light_visibility)
        if shading.clamp_vertex_colors:
            texture_mode = material.texture_mode if material.texture is not None else None
            parts = clamp_vertex_colors(*parts, texture_mode)
        return parts

    uv = None if uvs is None else np.einsum("nk,nkc->nc", weights, uvs[faces])
    if shading.frequency in ("flat", "gouraud"):
        if shading.frequency == "flat":
            # One evaluation per triangle: face normal from the stored positions, at the centroid
            # (maps that change the lighting are read at the centroid's uv).
            p = prepared.model_positions[faces]
            face_normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) @ prepared.normal_matrix.T
            normals = safe_normalize(face_normal, FALLBACK_NORMAL) * flip
            centroids = prepared.eye_positions[faces].mean(axis=1)

            def interpolated(lights_on=None):
                return vertex_color(centroids, normals, None if uvs is None else uvs[faces].mean(axis=1), lights_on)
        else:
            # Light each vertex (front with N, back with -N), then interpolate both parts
            # (unclamped like the seeds, or clamped per vertex like OpenGL: clamp_vertex_colors).
            vertex_normals = safe_normalize(prepared.eye_normals, FALLBACK_NORMAL)
            used = np.unique(faces)
            vertex_uv = None if uvs is None else uvs[used]
            slot = np.searchsorted(used, faces)  # (N, 3) rows of `used`

            def interpolated(lights_on=None):
                front = vertex_color(prepared.eye_positions[used], vertex_normals[used], vertex_uv, lights_on)
                back_parts = vertex_color(prepared.eye_positions[used], -vertex_normals[used], vertex_uv, lights_on) if two_sided else front
                parts = []
                for k in range(2):
                    chosen = np.where(back[:, None, None], back_parts[k][slot], front[k][slot])
                    parts.append(np.einsum("nk,nkc->nc", weights, chosen))
                return parts
        full_ambient_diffuse, full_specular = ambient_diffuse, specular = interpolated()
        # Shadows are per fragment (docs/shadows.md#flat-and-gouraud-shading): each shadowed
        # light's own share of the interpolated colour, scaled by 1 − V_i at the pixel.
        for index in range(0 if visibility is None else len(visibility)):
            shadowed = 1.0 - visibility[index]
            if shadowed.any():
                lights_on = np.ones(len(visibility))
                lights_on[index] = 0.0
                without_ambient_diffuse, without_specular = interpolated(lights_on)
                ambient_diffuse = ambient_diffuse - shadowed[:, None] * (full_ambient_diffuse - without_ambient_diffuse)
                specular = specular - shadowed[:, None] * (full_specular - without_specular)
    else:  # phong
        normals = safe_normalize(np.einsum("nk,nkc->nc", weights, prepared.eye_normals[faces]), FALLBACK_NORMAL) * flip
        points = np.einsum("nk,nkc->nc", weights, prepared.eye_positions[faces])
        mapped = None if uv is None else tangent_normal(material, uv)
        if mapped is not None:
            counter_clockwise = front_facing != prepared.mirrored
            face_sign = np.where(back, -1.0, 1.0)
            normals = perturb(normals, prepared.eye_positions[faces], uvs[faces], mapped, counter_clockwise, face_sign)
            if obj.mesh.tangents is not None and material.normal_map is not None:  # the file's frame
                linear = prepared.model_view[:3, :3]
                file_tangents = obj.mesh.tangents.astype(np.float64)
                eye_tangents = np.concatenate(
                    [file_tangents[:, :3] @ linear.T, file_tangents[:, 3:] * np.sign(np.linalg.det(linear))], axis=1
                )
                front = safe_normalize(np.einsum("nk,nkc->nc", weights, prepared.eye_normals[faces]), FALLBACK_NORMAL)
                normals = perturb_with_tangents(front, np.einsum("nk,nkc->nc", weights, eye_tangents[faces]), mapped, face_sign, normals)
        ambient_diffuse, specular = shade_with(points, normals, uv, visibility)

    linear = is_linear(scene, material)
    texel = color_map(material.texture, uv, linear) if uv is not None else None
    return combine(ambient_diffuse, specular, material, texel, **combine_factors(scene, material, uv))


def on_triangle(weights: np.ndarray) -> np.ndarray:
    """(N, 3) barycentric weights moved onto their triangle (negative ones to 0, the rest
    rescaled to sum to 1). A pixel the fixed-point rasterizer gives to a triangle may have
    its centre's float64 ray meet the triangle's plane a hair beyond an edge (−0.002 of
    the triangle); a shadow ray from there starts under the neighbouring facet of a fold
    and is hidden by it (random scene 236). The exact answer's point is on its visible
    triangle (docs/shadows.md#the-exact-answer)."""
    kept = np.maximum(weights, 0.0)
    return kept / kept.sum(axis=1, keepdims=True)


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
        tris = screen_triangles(eye_corners, np.arange(len(eye_corners)), camera, scene.size)
        visibility = rasterize(tris, scene.size, camera.near, camera.far, camera.orthographic)

        covered_flat = visibility.triangle >= 0
        pixels = np.flatnonzero(covered_flat)
        screen_triangle = visibility.triangle[pixels]
        source = tris.source[screen_triangle]
        self._pixels = pixels
        self._object_index = np.searchsorted(first_face, source, side="right") - 1
        self._local_triangle = source - first_face[self._object_index]
        rows, columns = np.divmod(pixels, width)

        # Facing from the winding on screen: counter-clockwise in NDC is front, flipped for mirrored objects.
        ccw_in_ndc = signed_area_fixed(tris.fixed[screen_triangle]) < 0
        mirrored = np.array([p.mirrored for p in self._prepared], dtype=bool)
        self._front_facing = ccw_in_ndc != mirrored[self._object_index]

        origins, rays = window_rays(camera, scene.size, columns + 0.5, rows + 0.5)
        self._weights = _ray_barycentrics(eye_corners[source], origins, rays)

        self.covered = covered_flat.reshape(height, width)
        self.triangle = self._image(self._local_triangle, -1, np.int64)
        self.object = self._image(self._object_index, -1, np.int64)
        self.depth = visibility.depth.reshape(height, width)
        self.edge_margin = self._image(edge_margins(tris.fixed[screen_triangle], columns, rows), np.inf, np.float64)
        self.visibility = self._light_visibility(eye_corners[source])

    def _light_visibility(self, pixel_corners: np.ndarray) -> np.ndarray:
        """(lights, H, W) V_i at each covered pixel's surface point (1 elsewhere), ray-cast
        (visibility.py) from the point in world space; all 1 when nothing casts shadows."""
        scene = self.scene
        width, height = scene.size
        result = np.ones((len(scene.lights), height * width))
        if has_shadows(scene) and len(self._pixels):
            eye_points = np.einsum("nk,nkc->nc", on_triangle(self._weights), pixel_corners)
            world_points = transform_points(np.linalg.inv(eye_from_world(scene.camera)), eye_points)
            result[:, self._pixels] = ShadowRays(scene).visibility(world_points, self._object_index, self._local_triangle)
        return result.reshape(len(scene.lights), height, width)

    def _image(self, values: np.ndarray, fill, dtype) -> np.ndarray:
        width, height = self.scene.size
        result = np.full(height * width, fill, dtype=dtype)
        result[self._pixels] = values
        return result.reshape(height, width)

    def shade(self, shading: Shading | None = None, visibility: np.ndarray | None = None) -> np.ndarray:
        """(H, W, 4) float64 color with the scene's shading, or with `shading` instead, and
        the exact shadows, or the per-light `visibility` (lights, H, W) instead."""
        scene = self.scene if shading is None else replace(self.scene, shading=shading)
        width, height = scene.size
        visibility = self.visibility if visibility is None else np.asarray(visibility, dtype=np.float64)
        if visibility.shape != (len(scene.lights), height, width):
            raise ValueError(f"visibility: expected shape {(len(scene.lights), height, width)}, got {visibility.shape}")
        per_pixel = visibility.reshape(len(scene.lights), height * width)
        shadowed = bool((per_pixel[:, self._pixels] != 1.0).any())
        color = np.broadcast_to(np.asarray(scene.background, dtype=np.float64), (height * width, 4)).copy()
        for index, (obj, geometry) in enumerate(zip(scene.objects, self._prepared)):
            mine = self._object_index == index
            if mine.any():
                color[self._pixels[mine]] = _shade_pixels(
                    scene, obj, geometry, self._local_triangle[mine], self._weights[mine], self._front_facing[mine],
                    per_pixel[:, self._pixels[mine]] if shadowed else None,
                )
        return color.reshape(height, width, 4)

    def texel_footprint(self) -> np.ndarray:
        """Texels per pixel step of each textured pixel (0 elsewhere): < 1 means magnified."""
        width, height = self.scene.size
        footprint = np.zeros(height * width)
        for index, (obj, geometry) in enumerate(zip(self.scene.objects, self._prepared)):
            mine = self._object_index == index
            if mine.any() and obj.surface_material.texture is not None:
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
        visibility=rasterized.visibility,
    )
