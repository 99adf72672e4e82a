"""Points, lines and edges: three kinds of draw of the colour pass, drawn as quads the
vertex stage builds on the screen, one instance per point or segment (docs/primitives.md).

- a point part of a mesh (point clouds, glTF POINTS): wgsl/points.wgsl, point_size pixels
  across, a square in the point's colour or a lit disc facing the point's normal;
- a line part (OBJ `l`, glTF LINES, LINE_STRIP, LINE_LOOP): wgsl/lines.wgsl, line_width
  pixels wide, in its colour;
- the edges of a triangle mesh over its surface (`--edges`): wgsl/lines.wgsl with EDGES,
  edge_width pixels wide, in the edge colour. They do not z-fight with their surface: the
  surfaces are pushed back by a slope-scaled depth bias (FeatureSet.under_edges, in the
  colour pass's descriptor builder) and the edges pass the depth test where level with it.

`strokes_pipeline` is their one pipeline-descriptor builder (the feature set's
`primitive` says which shader). A scene without points, lines or edges never reaches this
module: no pipeline, no upload, no code.
"""

from __future__ import annotations

import wgpu
from pyglm import glm

from ...scene import Material, Scene, SceneObject
from ...scene.geometry.mesh_parts import MeshPart
from ..gpu.device_cache import DeviceCache
from ..gpu.pipelines import BLEND_OVER, PassKind, PipelineDescriptor, PipelineKey
from ..shaders.bindings import binding_plan
from ..shaders.shadergen import generate_wgsl
from ..shaders.uniforms import object_uniforms, stroke_uniforms
from ..stroke_features import edge_features, line_features, point_features
from .draws import Draw

_EDGE_MATERIAL = Material()  # edges read no material: its block is filled, then ignored


def strokes_pipeline(key: PipelineKey) -> PipelineDescriptor:
    """Quads of two triangles, never culled (they face the camera); blended, without
    writing depth, when the material (or the edge colour) is translucent."""
    features = key.features
    return PipelineDescriptor(
        label=features.describe(),
        source=generate_wgsl(features),
        plan=binding_plan(features),
        indexed=False,
        quads=True,
        topology=wgpu.PrimitiveTopology.triangle_strip,
        depth_write=features.alpha_mode != "blend",
        color_format=key.target_format,
        blend=BLEND_OVER if features.alpha_mode == "blend" else None,
        samples=key.samples,
    )


STROKES = PassKind("strokes", strokes_pipeline)


def stroke_draw(cache: DeviceCache, scene: Scene, obj: SceneObject, part: MeshPart, material: Material,
                model_view: glm.dmat4, color_format: str, samples: int, draw_index: int) -> Draw:
    """The draw of one point or line part of `obj`."""
    points = part.primitive == "points"
    features = point_features(scene, obj, material, part) if points else line_features(scene, obj, material)
    entry = cache.pipelines.get(PipelineKey(STROKES, features, color_format, samples))
    upload = cache.gpu_points(obj.mesh) if points else cache.gpu_segments(obj.mesh, "lines")
    data = object_uniforms(model_view, material, entry.uniform_dtypes["object"], scene)
    pixels = scene.shading.point_size if points else scene.shading.line_width
    return Draw(
        entry=entry,
        draw_index=draw_index,
        gpu_mesh=upload,
        object_data=stroke_uniforms(data, scene.size, pixels),
        first_triangle=part.first - (upload.base if points else 0),
        triangle_count=part.count,
        textures={},
    )


def edge_draw(cache: DeviceCache, scene: Scene, obj: SceneObject, model_view: glm.dmat4, color_format: str,
              samples: int, draw_index: int) -> Draw:
    """The draw of every edge of `obj`'s triangles, in the edge colour."""
    entry = cache.pipelines.get(PipelineKey(STROKES, edge_features(scene), color_format, samples))
    data = object_uniforms(model_view, _EDGE_MATERIAL, entry.uniform_dtypes["object"], scene)
    return Draw(
        entry=entry,
        draw_index=draw_index,
        gpu_mesh=cache.gpu_segments(obj.mesh, "edges"),
        object_data=stroke_uniforms(data, scene.size, scene.shading.edge_width, scene.shading.edge_color),
        first_triangle=0,
        triangle_count=len(obj.mesh.edge_indices),
        textures={},
    )
