"""Scene → feature set: exactly the effects one draw needs.

The feature set is the key of everything downstream: it selects the WGSL that
`shadergen` emits (code and uniform fields for absent effects are left out), and
the pipeline key (gpu/pipelines.py) holds it. It is a frozen, hashable dataclass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..errors import SceneError
from ..scene.maps import MAP_FIELDS
from ..scene import DirectionalLight, Material, Mesh, PositionalLight, Scene, SceneObject, SpotLight, has_shadows


@dataclass(frozen=True)
class FeatureSet:
    """What one draw's shader must do (shading frequency, reflection, how many lights of
    each kind, maps, culling, ...): the key of its generated WGSL and of its pipeline."""

    frequency: str = "phong"  # flat | gouraud | phong
    reflection: str = "phong"  # phong | blinn-phong
    directional_lights: int = 0
    positional_lights: int = 0
    spot_lights: int = 0
    attenuation: bool = False  # some positional or spot light has attenuation other than (1, 0, 0)
    specular: bool = True  # some light and the material both have a specular color
    emission: bool = False
    texture_mode: str | None = None  # None | modulate | modulate_all | blend
    two_sided: bool = False
    cull_back: bool = False  # glTF doubleSided false: back faces are not drawn
    local_viewer: bool = True
    clamp_vertex_colors: bool = False  # flat/Gouraud: OpenGL's per-vertex clamp (docs/conventions.md#shading-frequencies)
    vertex_colors: bool = False  # the mesh has colors: they multiply ambient and diffuse
    alpha_mode: str = "opaque"  # opaque (alpha 1) | mask (discard below the cutoff) | blend
    unlit: bool = False  # KHR_materials_unlit: the surface color, no lighting
    # Linear colour space (glTF): sRGB-encoded output (colour textures are decoded by an
    # *-srgb texture format, which needs no shader code).
    srgb_output: bool = False
    # Material maps (scene/maps.py), each compiled only where a draw uses it.
    normal_map: bool = False  # Phong frequency only (needs per-fragment normals)
    bump_map: bool = False  # Phong only: a height map, turned into a normal map on upload
    specular_map: bool = False
    shininess_map: bool = False
    emissive_map: bool = False
    occlusion_map: bool = False
    alpha_map: bool = False
    # The mesh's file tangents (glTF TANGENT) give the normal map's frame (Phong only).
    vertex_tangents: bool = False
    # What the draw draws (docs/primitives.md): triangles, or points or lines as screen-space
    # quads (render/stroke_features.py makes their feature sets). point_normals: some point
    # has a normal (lit discs); edges: a triangle mesh's edges in the edge colour;
    # under_edges: surfaces pushed back this many pixels of their own depth slope (a
    # pipeline's depth bias), so that their edges drawn over them never z-fight.
    primitive: str = "triangles"
    point_normals: bool = False
    # (texture, set) of every sampled texture that reads another of the mesh's texture
    # coordinate sets than its uvs (Texture.uv_set ≥ 1: Mesh.extra_uvs); textures absent read set 0.
    uv_sets: tuple[tuple[str, int], ...] = ()
    edges: bool = False
    under_edges: int = 0
    # Shadows (docs/shadows.md), for a draw that receives them: the first N lights of each
    # kind cast (the uniforms hold casting lights first), and how their maps are filtered.
    directional_shadows: int = 0
    spot_shadows: int = 0
    positional_shadows: int = 0
    shadow_filter: str | None = None  # None (no shadow code) | nearest | bilinear | pcf3 | pcf5

    def __post_init__(self) -> None:
        if self.primitive != "triangles":
            # Points and lines have no surface: no textures, maps, sides or frequencies; a
            # line is drawn in its colour, a point lit only as a disc (stroke_features.py).
            lit = self.primitive == "points" and self.point_normals
            changes = {**_STROKE_FIXED, "point_normals": lit, "unlit": not lit, "specular": lit and self.specular,
                       "emission": lit and self.emission, "edges": self.edges and self.primitive == "lines"}
            for key, value in changes.items():
                object.__setattr__(self, key, value)

    @property
    def shadow_lights(self) -> int:
        """The casting lights this draw looks up (0 without a filter: no shadow code)."""
        if self.shadow_filter is None:
            return 0
        return self.directional_shadows + self.spot_shadows + self.positional_shadows

    @property
    def map_flags(self) -> tuple[str, ...]:
        """The material-map fields that are on, in binding order."""
        return tuple(name for name in MAP_FIELDS if getattr(self, name))

    @property
    def uses_uvs(self) -> bool:
        """Whether the draw reads texture coordinates (a texture or any map)."""
        return self.texture_mode is not None or bool(self.map_flags)

    @property
    def light_count(self) -> int:
        return self.directional_lights + self.positional_lights + self.spot_lights

    def defines(self) -> dict[str, int | bool]:
        """The names `#if` lines in the WGSL sources may test. Every name is always defined."""
        return {
            "FREQUENCY_FLAT": self.frequency == "flat",
            "FREQUENCY_GOURAUD": self.frequency == "gouraud",
            "FREQUENCY_PHONG": self.frequency == "phong",
            "REFLECTION_PHONG": self.reflection == "phong",
            "REFLECTION_BLINN_PHONG": self.reflection == "blinn-phong",
            "DIRECTIONAL_LIGHTS": self.directional_lights,
            "POSITIONAL_LIGHTS": self.positional_lights,
            "SPOT_LIGHTS": self.spot_lights,
            "ATTENUATION": self.attenuation,
            "SPECULAR": self.specular,
            "EMISSION": self.emission,
            "TEXTURE": self.texture_mode is not None,
            "TEXTURE_MODULATE": self.texture_mode == "modulate",
            "TEXTURE_MODULATE_ALL": self.texture_mode == "modulate_all",
            "TEXTURE_BLEND": self.texture_mode == "blend",
            "TWO_SIDED": self.two_sided,
            "LOCAL_VIEWER": self.local_viewer,
            "CLAMP_VERTEX_COLORS": self.clamp_vertex_colors,
            "VERTEX_COLORS": self.vertex_colors,
            "ALPHA_MASK": self.alpha_mode == "mask",
            "ALPHA_BLEND": self.alpha_mode == "blend",
            "UNLIT": self.unlit,
            "UVS": self.uses_uvs,
            "SRGB_OUTPUT": self.srgb_output,
            "NORMAL_MAP": self.normal_map,
            "BUMP_MAP": self.bump_map,
            "SPECULAR_MAP": self.specular_map,
            "SHININESS_MAP": self.shininess_map,
            "EMISSIVE_MAP": self.emissive_map,
            "OCCLUSION_MAP": self.occlusion_map,
            "ALPHA_MAP": self.alpha_map,
            "VERTEX_TANGENTS": self.vertex_tangents,
            "POINTS": self.primitive == "points",
            "LINES": self.primitive == "lines",
            "STROKES": self.primitive != "triangles",
            "POINT_NORMALS": self.point_normals,
            "EDGES": self.edges,
            "SHADOWS": self.shadow_lights > 0,
            "SHADOW_LIGHTS": self.shadow_lights,
            "DIRECTIONAL_SHADOWS": self.shadow_lights > 0 and self.directional_shadows > 0,
            "SPOT_SHADOWS": self.shadow_lights > 0 and self.spot_shadows > 0,
            "POSITIONAL_SHADOWS": self.shadow_lights > 0 and self.positional_shadows > 0,
            "SHADOW_FILTER_NEAREST": self.shadow_filter == "nearest",
            # flat/Gouraud pass each casting light's ambient-diffuse and specular shares
            # apart only where the fragment treats the two apart (chunks/shadows/shares.wgsl)
            "SHADOW_SPLIT": self.specular and (self.texture_mode == "modulate" or self.specular_map),
        }

    @property
    def extra_uv_sets(self) -> tuple[int, ...]:
        """The mesh's texture coordinate sets besides its uvs that the draw reads."""
        return tuple(sorted({uv_set for _, uv_set in self.uv_sets}))

    def uv_set(self, texture: str) -> int:
        """The set the sampled texture `texture` ("base_color", "occlusion_map", ...) reads."""
        return dict(self.uv_sets).get(texture, 0)

    def describe(self) -> str:
        lights = ", ".join(
            f"{count} {kind}"
            for count, kind in (
                (self.directional_lights, "directional"),
                (self.positional_lights, "positional"),
                (self.spot_lights, "spot"),
            )
            if count
        )
        parts = [
            f"frequency={self.frequency}",
            f"reflection={self.reflection}",
            f"lights=[{lights or 'none'}]",
            f"attenuation={self.attenuation}",
            f"specular={self.specular}",
            f"emission={self.emission}",
            f"texture={self.texture_mode or 'none'}",
            f"two_sided={self.two_sided}",
            f"viewer={'local' if self.local_viewer else 'infinite'}",
        ]
        if self.clamp_vertex_colors:
            parts.append("clamp_vertex_colors=True")
        if self.vertex_colors:
            parts.append("vertex_colors=True")
        if self.alpha_mode != "opaque":
            parts.append(f"alpha={self.alpha_mode}")
        if self.unlit:
            parts.append("unlit=True")
        if self.srgb_output:
            parts.append("srgb_output=True")
        if self.map_flags:
            parts.append(f"maps=[{', '.join(self.map_flags)}]")
        if self.cull_back:
            parts.append("cull_back=True")
        if self.primitive != "triangles":
            parts.append(f"primitive={self.primitive}" + (" point_normals=True" if self.point_normals else "") + (" edges=True" if self.edges else ""))
        if self.under_edges:
            parts.append(f"under_edges={self.under_edges}")
        if self.uv_sets:
            parts.append("uv_sets=[" + ", ".join(f"{name}:{uv_set}" for name, uv_set in self.uv_sets) + "]")
        if self.shadow_lights:
            parts.append(f"shadows=[{self.directional_shadows} directional, {self.spot_shadows} spot, "
                         f"{self.positional_shadows} positional; {self.shadow_filter}]")
        return " ".join(parts)

    def scene_part(self) -> "FeatureSet":
        """Only the fields that shape the frame uniforms (shared by every object of a scene)."""
        return FeatureSet(
            frequency="phong",
            reflection=self.reflection,
            directional_lights=self.directional_lights,
            positional_lights=self.positional_lights,
            spot_lights=self.spot_lights,
            attenuation=self.attenuation,
        )


