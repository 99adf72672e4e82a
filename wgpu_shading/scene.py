"""Scene description: plain, immutable dataclasses that validate themselves.

A scene is what SPEC §11's TOML file describes: output, shading settings, a camera,
global ambient light, lights and objects. Everything here is in world space and in
float64; conversion to the GPU's float32 eye space happens in `uniforms.py`.

Valid ranges (enforced on construction, so a bad value fails loudly and early):
  colors        RGBA or RGB (alpha 1), every component finite and >= 0, alpha <= 1
  positions     finite, |coordinate| <= 1e15
  directions    finite and not zero (they are normalized when used)
  shininess     0 .. 1e6 (0 means x^0 = 1: a uniform specular term on the lit side)
  attenuation   constant, linear, quadratic: each finite and >= 0, not all zero
  spot cutoff   0 .. 90 degrees; spot exponent 0 .. 1e6
  fov_y         strictly between 0 and 180 degrees; 0 < near < far
  scale         every component finite and non-zero (negative mirrors)
  size          1 .. 16384 pixels per side
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, Sequence, Union

import numpy as np

from .errors import SceneError

if TYPE_CHECKING:  # pragma: no cover
    import os
    from pathlib import Path

    from .meshes import Mesh

Color = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]

Frequency = Literal["flat", "gouraud", "phong"]
Reflection = Literal["phong", "blinn-phong"]
TextureMode = Literal["modulate", "modulate_all", "blend"]

FREQUENCIES: tuple[str, ...] = ("flat", "gouraud", "phong")
REFLECTIONS: tuple[str, ...] = ("phong", "blinn-phong")
TEXTURE_MODES: tuple[str, ...] = ("modulate", "modulate_all", "blend")

MAX_COORDINATE = 1e15
MAX_EXPONENT = 1e6
MAX_IMAGE_SIDE = 16384


# --------------------------------------------------------------------------- validation


def _numbers(value: object, name: str, lengths: Sequence[int]) -> tuple[float, ...]:
    """A tuple of finite floats of one of the allowed lengths, or a SceneError naming `name`."""
    expected = " or ".join(str(n) for n in lengths)
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise SceneError(f"{name}: expected a list of {expected} numbers, got {value!r}")
    items = list(value)  # type: ignore[arg-type]
    if len(items) not in lengths:
        raise SceneError(f"{name}: expected {expected} numbers, got {len(items)}: {value!r}")
    numbers = []
    for item in items:
        if isinstance(item, bool) or not isinstance(item, (int, float, np.integer, np.floating)):
            raise SceneError(f"{name}: expected numbers, got {item!r} in {value!r}")
        number = float(item)
        if not math.isfinite(number):
            raise SceneError(f"{name}: expected finite numbers, got {number} in {value!r}")
        numbers.append(number)
    return tuple(numbers)


def color(value: object, name: str = "color") -> Color:
    """RGBA from RGB or RGBA; components >= 0, alpha <= 1."""
    numbers = _numbers(value, name, (3, 4))
    if len(numbers) == 3:
        numbers = numbers + (1.0,)
    if min(numbers) < 0.0:
        raise SceneError(f"{name}: color components must be >= 0, got {list(numbers)}")
    if numbers[3] > 1.0:
        raise SceneError(f"{name}: alpha must be between 0 and 1, got {numbers[3]}")
    return numbers  # type: ignore[return-value]


def vec3(value: object, name: str) -> Vec3:
    numbers = _numbers(value, name, (3,))
    if max(abs(n) for n in numbers) > MAX_COORDINATE:
        raise SceneError(f"{name}: coordinates must be within ±{MAX_COORDINATE:g}, got {list(numbers)}")
    return numbers  # type: ignore[return-value]


def direction(value: object, name: str) -> Vec3:
    numbers = vec3(value, name)
    if math.hypot(*numbers) == 0.0:
        raise SceneError(f"{name}: a direction must not be the zero vector")
    return numbers


def number(value: object, name: str, low: float, high: float, *, low_open: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise SceneError(f"{name}: expected a number, got {value!r}")
    result = float(value)
    too_low = result <= low if low_open else result < low
    if not math.isfinite(result) or too_low or result > high:
        bracket = "(" if low_open else "["
        raise SceneError(f"{name}: expected a number in {bracket}{low:g}, {high:g}], got {value!r}")
    return result


def choice(value: object, name: str, options: Sequence[str]) -> str:
    if value not in options:
        raise SceneError(f"{name}: expected one of {', '.join(map(repr, options))}, got {value!r}")
    return str(value)


def _set(instance: object, **values: object) -> None:
    """Assign normalized values on a frozen dataclass during __post_init__."""
    for key, value in values.items():
        object.__setattr__(instance, key, value)


# --------------------------------------------------------------------------- camera


def _cross(a, b) -> np.ndarray:
    """np.cross for two 3-vectors, bit for bit (the same products and differences), at a
    twentieth of the cost: np.cross's axis handling is most of a frame's CPU preparation."""
    a0, a1, a2 = (float(v) for v in a)
    b0, b1, b2 = (float(v) for v in b)
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


@dataclass(frozen=True)
class Camera:
    """A perspective camera (gluLookAt + gluPerspective)."""

    eye: Vec3 = (0.0, 0.0, 3.0)
    target: Vec3 = (0.0, 0.0, 0.0)
    up: Vec3 = (0.0, 1.0, 0.0)
    fov_y: float = 45.0  # degrees, vertical
    near: float = 0.1
    far: float = 100.0

    def __post_init__(self) -> None:
        eye = vec3(self.eye, "camera.eye")
        target = vec3(self.target, "camera.target")
        up = direction(self.up, "camera.up")
        fov_y = number(self.fov_y, "camera.fov_y", 0.0, 180.0, low_open=True)
        if fov_y >= 180.0:
            raise SceneError(f"camera.fov_y: expected less than 180 degrees, got {fov_y}")
        near = number(self.near, "camera.near", 0.0, math.inf, low_open=True)
        far = number(self.far, "camera.far", 0.0, math.inf, low_open=True)
        if not far > near:
            raise SceneError(f"camera.far ({far:g}) must be greater than camera.near ({near:g})")
        forward = np.subtract(target, eye)
        distance = float(np.linalg.norm(forward))
        scale = max(float(np.abs(eye).max()), float(np.abs(target).max()), 1.0)
        if distance <= 1e-12 * scale:
            raise SceneError(f"camera: eye {list(eye)} and target {list(target)} coincide; the view direction is undefined")
        up_unit = np.asarray(up) / np.linalg.norm(up)
        if np.linalg.norm(np.cross(forward / distance, up_unit)) < 1e-9:
            raise SceneError(f"camera.up {list(up)} is parallel to the view direction; pick an up vector that is not")
        _set(self, eye=eye, target=target, up=up, fov_y=fov_y, near=near, far=far)

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit right, up and backward (eye-space +x, +y, +z) axes in world space, float64."""
        backward = np.subtract(self.eye, self.target)
        backward = backward / np.linalg.norm(backward)
        right = _cross(self.up, backward)
        right = right / np.linalg.norm(right)
        true_up = _cross(backward, right)
        return right, true_up, backward

    def eye_from_world(self) -> np.ndarray:
        """The view matrix (gluLookAt), float64 4x4, column vectors."""
        right, true_up, backward = self.basis()
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, true_up, backward
        view[:3, 3] = -view[:3, :3] @ np.asarray(self.eye)
        return view


