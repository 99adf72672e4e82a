"""Materials and textures (OpenGL material model; texture modes: docs/conventions.md#textures)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .maps import COLOR_SPACES, MAP_FIELDS, TEXTURE_ENCODINGS
from .values import MAX_EXPONENT, MAX_IMAGE_SIDE, TEXTURE_MODES, Color, TextureMode, set_fields, choice, color, number


# Texture side limit: WebGPU's default max-texture-dimension-2d; the renderer also checks
# its adapter's own limit when it uploads.
MAX_TEXTURE_SIDE = MAX_IMAGE_SIDE
# What a coordinate outside [0, 1] samples (glTF's REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).
WRAP_MODES = ("repeat", "clamp", "mirror")
# Texture coordinate sets a texture may read: Mesh.uvs and three of Mesh.extra_uvs. WebGPU
# guarantees 8 vertex buffers to a draw: positions, normals, uvs, colours, tangents, and
# these three (docs/primitives.md#texture-coordinate-sets).
MAX_UV_SET = 3


@dataclass(frozen=True, eq=False)
class Texture:
    """An RGBA8 image (rows top to bottom) sampled with the mesh's UVs (v = 0 at the bottom)."""

    pixels: np.ndarray
    name: str = ""
    nearest: bool = False  # nearest-neighbour sampling (glTF NEAREST filters), else linear + mipmaps
    wrap: tuple[str, str] = ("repeat", "repeat")  # u and v outside [0, 1]: one of WRAP_MODES each
    # How colour images store their values: "srgb" (every image file unless it says otherwise;
    # decoded on the GPU in linear colour space) or "linear". Data maps ignore it.
    encoding: str = "srgb"
    # The mesh's texture coordinates it is sampled with: 0 = Mesh.uvs, k ≥ 1 = Mesh.extra_uvs
    # [:, k − 1] (a glTF texture's texCoord with its own transform: docs/primitives.md).
    uv_set: int = 0

    def __post_init__(self) -> None:
        if isinstance(self.uv_set, bool) or not isinstance(self.uv_set, (int, np.integer)) or not 0 <= self.uv_set <= MAX_UV_SET:
            raise SceneError(f"texture {self.name!r}.uv_set: expected a whole number from 0 to {MAX_UV_SET}, got {self.uv_set!r}")
        set_fields(self, uv_set=int(self.uv_set))
        set_fields(self, encoding=choice(self.encoding, f"texture {self.name!r}.encoding", TEXTURE_ENCODINGS))
        if not isinstance(self.nearest, bool):
            raise SceneError(f"texture {self.name!r}.nearest: expected true or false, got {self.nearest!r}")
        if isinstance(self.wrap, str) or len(tuple(self.wrap)) != 2:
            raise SceneError(f"texture {self.name!r}.wrap: expected two of {', '.join(WRAP_MODES)} (u, v), got {self.wrap!r}")
        set_fields(self, wrap=tuple(choice(mode, f"texture {self.name!r}.wrap", WRAP_MODES) for mode in self.wrap))
        given = self.pixels
        pixels = np.asarray(self.pixels)
        if pixels.ndim == 2:
            pixels = np.repeat(pixels[:, :, None], 3, axis=2)
        if pixels.ndim != 3 or pixels.shape[2] not in (1, 2, 3, 4) or 0 in pixels.shape[:2]:
            raise SceneError(f"texture {self.name!r}: expected an H×W×(1..4) image, got shape {pixels.shape}")
        if max(pixels.shape[:2]) > MAX_TEXTURE_SIDE:
            height, width = pixels.shape[:2]
            raise SceneError(
                f"texture {self.name!r}: {width}×{height} pixels; at most {MAX_TEXTURE_SIDE} per side are supported"
            )
        if pixels.dtype != np.uint8:
            if pixels.dtype == np.bool_:  # 1-bit images: True is white, not 1/255
                pixels = pixels.astype(np.uint8) * 255
            elif pixels.dtype.kind == "f":
                if not np.isfinite(pixels).all():
                    raise SceneError(f"texture {self.name!r}: pixel values must be finite")
                pixels = np.round(np.clip(pixels, 0.0, 1.0) * 255.0)
            elif pixels.dtype == np.uint16:
                pixels = pixels // 257
            elif pixels.dtype.kind not in "iu" or pixels.min() < 0 or pixels.max() > 255:
                raise SceneError(
                    f"texture {self.name!r}: expected 8-bit, 16-bit, 1-bit or [0, 1] float pixels, got {pixels.dtype}"
                    + (f" values from {pixels.min()} to {pixels.max()}" if pixels.dtype.kind in "iu" else "")
                )
            pixels = pixels.astype(np.uint8)
        channels = pixels.shape[2]
        if channels == 1:
            pixels = np.repeat(pixels, 3, axis=2)
        elif channels == 2:  # luminance + alpha
            pixels = np.concatenate([np.repeat(pixels[:, :, :1], 3, axis=2), pixels[:, :, 1:]], axis=2)
        if pixels.shape[2] == 3:
            pixels = np.concatenate([pixels, np.full(pixels.shape[:2] + (1,), 255, np.uint8)], axis=2)
        # A snapshot: renderers cache the upload by identity, so the pixels must never change;
        # the caller's array is copied, never frozen behind its back.
        private = pixels.flags.owndata and not (isinstance(given, np.ndarray) and np.may_share_memory(pixels, given))
        if not pixels.flags.c_contiguous or not (private or (pixels.flags.owndata and not pixels.flags.writeable)):
            pixels = np.array(pixels, order="C", copy=True)
        pixels.setflags(write=False)
        set_fields(self, pixels=pixels)