# What every point and line feature set holds, whatever it was made with.
_STROKE_FIXED = dict(frequency="phong", texture_mode=None, two_sided=False, cull_back=False, clamp_vertex_colors=False,
                     normal_map=False, bump_map=False, specular_map=False, shininess_map=False, emissive_map=False,
                     occlusion_map=False, alpha_map=False, vertex_tangents=False, under_edges=0, uv_sets=(),
                     directional_shadows=0, spot_shadows=0, positional_shadows=0, shadow_filter=None)


def _has_attenuation(light: PositionalLight | SpotLight) -> bool:
    return tuple(light.attenuation) != (1.0, 0.0, 0.0) or light.range > 0.0


def object_features(scene: Scene, obj: SceneObject, index: int = 0, material: Material | None = None) -> FeatureSet:
    """The feature set for drawing `obj` (or one part of it, drawn with `material`) in `scene`."""
    material = obj.surface_material if material is None else material
    texture_mode = None
    if material.texture is not None:
        if obj.mesh.uvs is None:
            raise SceneError(
                f"objects[{index}]: material {material.name or '(inline)'} has a texture but mesh "
                f"{obj.mesh.name!r} has no UV coordinates"
            )
        texture_mode = material.texture_mode
    maps = material.maps
    if maps and obj.mesh.uvs is None:
        raise SceneError(
            f"objects[{index}]: material {material.name or '(inline)'} has {', '.join(maps)} but mesh "
            f"{obj.mesh.name!r} has no UV coordinates"
        )
    lit = not material.unlit
    specular = lit_specular(scene, material)
    per_fragment_normals = lit and scene.shading.frequency == "phong"
    features = FeatureSet(
        frequency=scene.shading.frequency,
        **scene_lighting(scene),
        specular=specular,
        emission=material.has_emission and not material.unlit,
        texture_mode=texture_mode,
        # --two-sided (the scene's) draws and lights both sides of everything; otherwise a
        # glTF material's doubleSided decides (culled when false), and classic ones follow the scene.
        two_sided=scene.shading.two_sided or material.double_sided is True,
        cull_back=material.double_sided is False and not scene.shading.two_sided,
        local_viewer=scene.shading.local_viewer,
        # Phong shading has no vertex colors: leaving the flag out keeps one pipeline for both.
        clamp_vertex_colors=scene.shading.clamp_vertex_colors and scene.shading.frequency != "phong",
        vertex_colors=obj.mesh.colors is not None,
        alpha_mode=material.alpha_mode,
        unlit=material.unlit,
        srgb_output=scene.shading.color_space_of(material) == "linear",
        # A map that cannot change this draw's pixels is left out (docs/conventions.md).
        normal_map="normal_map" in maps and per_fragment_normals,
        bump_map="bump_map" in maps and per_fragment_normals,
        specular_map="specular_map" in maps and specular,
        shininess_map="shininess_map" in maps and specular,
        emissive_map="emissive_map" in maps and lit and material.has_emission,
        occlusion_map="occlusion_map" in maps and lit,
        alpha_map="alpha_map" in maps and material.alpha_mode != "opaque",
        vertex_tangents=obj.mesh.tangents is not None and "normal_map" in maps and per_fragment_normals,
        under_edges=surface_offset(scene, obj.mesh),
        **_shadow_fields(scene, obj, lit),
    )
    uv_sets = texture_uv_sets(features, material, obj.mesh, index)
    return replace(features, uv_sets=uv_sets) if uv_sets else features