# --------------------------------------------------------------------------- lights


def _light_colors(light: object, prefix: str) -> dict[str, Color]:
    return {
        key: color(getattr(light, key), f"{prefix}.{key}") for key in ("ambient", "diffuse", "specular")
    }


def _attenuation(value: object, name: str) -> Vec3:
    coefficients = _numbers(value, name, (3,))
    if min(coefficients) < 0.0:
        raise SceneError(f"{name}: coefficients must be >= 0, got {list(coefficients)}")
    if max(coefficients) == 0.0:
        raise SceneError(
            f"{name}: (0, 0, 0) divides by zero everywhere; use (1, 0, 0) for no attenuation"
        )
    return coefficients  # type: ignore[return-value]


@dataclass(frozen=True)
class DirectionalLight:
    """A light at infinity (sunlight): `direction` is the way the light travels, in world space."""

    direction: Vec3 = (0.0, 0.0, -1.0)
    ambient: Color = (0.0, 0.0, 0.0, 1.0)
    diffuse: Color = (1.0, 1.0, 1.0, 1.0)
    specular: Color = (1.0, 1.0, 1.0, 1.0)

    kind = "directional"

    def __post_init__(self) -> None:
        _set(self, direction=direction(self.direction, "light.direction"), **_light_colors(self, "light"))


