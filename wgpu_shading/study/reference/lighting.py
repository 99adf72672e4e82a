"""The lighting equation of docs/conventions.md in float64, at arrays of eye-space
points: guarded power and normalize with the conventions' limits, the lights in eye space,
ambient + diffuse + specular per light, and the texture sampling and combine of docs/conventions.md#textures
with the final clamp. Shape-agnostic: the rasterized meshes (`shading.py`) and the
analytic shapes (`analytic.py`) both shade through `shade` and `combine`."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...scene import DirectionalLight, Material, PositionalLight, Scene, SpotLight
from .transforms import eye_from_world, transform_points

# --------------------------------------------------------------------------- constants from conventions.md

MIN_LENGTH_SQUARED = 1e-30  # |v|² at or below this is "zero length": normalize falls back
MIN_ATTENUATION_DENOMINATOR = 1e-20  # kc + kl·d + kq·d² is floored here
FALLBACK_NORMAL = np.array([0.0, 0.0, 1.0])  # eye space: faces the viewer
INFINITE_VIEWER = np.array([0.0, 0.0, 1.0])  # V when local_viewer is false


# --------------------------------------------------------------------------- guarded math


def guarded_power(base: np.ndarray, exponent: float | np.ndarray) -> np.ndarray:
    """max(base, 0)^exponent with the conventions' limits: base <= 0 gives 0 for every
    exponent (0^0 too); otherwise exponent <= 0 gives 1; otherwise min(base, 1)^exponent.
    Continuous in the exponent at 0, so float32 rounding a tiny exponent to 0 changes nothing."""
    base = np.asarray(base, dtype=np.float64)
    exponent = np.broadcast_to(np.asarray(exponent, dtype=np.float64), base.shape)
    positive_base = np.where(base > 0.0, np.minimum(base, 1.0), 1.0)  # 1.0: any safe value
    power = np.where(exponent <= 0.0, 1.0, positive_base**exponent)
    return np.where(base > 0.0, power, 0.0)


def safe_normalize(vectors: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """Rows of `vectors` scaled to unit length; rows with |v|² <= 1e-30 become `fallback`
    (one vector for all rows, or one per row)."""
    vectors = np.asarray(vectors, dtype=np.float64)
    length_squared = np.einsum("ij,ij->i", vectors, vectors)
    usable = length_squared > MIN_LENGTH_SQUARED
    scale = 1.0 / np.sqrt(np.where(usable, length_squared, 1.0))
    return np.where(usable[:, None], vectors * scale[:, None], np.broadcast_to(fallback, vectors.shape))


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot product of (N, 3) arrays (either may broadcast from (3,))."""
    return np.sum(a * b, axis=-1)


# --------------------------------------------------------------------------- lights


@dataclass(frozen=True)
class EyeLight:
    """One light in eye space, ready for the lighting equation."""

    kind: str  # directional | positional | spot
    ambient: np.ndarray  # RGB
    diffuse: np.ndarray
    specular: np.ndarray
    to_light: np.ndarray | None = None  # directional: unit vector towards the light
    position: np.ndarray | None = None  # positional, spot
    attenuation: tuple[float, float, float] = (1.0, 0.0, 0.0)
    range: float = 0.0  # positional, spot: glTF's cut-off distance (0: none)
    axis: np.ndarray | None = None  # spot: unit direction the light travels
    cutoff_chord_squared: float = 0.0  # spot: 4·sin²(cutoff/2)
    exponent: float = 0.0  # spot


def lights_in_eye_space(scene: Scene) -> list[EyeLight]:
    """World → eye space once per frame: positions with the full view matrix, directions
    with its rotation only."""
    view = eye_from_world(scene.camera)
    rotation = view[:3, :3]
    lights = []
    for light in scene.lights:
        colors = {key: np.asarray(getattr(light, key)[:3], dtype=np.float64) for key in ("ambient", "diffuse", "specular")}
        if isinstance(light, DirectionalLight):
            towards = rotation @ -np.asarray(light.direction, dtype=np.float64)  # light travels along direction
            lights.append(EyeLight("directional", to_light=towards / np.linalg.norm(towards), **colors))
            continue
        position = transform_points(view, np.asarray(light.position, dtype=np.float64)[None])[0]
        attenuation = tuple(float(c) for c in light.attenuation)
        if isinstance(light, SpotLight):
            axis = rotation @ np.asarray(light.direction, dtype=np.float64)
            lights.append(
                EyeLight(
                    "spot",
                    position=position,
                    attenuation=attenuation,
                    range=float(light.range),
                    axis=axis / np.linalg.norm(axis),
                    cutoff_chord_squared=4.0 * math.sin(math.radians(light.cutoff) / 2.0) ** 2,
                    exponent=float(light.exponent),
                    **colors,
                )
            )
        elif isinstance(light, PositionalLight):
            lights.append(EyeLight("positional", position=position, attenuation=attenuation, range=float(light.range), **colors))
    return lights