# The vertex stage passes each casting light's view of the point to the fragment stage
# (wgsl/chunks/shadows/lookup.wgsl), and flat and Gouraud shading its share of the lit colour
# too (shares.wgsl): varyings for this many casting lights at most.
MAX_SHADOW_LIGHTS = 8
MAX_VERTEX_LIT_SHADOW_LIGHTS = 4

# The kinds of light in the order of the shaders' shadow slots (casting_lights).
SLOT_KINDS = (DirectionalLight, SpotLight, PositionalLight)


def casting_lights(scene: Scene) -> tuple[int, ...]:
    """The scene's casting lights (indices into scene.lights) in the order a shader numbers
    them: directional, then spot, then positional lights, each kind in scene order. With
    shadows, the uniforms' light arrays hold each kind's casting lights first
    (shaders/uniforms.py), so slot s of a kind is that kind's light s."""
    if not has_shadows(scene):
        return ()
    return tuple(index for kind in SLOT_KINDS for index, light in enumerate(scene.lights)
                 if light.shadows and type(light) is kind)


def _shadow_fields(scene: Scene, obj: SceneObject, lit: bool) -> dict:
    """The shadow fields of a draw of `obj`: only for a lit receiver in a scene with shadows."""
    if not (lit and obj.receive_shadows and has_shadows(scene)):
        return {}
    casting = [scene.lights[index] for index in casting_lights(scene)]
    limit = MAX_SHADOW_LIGHTS if scene.shading.frequency == "phong" else MAX_VERTEX_LIT_SHADOW_LIGHTS
    if len(casting) > limit:
        shares = "" if scene.shading.frequency == "phong" else " and its share of the colour"
        raise SceneError(
            f"shadows: {scene.shading.frequency} shading passes each casting light's view of the point{shares} from "
            f"the vertex stage to the fragment stage, for at most {limit} casting lights; this scene has "
            f"{len(casting)} (let fewer lights cast{', or use phong shading' if shares else ''})"
        )
    return dict(
        directional_shadows=sum(type(light) is DirectionalLight for light in casting),
        spot_shadows=sum(type(light) is SpotLight for light in casting),
        positional_shadows=sum(type(light) is PositionalLight for light in casting),
        shadow_filter=scene.shadows.resolved().filter,
    )


