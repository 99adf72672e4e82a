"""Objects placed in the world, the shading settings, and the Scene that holds it all."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from pyglm import glm

from ..errors import SceneError, shown
from .camera import Camera
from .lights import DirectionalLight, Light, PositionalLight, SpotLight
from .maps import SCENE_COLOR_SPACES
from .material import Material
from .geometry.mesh import Mesh
from .shadows import ShadowSettings
from .values import (
    FREQUENCIES,
    MAX_EXPONENT,
    MAX_LIGHTS,
    MAX_OBJECTS,
    MAX_SCALE,
    MAX_STROKE_PIXELS,
    MIN_STROKE_PIXELS,
    MIN_SCALE,
    REFLECTIONS,
    Color,
    Frequency,
    Reflection,
    Vec3,
    boolean,
    set_fields,
    choice,
    color,
    image_size,
    number,
    vec3,
)

# Eye-space coordinates of every object stay within this: squared distances and lengths
# computed in float32 by the shaders (up to 3·(2e18)²) then stay below float32's 3.4e38.
MAX_EYE_COORDINATE = 1e18
SAMPLE_COUNTS = (1, 4)  # what every WebGPU adapter supports for render targets

# Euler XYZ about fixed axes is R = Rz · Ry · Rx: applied to the matrix in the order Z, Y, X.
_AXES_ZYX = (glm.dvec3(0.0, 0.0, 1.0), glm.dvec3(0.0, 1.0, 0.0), glm.dvec3(1.0, 0.0, 0.0))


# The rotation that takes a file's up axis to +Y (the renderer's up): f3d's `--up` rule,
# the smallest rotation between the two (180° about X for -Y).
UP_AXES = ("+Y", "-Y", "+Z", "-Z", "+X", "-X")
_UP_ROTATIONS = {
    "+Y": None,
    "-Y": (180.0, (1.0, 0.0, 0.0)),
    "+Z": (-90.0, (1.0, 0.0, 0.0)),
    "-Z": (90.0, (1.0, 0.0, 0.0)),
    "+X": (90.0, (0.0, 0.0, 1.0)),
    "-X": (-90.0, (0.0, 0.0, 1.0)),
}


def up_axis(value: object, where: str = "up") -> str:
    """'+Z', 'z', '-x' ... → the canonical '+Z' form; an error names the valid ones."""
    text = str(value).strip().upper() if isinstance(value, str) else ""
    if text and text[0] not in "+-":
        text = "+" + text
    if text not in _UP_ROTATIONS:
        raise SceneError(f"{where}: expected one of {', '.join(UP_AXES)}, got {value!r}")
    return text


@dataclass(frozen=True)
class SceneObject:
    """A mesh placed in the world: model = translate · rotate · scale · up.

    material: one material for every part of the mesh, or None for the file's own
    materials, part by part (OpenGL's default material where a part has none).
    up: the file's up axis ("+Y" default, "+Z" for most CAD and scan data); the object is
    turned so that it points along the world's +Y."""

    mesh: "Mesh"
    material: Material | None = None
    translate: Vec3 = (0.0, 0.0, 0.0)
    rotate: Vec3 = (0.0, 0.0, 0.0)  # degrees about X, then Y, then Z
    scale: Vec3 = (1.0, 1.0, 1.0)
    up: str = "+Y"
    cast_shadows: bool = True  # it hides lights that cast shadows from what lies behind it
    receive_shadows: bool = True  # its surface is darkened where such a light is hidden

    def __post_init__(self) -> None:
        for key in ("cast_shadows", "receive_shadows"):
            set_fields(self, **{key: boolean(getattr(self, key), f"object.{key}")})
        if not isinstance(self.mesh, Mesh):
            raise SceneError(f"object.mesh: expected a Mesh, got {type(self.mesh).__name__}: {shown(self.mesh)}")
        if self.material is not None and not isinstance(self.material, Material):
            raise SceneError(f"object.material: expected a Material, got {type(self.material).__name__}")
        set_fields(self, up=up_axis(self.up, "object.up"))
        scale = vec3(self.scale, "object.scale")
        if min(abs(s) for s in scale) == 0.0:
            raise SceneError(f"object.scale: components must be non-zero (the object would be flat), got {list(scale)}")
        if not all(MIN_SCALE <= abs(s) <= MAX_SCALE for s in scale):
            raise SceneError(
                f"object.scale: components must be between {MIN_SCALE:g} and {MAX_SCALE:g} in size "
                f"(float32 model and normal matrices), got {list(scale)}"
            )
        set_fields(
            self,
            translate=vec3(self.translate, "object.translate"),
            rotate=vec3(self.rotate, "object.rotate"),
            scale=scale,
        )

    def world_from_model(self) -> np.ndarray:
        """The model matrix as a float64 4x4 numpy array (column vectors: p_world = M @
        p_model): translate · Rz · Ry · Rx · scale · translate(mesh.origin), in double precision.

        Rotations are about fixed axes, X first. Mesh positions are stored relative to
        mesh.origin (float32 keeps their precision that way); the last factor puts the
        origin back, in float64."""
        # (pyglm converts a *tuple* through float32: glm.dvec3(t) loses digits, glm.dvec3(*t) does not.)
        model = glm.translate(glm.dmat4(1.0), glm.dvec3(*self.translate))
        for degrees, axis in zip(reversed(self.rotate), _AXES_ZYX):
            if degrees:  # skip exact zeros so unrotated objects stay bit-exact
                model = glm.rotate(model, math.radians(degrees), axis)
        model = glm.scale(model, glm.dvec3(*self.scale))
        up_rotation = _UP_ROTATIONS[self.up]
        if up_rotation is not None:
            model = glm.rotate(model, math.radians(up_rotation[0]), glm.dvec3(*up_rotation[1]))
        return np.array(glm.translate(model, glm.dvec3(*self.mesh.origin)))

    def model_matrix(self) -> glm.dmat4:
        """Deprecated: `glm.dmat4(obj.world_from_model())` (one name per matrix)."""
        import warnings

        warnings.warn("SceneObject.model_matrix() is deprecated; use world_from_model()", DeprecationWarning, stacklevel=2)
        return glm.dmat4(self.world_from_model())

    def part_materials(self) -> tuple[Material, ...]:
        """The material each part of the mesh is drawn with (see `material`)."""
        if self.material is not None:
            return (self.material,) * len(self.mesh.parts)
        return tuple(part.material or _DEFAULT_MATERIAL for part in self.mesh.parts)

    @property
    def surface_material(self) -> Material:
        """The material of the first part: the one material of a single-material object."""
        return self.part_materials()[0]



_DEFAULT_MATERIAL = Material()


# --------------------------------------------------------------------------- shading, scene


@dataclass(frozen=True)
class Shading:
    """The two independent axes (docs/conventions.md#two-independent-axes) plus OpenGL's light-model switches."""

    frequency: Frequency = "phong"
    reflection: Reflection = "phong"
    blinn_exponent_scale: float = 1.0  # k_blinn: Blinn-Phong exponent = shininess × this
    local_viewer: bool = True
    two_sided: bool = False
    # Flat/Gouraud: clamp each vertex's (face's) color to [0, 1] before interpolation, as
    # OpenGL fixed-function does; default False is the seeds' GLSL (clamp per fragment only).
    clamp_vertex_colors: bool = False
    # "auto": each material's own colour space (glTF linear, everything else display);
    # "display" or "linear" for every material (scene/maps.py, docs/conventions.md).
    color_space: str = "auto"
    # Points, lines and edges (docs/primitives.md), in pixels of the image: a point is a
    # point_size square (a disc facing its normal when it has one), a line line_width wide;
    # `edges` draws every triangle's edges over the surfaces in edge_color, edge_width wide.
    point_size: float = 3.0
    line_width: float = 1.0
    edges: bool = False
    edge_color: Color = (0.0, 0.0, 0.0, 1.0)
    edge_width: float = 1.0

    def color_space_of(self, material: Material) -> str:
        """The colour space `material` is drawn in."""
        return material.color_space if self.color_space == "auto" else self.color_space

    def __post_init__(self) -> None:
        for key in ("local_viewer", "two_sided", "clamp_vertex_colors", "edges"):
            if not isinstance(getattr(self, key), bool):
                raise SceneError(f"shading.{key}: expected true or false, got {getattr(self, key)!r}")
        edge_color = color(self.edge_color, "shading.edge_color")
        if max(edge_color) > 1.0:
            raise SceneError(f"shading.edge_color: components must be between 0 and 1 (a colour on the image), got {list(edge_color)}")
        set_fields(self, edge_color=edge_color, **{
            key: number(getattr(self, key), f"shading.{key}", MIN_STROKE_PIXELS, MAX_STROKE_PIXELS)
            for key in ("point_size", "line_width", "edge_width")
        })
        set_fields(
            self,
            frequency=choice(self.frequency, "shading.frequency", FREQUENCIES),
            reflection=choice(self.reflection, "shading.reflection", REFLECTIONS),
            color_space=choice(self.color_space, "shading.color_space", SCENE_COLOR_SPACES),
            blinn_exponent_scale=number(
                self.blinn_exponent_scale, "shading.blinn_exponent_scale", 0.0, MAX_EXPONENT
            ),
        )



@dataclass(frozen=True)
class BareMesh:
    """How a bare mesh's scene was made (the policy: scene/view/bare_mesh.py), recorded so
    that a view changing it need not guess: its camera's near and far enclose the object, and
    `viewer_lights` are the lights made for that camera (None: the file's own lights). A
    view that moves the camera makes both again, the lights only while the scene's lights
    are still these (lights a view or a caller replaced stay)."""

    viewer_lights: tuple[Light, ...] | None = None


@dataclass(frozen=True)
class Scene:
    """Everything one frame draws: objects, lights, camera, shading settings, the global
    ambient, the output size and background, antialiasing samples and shadow settings.
    Frozen, like all it holds: a renderer may keep what it prepared for one Scene object
    (render/gpu/frame_plans.py); a changed scene is a new object (dataclasses.replace)."""

    objects: tuple[SceneObject, ...] = ()
    lights: tuple[Light, ...] = ()
    camera: Camera = field(default_factory=Camera)
    shading: Shading = field(default_factory=Shading)
    ambient: Color = (0.2, 0.2, 0.2, 1.0)  # global ambient (GL_LIGHT_MODEL_AMBIENT)
    size: tuple[int, int] = (512, 512)  # width, height
    background: Color = (0.0, 0.0, 0.0, 1.0)
    # Antialiasing: MSAA samples per pixel, 1 (off: pixel-comparable with the GL references) or 4.
    samples: int = 1
    bare_mesh: BareMesh | None = None  # a bare mesh's scene: what the viewer made (None: a scene file's, or code's)
    # How the GPU approximates shadows (scene/shadows.py); which lights cast them is each light's `shadows`.
    shadows: ShadowSettings = field(default_factory=ShadowSettings)

    def __post_init__(self) -> None:
        if self.samples not in SAMPLE_COUNTS or isinstance(self.samples, bool):
            raise SceneError(f"output.samples: expected 1 (no antialiasing) or 4 (MSAA), got {shown(self.samples)}")
        # 4.0 and numpy integers compare equal to 4 but wgpu needs a Python int.
        set_fields(self, samples=int(self.samples))
        for key in ("objects", "lights"):
            value = getattr(self, key)
            if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
                raise SceneError(f"{key}: expected a list, got {shown(value)}")
        objects = tuple(self.objects)
        lights = tuple(self.lights)
        if len(lights) > MAX_LIGHTS:
            raise SceneError(
                f"lights: {len(lights)} lights; at most {MAX_LIGHTS} are supported "
                "(their uniforms must fit the GPU's 64 KiB uniform buffer)"
            )
        if len(objects) > MAX_OBJECTS:
            raise SceneError(f"objects: {len(objects)} objects; at most {MAX_OBJECTS} are supported (one draw each)")
        for index, obj in enumerate(objects):
            if not isinstance(obj, SceneObject):
                raise SceneError(f"objects[{index}]: expected a SceneObject, got {type(obj).__name__}")
        for index, light in enumerate(lights):
            if not isinstance(light, (DirectionalLight, PositionalLight, SpotLight)):
                raise SceneError(f"lights[{index}]: expected a light, got {type(light).__name__}")
        if not isinstance(self.camera, Camera):
            raise SceneError(f"camera: expected a Camera, got {type(self.camera).__name__}")
        if not isinstance(self.shading, Shading):
            raise SceneError(f"shading: expected a Shading, got {type(self.shading).__name__}")
        if self.bare_mesh is not None and not isinstance(self.bare_mesh, BareMesh):
            raise SceneError(f"bare_mesh: expected a BareMesh or None, got {type(self.bare_mesh).__name__}")
        if not isinstance(self.shadows, ShadowSettings):
            raise SceneError(f"shadows: expected ShadowSettings, got {type(self.shadows).__name__}")
        background = color(self.background, "output.background")
        if max(background) > 1.0:
            raise SceneError(f"output.background: components must be between 0 and 1, got {list(background)}")
        set_fields(
            self,
            objects=objects,
            lights=lights,
            ambient=color(self.ambient, "ambient.color"),
            size=image_size(self.size),
            background=background,
        )
        self._check_eye_space()

    def _check_eye_space(self) -> None:
        """Every object's bounding box, seen from the camera, within ±MAX_EYE_COORDINATE:
        the GPU works in float32 eye space, where farther coordinates overflow."""
        view = self.camera.eye_from_world()
        for index, obj in enumerate(self.objects):
            lower, upper = obj.mesh.relative_bounds
            corners = np.array(
                [[x, y, z, 1.0] for x in (lower[0], upper[0]) for y in (lower[1], upper[1]) for z in (lower[2], upper[2])]
            ).T
            with np.errstate(all="ignore"):  # an overflow is caught just below, underflow is harmless
                eye = (view @ obj.world_from_model()) @ corners
                reach = float(np.abs(eye[:3]).max())
            if not reach <= MAX_EYE_COORDINATE:
                raise SceneError(
                    f"objects[{index}] ({obj.mesh.name}): seen from the camera its coordinates reach {reach:.3g}; "
                    f"at most {MAX_EYE_COORDINATE:g} are supported (float32); scale it down or move the camera"
                )


def check_scene_argument(scene: object, where: str) -> None:
    """A clear error for a caller who passes something other than a Scene (a dict, a path)."""
    if not isinstance(scene, Scene):
        hint = " (load a scene file with load_scene(path))" if isinstance(scene, (str, bytes)) or hasattr(scene, "__fspath__") else ""
        raise SceneError(f"{where}: expected a Scene, got {type(scene).__name__}{hint}")


# --------------------------------------------------------------------------- shadows (scene/shadows.py)


def shadowing_lights(scene: Scene) -> tuple[int, ...]:
    """Indices of the scene's lights that cast shadows, in scene order."""
    return tuple(index for index, light in enumerate(scene.lights) if light.shadows)


def has_shadows(scene: Scene) -> bool:
    """Whether anything in the scene can be shadowed: a light casts, some object casts and
    some object receives. Without that, a frame has no shadow pass and no shadow code."""
    return (
        bool(shadowing_lights(scene))
        and any(obj.cast_shadows for obj in scene.objects)
        and any(obj.receive_shadows for obj in scene.objects)
    )


def every_light_casts(scene: Scene) -> Scene:
    """The scene with `shadows = true` on every light: what `--shadows` means."""
    return replace(scene, lights=tuple(replace(light, shadows=True) for light in scene.lights))