def attenuation_factor(coefficients: tuple[float, float, float], distance: np.ndarray, range_: float = 0.0) -> np.ndarray:
    """1 / max(kc + kl·d + kq·d², 1e-20): finite even for a light at the point with kc = 0;
    × KHR_lights_punctual's window clamp(1 − (d/range)⁴, 0, 1)² when range > 0."""
    kc, kl, kq = coefficients
    window = np.clip(1.0 - (distance / range_) ** 4, 0.0, 1.0) ** 2 if range_ > 0.0 else 1.0
    return window / np.maximum(kc + kl * distance + kq * distance**2, MIN_ATTENUATION_DENOMINATOR)


# --------------------------------------------------------------------------- the lighting equation


def view_vectors(points: np.ndarray, normals: np.ndarray, local_viewer: bool) -> np.ndarray:
    """V: towards the eye at the origin (local viewer; N when the eye is at the point), or
    the constant (0, 0, 1) of OpenGL's infinite viewer."""
    if local_viewer:
        return safe_normalize(-np.asarray(points, dtype=np.float64), normals)
    return np.broadcast_to(INFINITE_VIEWER, np.shape(points)).copy()


def specular_factor(normals, to_light, to_viewer, shininess: float, reflection: str, k_blinn: float) -> np.ndarray:
    """(R·V)^s for Phong reflection, (N·H)^(s·k_blinn) for Blinn-Phong, guarded."""
    if reflection == "phong":
        reflected = 2.0 * dot(normals, to_light)[:, None] * normals - to_light  # reflect(-L, N)
        return guarded_power(dot(reflected, to_viewer), shininess)
    # L = -V has no half vector: H = 0 makes N·H = 0, so no highlight.
    half = safe_normalize(to_light + to_viewer, np.zeros(3))
    return guarded_power(dot(normals, half), shininess * k_blinn)