@dataclass(frozen=True)
class PositionalLight:
    """A point light at `position` (world space) with OpenGL attenuation 1/(kc + kl d + kq d²)."""

    position: Vec3 = (5.0, 2.0, 2.0)
    ambient: Color = (0.0, 0.0, 0.0, 1.0)
    diffuse: Color = (1.0, 1.0, 1.0, 1.0)
    specular: Color = (1.0, 1.0, 1.0, 1.0)
    attenuation: Vec3 = (1.0, 0.0, 0.0)  # constant, linear, quadratic

    kind = "positional"

    def __post_init__(self) -> None:
        _set(
            self,
            position=vec3(self.position, "light.position"),
            attenuation=_attenuation(self.attenuation, "light.attenuation"),
            **_light_colors(self, "light"),
        )


@dataclass(frozen=True)
class SpotLight:
    """A positional light limited to a cone around `direction` (the way the light travels).

    Inside the cone the intensity is cos(φ)^exponent, φ the angle off the axis; outside
    (φ >= cutoff) it is zero. The cone is open: cutoff 0 gives no light at all.
    """

    position: Vec3 = (5.0, 2.0, -3.0)
    direction: Vec3 = (0.0, 0.0, -1.0)
    cutoff: float = 20.0  # degrees, 0..90
    exponent: float = 10.0
    ambient: Color = (0.0, 0.0, 0.0, 1.0)
    diffuse: Color = (1.0, 1.0, 1.0, 1.0)
    specular: Color = (1.0, 1.0, 1.0, 1.0)
    attenuation: Vec3 = (1.0, 0.0, 0.0)

    kind = "spot"

    def __post_init__(self) -> None:
        _set(
            self,
            position=vec3(self.position, "light.position"),
            direction=direction(self.direction, "light.direction"),
            cutoff=number(self.cutoff, "light.cutoff", 0.0, 90.0),
            exponent=number(self.exponent, "light.exponent", 0.0, MAX_EXPONENT),
            attenuation=_attenuation(self.attenuation, "light.attenuation"),
            **_light_colors(self, "light"),
        )


Light = Union[DirectionalLight, PositionalLight, SpotLight]
LIGHT_TYPES: dict[str, type] = {
    "directional": DirectionalLight,
    "positional": PositionalLight,
    "spot": SpotLight,
}


# --------------------------------------------------------------------------- materials, textures