# The sampled textures of a draw by the Material field holding each (shaders/bindings.py's names).
_TEXTURE_FIELDS = {"base_color": "texture", **{name: name for name in MAP_FIELDS}}


def texture_uv_sets(features: FeatureSet, material: Material, mesh, index: int) -> tuple[tuple[str, int], ...]:
    """(texture, set) for the draw's textures that read another set than the mesh's uvs
    (Texture.uv_set, docs/primitives.md#texture-coordinate-sets); the mesh must have it."""
    used = (["base_color"] if features.texture_mode is not None else []) + list(features.map_flags)
    sets = tuple((name, getattr(material, _TEXTURE_FIELDS[name]).uv_set) for name in used
                 if getattr(material, _TEXTURE_FIELDS[name]).uv_set)
    available = 0 if mesh.extra_uvs is None else mesh.extra_uvs.shape[1]
    for name, uv_set in sets:
        if uv_set > available:
            raise SceneError(f"objects[{index}]: material {material.name or '(inline)'}: its {_TEXTURE_FIELDS[name]} reads "
                             f"texture coordinate set {uv_set}, but mesh {mesh.name!r} has {available + 1 if mesh.uvs is not None else 0}")
    return sets


def scene_lighting(scene: Scene) -> dict:
    """The fields every draw of a scene shares (they shape its frame uniforms): the
    reflection model and the lights."""
    lights = scene.lights
    return dict(
        reflection=scene.shading.reflection,
        directional_lights=sum(isinstance(light, DirectionalLight) for light in lights),
        positional_lights=sum(isinstance(light, PositionalLight) for light in lights),
        spot_lights=sum(isinstance(light, SpotLight) for light in lights),
        attenuation=any(_has_attenuation(light) for light in lights if isinstance(light, (PositionalLight, SpotLight))),
    )


def lit_specular(scene: Scene, material: Material) -> bool:
    """Whether a lit draw of `material` has a highlight: the material and some light have a specular colour."""
    return not material.unlit and material.has_specular and any(max(light.specular[:3]) > 0.0 for light in scene.lights)


def surface_offset(scene: Scene, mesh: Mesh | None = None) -> int:
    """How far surfaces are pushed back under the lines drawn on them, in pixels of their own
    depth slope: half the widest such line (how far its quad reaches over a triangle next to
    it), rounded up, plus one. Those lines are the edges (`--edges`) and the mesh's own
    segments beside its triangles (a PLY's `edge` element over its faces, OBJ `l` beside
    `f`); 0 without either. docs/primitives.md#edges."""
    widths = [scene.shading.edge_width] if scene.shading.edges else []
    if mesh is not None and mesh.line_count and mesh.triangle_count:
        widths.append(scene.shading.line_width)
    return math.ceil(max(widths) / 2.0) + 1 if widths else 0