def shade(
    points: np.ndarray, normals: np.ndarray, to_viewer: np.ndarray, scene: Scene, material: Material,
    *, ambient_scale: np.ndarray | None = None, shininess_scale: np.ndarray | None = None, with_emission: bool = True,
    visibility: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The lighting equation (docs/conventions.md) at N eye-space points with unit normals and unit view vectors, all (N, 3).

    Returns the ambient+diffuse+emission part and the specular part, (N, 3) each, unclamped
    (textures treat them apart; the clamp comes last, in `combine`). Maps
    (docs/conventions.md): `ambient_scale` (N,) multiplies the material's ambient
    (occlusion), `shininess_scale` (N,) its shininess; without `with_emission` the emission
    is left out (an emissive map adds it after the combine). `visibility` (lights, N) is
    each light's V_i: it scales that light's diffuse and specular terms, after
    attenuation and the spot factor; its ambient term is not shadowed.
    """
    points = np.asarray(points, dtype=np.float64)
    normals = np.asarray(normals, dtype=np.float64)
    to_viewer = np.asarray(to_viewer, dtype=np.float64)
    count = len(points)
    m_ambient, m_diffuse, m_specular, m_emission = (
        np.asarray(c[:3], dtype=np.float64) for c in (material.ambient, material.diffuse, material.specular, material.emission)
    )
    if not with_emission:
        m_emission = np.zeros(3)
    if ambient_scale is not None:
        m_ambient = np.asarray(ambient_scale, dtype=np.float64)[:, None] * m_ambient
    shininess = material.shininess if shininess_scale is None else material.shininess * np.asarray(shininess_scale)
    ambient_diffuse = m_emission + np.asarray(scene.ambient[:3]) * m_ambient * np.ones((count, 1))
    specular = np.zeros((count, 3))
    shading = scene.shading
    for index, light in enumerate(lights_in_eye_space(scene)):
        shadow = np.ones(count) if visibility is None else np.asarray(visibility[index], dtype=np.float64)
        if light.kind == "directional":
            to_light = np.broadcast_to(light.to_light, points.shape)
            scale = np.ones(count)
        else:
            offset = light.position - points
            # A light exactly at the point has no direction: light it as if from straight above.
            to_light = safe_normalize(offset, normals)
            scale = attenuation_factor(light.attenuation, np.sqrt(dot(offset, offset)), light.range)
            if light.kind == "spot":
                # Open cone, tested as a squared chord between -L and the axis (exact for tiny cutoffs).
                chord = -to_light - light.axis
                inside = dot(chord, chord) < light.cutoff_chord_squared
                spot = guarded_power(dot(-to_light, light.axis), light.exponent)
                scale = scale * np.where(inside, spot, 0.0)
        n_dot_l = dot(normals, to_light)
        ambient_diffuse += scale[:, None] * (
            light.ambient * m_ambient + (shadow * np.maximum(n_dot_l, 0.0))[:, None] * light.diffuse * m_diffuse
        )
        highlight = specular_factor(
            normals, to_light, to_viewer, shininess, shading.reflection, shading.blinn_exponent_scale
        )
        lit_side = n_dot_l > 0.0  # f_i: no highlight where the light does not reach
        specular += np.where(lit_side, shadow * scale * highlight, 0.0)[:, None] * light.specular * m_specular
    return ambient_diffuse, specular


def clamp_vertex_colors(ambient_diffuse: np.ndarray, specular: np.ndarray, texture_mode: str | None):
    """[shading] clamp_vertex_colors: OpenGL fixed-function's clamp of each vertex's color,
    before interpolation. The whole sum (GL_SINGLE_COLOR), or with the `modulate` texture
    mode (GL_SEPARATE_SPECULAR_COLOR) the primary and secondary colors apart."""
    if texture_mode == "modulate":
        return np.clip(ambient_diffuse, 0.0, 1.0), np.clip(specular, 0.0, 1.0)
    return np.clip(ambient_diffuse + specular, 0.0, 1.0), np.zeros_like(specular)


def combine(
    ambient_diffuse: np.ndarray, specular: np.ndarray, material: Material, texel: np.ndarray | None = None,
    *, specular_scale: np.ndarray | None = None, emitted: np.ndarray | None = None, alpha_scale: np.ndarray | None = None,
    srgb_output: bool = False,
) -> np.ndarray:
    """Texture combine (docs/conventions.md#textures) and the final clamp: (N, 4) RGBA.

    `texel` is the sampled RGBA in [0, 1] (N, 4), or None for an untextured material; the
    mode is material.texture_mode. Alpha (docs/conventions.md#the-lighting-equation) is 1 unless the material blends: then
    the diffuse alpha (× texel alpha). (A masked fragment below the cutoff is discarded on
    the GPU; the reference shows it opaque.)

    Maps (docs/conventions.md): `specular_scale` (N, 3) multiplies the specular part first,
    `emitted` (N, 3) is added after the texture combine, `alpha_scale` (N,) multiplies the
    alpha; `srgb_output` (linear colour space) encodes the clamped colour as sRGB.
    """
    if specular_scale is not None:
        specular = specular * specular_scale
    alpha = np.full(len(ambient_diffuse), float(material.diffuse[3]))
    if texel is None:
        rgb = ambient_diffuse + specular
    else:
        texel_rgb = texel[:, :3]
        mode = material.texture_mode
        if mode == "modulate":
            rgb = texel_rgb * ambient_diffuse + specular
        elif mode == "modulate_all":
            rgb = texel_rgb * (ambient_diffuse + specular)
        elif mode == "blend":
            rgb = 0.5 * texel_rgb + 0.5 * (ambient_diffuse + specular)
        else:
            raise ValueError(f"unknown texture mode {mode!r}")
        alpha = alpha * texel[:, 3]
    if emitted is not None:
        rgb = rgb + emitted
    if alpha_scale is not None:
        alpha = alpha * alpha_scale
    if material.alpha_mode != "blend":
        alpha = np.ones(len(ambient_diffuse))
    rgb = np.clip(rgb, 0.0, 1.0)
    if srgb_output:  # IEC 61966-2-1
        rgb = np.where(rgb <= 0.0031308, rgb * 12.92, 1.055 * np.maximum(rgb, 0.0031308) ** (1.0 / 2.4) - 0.055)
    return np.concatenate([rgb, alpha[:, None]], axis=1)


# --------------------------------------------------------------------------- textures


def sample_texture_bilinear(pixels: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Bilinear sample of level 0 with repeat wrap: (N, 4) RGBA in [0, 1].

    `pixels` is an (H, W, 4) uint8 image with row 0 at the top; v = 0 is the bottom row;
    texel (i, j) (j counted from the bottom) has its centre at ((i + 0.5)/W, (j + 0.5)/H).
    """
    image = np.asarray(pixels, dtype=np.float64) / 255.0
    height, width = image.shape[:2]
    uv = np.asarray(uv, dtype=np.float64)
    # Continuous texel coordinates whose integer values are texel centres.
    x = uv[:, 0] * width - 0.5
    y = uv[:, 1] * height - 0.5  # counted from the bottom row
    i0, j0 = np.floor(x), np.floor(y)
    fx, fy = (x - i0)[:, None], (y - j0)[:, None]
    i0, j0 = i0.astype(np.int64), j0.astype(np.int64)
    columns = (np.mod(i0, width), np.mod(i0 + 1, width))
    rows = (height - 1 - np.mod(j0, height), height - 1 - np.mod(j0 + 1, height))  # bottom-up → top-down
    bottom = (1 - fx) * image[rows[0], columns[0]] + fx * image[rows[0], columns[1]]
    top = (1 - fx) * image[rows[1], columns[0]] + fx * image[rows[1], columns[1]]
    return (1 - fy) * bottom + fy * top