@dataclass(frozen=True, eq=False)
class Texture:
    """An RGBA8 image (rows top to bottom) sampled with the mesh's UVs (v = 0 at the bottom)."""

    pixels: np.ndarray
    name: str = ""

    def __post_init__(self) -> None:
        pixels = np.asarray(self.pixels)
        if pixels.ndim == 2:
            pixels = np.repeat(pixels[:, :, None], 3, axis=2)
        if pixels.ndim != 3 or pixels.shape[2] not in (1, 2, 3, 4) or 0 in pixels.shape[:2]:
            raise SceneError(f"texture {self.name!r}: expected an H×W×(1..4) image, got shape {pixels.shape}")
        if pixels.dtype != np.uint8:
            if pixels.dtype.kind == "f":
                if not np.isfinite(pixels).all():
                    raise SceneError(f"texture {self.name!r}: pixel values must be finite")
                pixels = np.round(np.clip(pixels, 0.0, 1.0) * 255.0)
            elif pixels.dtype == np.uint16:
                pixels = pixels // 257
            pixels = pixels.astype(np.uint8)
        channels = pixels.shape[2]
        if channels == 1:
            pixels = np.repeat(pixels, 3, axis=2)
        elif channels == 2:  # luminance + alpha
            pixels = np.concatenate([np.repeat(pixels[:, :, :1], 3, axis=2), pixels[:, :, 1:]], axis=2)
        if pixels.shape[2] == 3:
            pixels = np.concatenate([pixels, np.full(pixels.shape[:2] + (1,), 255, np.uint8)], axis=2)
        pixels = np.ascontiguousarray(pixels)
        pixels.setflags(write=False)
        _set(self, pixels=pixels)

    @classmethod
    def from_file(cls, path: str | "os.PathLike[str]") -> "Texture":
        import imageio.v3 as iio  # lazy: imageio costs ~0.1 s to import

        try:
            pixels = iio.imread(path)
        except FileNotFoundError:
            raise SceneError(f"texture {str(path)!r}: file not found") from None
        except Exception as error:  # imageio raises many kinds for unreadable files
            raise SceneError(f"texture {str(path)!r}: cannot read image ({error})") from None
        if pixels.ndim == 4:  # animated formats: first frame
            pixels = pixels[0]
        return cls(pixels, name=str(path))


@dataclass(frozen=True)
class Material:
    """OpenGL material; the defaults are OpenGL's (grey diffuse, no specular)."""

    ambient: Color = (0.2, 0.2, 0.2, 1.0)
    diffuse: Color = (0.8, 0.8, 0.8, 1.0)
    specular: Color = (0.0, 0.0, 0.0, 1.0)
    emission: Color = (0.0, 0.0, 0.0, 1.0)
    shininess: float = 0.0  # OpenGL units (the table's value × 128)
    texture: Texture | None = None
    texture_mode: TextureMode = "modulate"
    name: str = ""

    def __post_init__(self) -> None:
        prefix = f"material {self.name!r}" if self.name else "material"
        _set(
            self,
            ambient=color(self.ambient, f"{prefix}.ambient"),
            diffuse=color(self.diffuse, f"{prefix}.diffuse"),
            specular=color(self.specular, f"{prefix}.specular"),
            emission=color(self.emission, f"{prefix}.emission"),
            shininess=number(self.shininess, f"{prefix}.shininess", 0.0, MAX_EXPONENT),
            texture_mode=choice(self.texture_mode, f"{prefix}.texture_mode", TEXTURE_MODES),
        )
        if self.texture is not None and not isinstance(self.texture, Texture):
            raise SceneError(f"{prefix}.texture: expected a Texture, got {type(self.texture).__name__}")

    @property
    def has_specular(self) -> bool:
        return max(self.specular[:3]) > 0.0

    @property
    def has_emission(self) -> bool:
        return max(self.emission[:3]) > 0.0


# --------------------------------------------------------------------------- objects


def _rotation_xyz(degrees: Vec3) -> np.ndarray:
    """Rotate about X, then Y, then Z (fixed axes): R = Rz · Ry · Rx."""
    ax, ay, az = np.radians(degrees)
    cx, sx, cy, sy, cz, sz = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay), np.cos(az), np.sin(az)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


