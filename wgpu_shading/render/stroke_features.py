"""The feature sets of points, lines and edges (docs/primitives.md): what their draws need
of the scene and the material. Textures and maps are not theirs (a point or a line has no
surface to map); the lights and the reflection model are the scene's, like every draw's
(they shape the frame uniforms every draw of a scene shares)."""

from __future__ import annotations

from ..scene import Material, Scene, SceneObject
from ..scene.geometry.mesh_parts import MeshPart
from .features import FeatureSet, lit_specular, object_features, scene_lighting


def point_features(scene: Scene, obj: SceneObject, material: Material, part: MeshPart) -> FeatureSet:
    """Points are lit discs where the part has normals and the material is lit, else
    squares in their colour (the material's diffuse × the vertex colours)."""
    lit = not material.unlit and obj.mesh.has_point_normals(part)
    return FeatureSet(
        frequency="phong",  # every frequency draws points alike: one pipeline
        **scene_lighting(scene),
        specular=lit and lit_specular(scene, material),
        emission=lit and material.has_emission,
        local_viewer=scene.shading.local_viewer,
        vertex_colors=obj.mesh.colors is not None,
        alpha_mode=material.alpha_mode,
        unlit=not lit,
        srgb_output=scene.shading.color_space_of(material) == "linear",
        primitive="points",
        point_normals=lit,
    )


def line_features(scene: Scene, obj: SceneObject, material: Material) -> FeatureSet:
    """Lines are drawn in their colour: the material's diffuse × the vertex colours."""
    return FeatureSet(
        frequency="phong",
        **scene_lighting(scene),
        specular=False,
        vertex_colors=obj.mesh.colors is not None,
        alpha_mode=material.alpha_mode,
        unlit=True,
        srgb_output=scene.shading.color_space_of(material) == "linear",
        primitive="lines",
    )


def edge_features(scene: Scene) -> FeatureSet:
    """A triangle mesh's edges (`--edges`): the scene's edge colour as it is (a colour on the
    image, like the background), blended over the surfaces where its alpha is below 1."""
    return FeatureSet(
        frequency="phong",
        **scene_lighting(scene),
        specular=False,
        alpha_mode="blend" if scene.shading.edge_color[3] < 1.0 else "opaque",
        unlit=True,
        primitive="lines",
        edges=True,
    )


def part_features(scene: Scene, obj: SceneObject, index: int, part: MeshPart, material: Material) -> FeatureSet:
    """The feature set the colour pass draws one part of `obj` with, whatever its primitive."""
    if part.primitive == "points":
        return point_features(scene, obj, material, part)
    if part.primitive == "lines":
        return line_features(scene, obj, material)
    return object_features(scene, obj, index, material)