ALPHA_MODES = ("opaque", "mask", "blend")


@dataclass(frozen=True)
class Material:
    """OpenGL material; the defaults are OpenGL's (grey diffuse, no specular).

    Alpha (docs/conventions.md#the-lighting-equation): the colors' alphas are kept (the uniform layout contract) but make
    nothing translucent unless `alpha_mode` asks: "opaque" (default) writes alpha 1,
    "mask" discards fragments whose alpha (diffuse × texel) is below `alpha_cutoff`,
    "blend" blends over what is behind (glTF's alphaMode). `unlit`: the diffuse color
    (× texture × vertex color) as is, no lighting (KHR_materials_unlit).
    """

    ambient: Color = (0.2, 0.2, 0.2, 1.0)
    diffuse: Color = (0.8, 0.8, 0.8, 1.0)
    specular: Color = (0.0, 0.0, 0.0, 1.0)
    emission: Color = (0.0, 0.0, 0.0, 1.0)
    shininess: float = 0.0  # OpenGL units (the table's value × 128)
    texture: Texture | None = None
    texture_mode: TextureMode = "modulate"
    name: str = ""
    alpha_mode: str = "opaque"
    alpha_cutoff: float = 0.5
    unlit: bool = False
    # Maps (scene/maps.py): optional Textures sampled with the mesh's UVs, and their factors.
    normal_map: Texture | None = None
    normal_scale: float = 1.0  # glTF normalTexture.scale, MTL norm -bm: × the map's x and y
    bump_map: Texture | None = None
    bump_scale: float = 1.0  # MTL -bm: × the height map's depth
    specular_map: Texture | None = None
    shininess_map: Texture | None = None
    emissive_map: Texture | None = None
    occlusion_map: Texture | None = None
    occlusion_strength: float = 1.0  # glTF occlusionTexture.strength
    alpha_map: Texture | None = None
    # "display" (OpenGL: colours are what the screen shows) or "linear" (glTF: linear light,
    # sRGB-encoded output); Shading.color_space may override it for the whole scene.
    color_space: str = "display"
    # glTF doubleSided (§3.9.6): False culls back faces, True lights both sides (the back
    # with the flipped normal); None (classic materials) follows the scene's two_sided.
    double_sided: bool | None = None

    def __post_init__(self) -> None:
        prefix = f"material {self.name!r}" if self.name else "material"
        set_fields(
            self,
            ambient=color(self.ambient, f"{prefix}.ambient"),
            diffuse=color(self.diffuse, f"{prefix}.diffuse"),
            specular=color(self.specular, f"{prefix}.specular"),
            emission=color(self.emission, f"{prefix}.emission"),
            shininess=number(self.shininess, f"{prefix}.shininess", 0.0, MAX_EXPONENT),
            texture_mode=choice(self.texture_mode, f"{prefix}.texture_mode", TEXTURE_MODES),
            alpha_mode=choice(self.alpha_mode, f"{prefix}.alpha_mode", ALPHA_MODES),
            alpha_cutoff=number(self.alpha_cutoff, f"{prefix}.alpha_cutoff", 0.0, 1.0),
            normal_scale=number(self.normal_scale, f"{prefix}.normal_scale", -1e3, 1e3),
            bump_scale=number(self.bump_scale, f"{prefix}.bump_scale", -1e3, 1e3),
            occlusion_strength=number(self.occlusion_strength, f"{prefix}.occlusion_strength", 0.0, 1.0),
            color_space=choice(self.color_space, f"{prefix}.color_space", COLOR_SPACES),
        )
        for key in MAP_FIELDS:
            value = getattr(self, key)
            if value is not None and not isinstance(value, Texture):
                raise SceneError(f"{prefix}.{key}: expected a Texture, got {type(value).__name__}")
        if not isinstance(self.unlit, bool):
            raise SceneError(f"{prefix}.unlit: expected true or false, got {self.unlit!r}")
        if self.double_sided is not None and not isinstance(self.double_sided, bool):
            raise SceneError(f"{prefix}.double_sided: expected true, false or None, got {self.double_sided!r}")
        if self.texture is not None and not isinstance(self.texture, Texture):
            raise SceneError(f"{prefix}.texture: expected a Texture, got {type(self.texture).__name__}")

    @property
    def has_specular(self) -> bool:
        return max(self.specular[:3]) > 0.0

    @property
    def has_emission(self) -> bool:
        return max(self.emission[:3]) > 0.0

    @property
    def maps(self) -> dict[str, Texture]:
        """The maps this material has, by field name (scene/maps.py)."""
        return {key: getattr(self, key) for key in MAP_FIELDS if getattr(self, key) is not None}