@dataclass(frozen=True)
class SceneObject:
    """A mesh placed in the world: model = translate · rotate · scale."""

    mesh: "Mesh"
    material: Material = field(default_factory=Material)
    translate: Vec3 = (0.0, 0.0, 0.0)
    rotate: Vec3 = (0.0, 0.0, 0.0)  # degrees about X, then Y, then Z
    scale: Vec3 = (1.0, 1.0, 1.0)

    def __post_init__(self) -> None:
        from .meshes import Mesh

        if not isinstance(self.mesh, Mesh):
            raise SceneError(f"object.mesh: expected a Mesh, got {type(self.mesh).__name__}")
        if not isinstance(self.material, Material):
            raise SceneError(f"object.material: expected a Material, got {type(self.material).__name__}")
        scale = vec3(self.scale, "object.scale")
        if min(abs(s) for s in scale) == 0.0:
            raise SceneError(f"object.scale: components must be non-zero (the object would be flat), got {list(scale)}")
        _set(
            self,
            translate=vec3(self.translate, "object.translate"),
            rotate=vec3(self.rotate, "object.rotate"),
            scale=scale,
        )

    def world_from_model(self) -> np.ndarray:
        """float64 4x4 for the mesh's stored (origin-relative) vertex positions."""
        model = np.eye(4)
        model[:3, :3] = _rotation_xyz(self.rotate) @ np.diag(self.scale)
        model[:3, 3] = self.translate
        # Mesh positions are stored relative to mesh.origin (float32 keeps precision that way);
        # put the origin back here, in float64.
        model[:3, 3] += model[:3, :3] @ np.asarray(self.mesh.origin)
        return model


# --------------------------------------------------------------------------- shading, scene


@dataclass(frozen=True)
class Shading:
    """The two independent axes of SPEC §2 plus OpenGL's light-model switches."""

    frequency: Frequency = "phong"
    reflection: Reflection = "phong"
    blinn_exponent_scale: float = 1.0  # k_blinn: Blinn-Phong exponent = shininess × this
    local_viewer: bool = True
    two_sided: bool = False

    def __post_init__(self) -> None:
        for key in ("local_viewer", "two_sided"):
            if not isinstance(getattr(self, key), bool):
                raise SceneError(f"shading.{key}: expected true or false, got {getattr(self, key)!r}")
        _set(
            self,
            frequency=choice(self.frequency, "shading.frequency", FREQUENCIES),
            reflection=choice(self.reflection, "shading.reflection", REFLECTIONS),
            blinn_exponent_scale=number(
                self.blinn_exponent_scale, "shading.blinn_exponent_scale", 0.0, MAX_EXPONENT
            ),
        )


def image_size(value: object, name: str = "output.size") -> tuple[int, int]:
    numbers = _numbers(value, name, (2,))
    if any(n != int(n) for n in numbers):
        raise SceneError(f"{name}: expected whole numbers of pixels, got {list(numbers)}")
    width, height = int(numbers[0]), int(numbers[1])
    if not (1 <= width <= MAX_IMAGE_SIDE and 1 <= height <= MAX_IMAGE_SIDE):
        raise SceneError(f"{name}: width and height must be between 1 and {MAX_IMAGE_SIDE}, got {width}×{height}")
    return width, height


def output_path(path: "os.PathLike[str] | str", suffixes: Sequence[str]) -> "Path":
    """A file to write: one of `suffixes`, in a folder that exists (checked before any work)."""
    from pathlib import Path

    path = Path(path)
    if path.suffix.lower() not in suffixes:
        raise SceneError(f"output {str(path)!r}: unsupported format; use one of {', '.join(suffixes)}")
    if not path.parent.exists():
        raise SceneError(f"output {str(path)!r}: folder {str(path.parent)!r} does not exist")
    return path


@dataclass(frozen=True)
class Scene:
    objects: tuple[SceneObject, ...] = ()
    lights: tuple[Light, ...] = ()
    camera: Camera = field(default_factory=Camera)
    shading: Shading = field(default_factory=Shading)
    ambient: Color = (0.2, 0.2, 0.2, 1.0)  # global ambient (GL_LIGHT_MODEL_AMBIENT)
    size: tuple[int, int] = (512, 512)  # width, height
    background: Color = (0.0, 0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        objects = tuple(self.objects)
        lights = tuple(self.lights)
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
        _set(
            self,
            objects=objects,
            lights=lights,
            ambient=color(self.ambient, "ambient.color"),
            size=image_size(self.size),
            background=color(self.background, "output.background"),
        )
