"""Scene → uniform data: world-space float64 values to eye-space float32 buffers.

Everything is computed in float64 and rounded to float32 once, at the end. The
model-view matrix is formed in float64 before rounding, so an object 1e5 units from
the origin seen from close by keeps its precision (camera-relative rendering).
The buffers are numpy structured arrays whose dtypes `layout.py` derived from the
WGSL structs; fields are filled by name.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from pyglm import glm

from ...errors import SceneError
from ...scene import Camera, DirectionalLight, Material, Scene, SceneObject, SpotLight, has_shadows


def clip_from_eye(camera: Camera, aspect: float) -> np.ndarray:
    """The projection with reversed Z: depth 1 at the near plane, 0 at the far plane.

    Perspective: paired with a float32 depth buffer and the `greater` test, reversed Z
    spreads float precision evenly over distance, so near/far ratios of 1e-7 do not
    z-fight. It is the right-handed zero-to-one (Vulkan) perspective with near and far
    swapped, built in double precision: pyglm's perspective functions exist in single
    precision only, and rounding their tan() and quotients in float32 moved triangle edges
    by a pixel against the float64 reference (tests/test_gpu_vs_reference.py).

    Orthographic: glOrtho's box, `camera.view_height()` tall and as wide as the aspect
    asks, centred on the view axis; depth falls linearly from 1 at near to 0 at far (the
    same reversed convention, so the depth test and clear value do not change).
    """
    near, far = camera.near, camera.far
    if camera.orthographic:
        half_height = camera.view_height() / 2.0
        return np.array(
            glm.dmat4(
                glm.dvec4(1.0 / (half_height * aspect), 0.0, 0.0, 0.0),  # columns
                glm.dvec4(0.0, 1.0 / half_height, 0.0, 0.0),
                glm.dvec4(0.0, 0.0, 1.0 / (far - near), 0.0),
                glm.dvec4(0.0, 0.0, far / (far - near), 1.0),
            )
        )
    focal = 1.0 / math.tan(math.radians(camera.fov_y) / 2.0)
    return np.array(
        glm.dmat4(
            glm.dvec4(focal / aspect, 0.0, 0.0, 0.0),  # columns
            glm.dvec4(0.0, focal, 0.0, 0.0),
            glm.dvec4(0.0, 0.0, near / (far - near), -1.0),
            glm.dvec4(0.0, 0.0, near * far / (far - near), 0.0),
        )
    )


def linear_depth(depth: np.ndarray, camera: Camera) -> np.ndarray:
    """Eye-space distance along the view axis from reversed-Z depth; inf where nothing was drawn.

    `depth` may be a strided float32 view (the mapped readback rows): it is read once into
    the float64 result and everything else happens in place, with no float64 temporaries
    (a third of the time of the straightforward expression; the same values bit for bit)."""
    near, far = camera.near, camera.far
    distance = np.multiply(depth, far - near, dtype=np.float64)  # float32 → float64 exactly, then × (far − near)
    if camera.orthographic:
        np.subtract(far, distance, out=distance)
    else:
        distance += near
        np.divide(near * far, distance, out=distance)
    distance[depth <= 0.0] = np.inf
    return distance


def uniform_lights(scene: Scene) -> tuple:
    """The lights in the order the light arrays hold them: each kind in scene order, except
    that with shadows a kind's casting lights come first (a shader knows them by their count,
    features.casting_lights)."""
    if not has_shadows(scene):
        return scene.lights
    return tuple(sorted(scene.lights, key=lambda light: not light.shadows))


def _fill_light_colors(lights: np.ndarray, index: int, light: object) -> None:
    lights["ambient"][index] = light.ambient  # type: ignore[attr-defined]
    lights["diffuse"][index] = light.diffuse  # type: ignore[attr-defined]
    lights["specular"][index] = light.specular  # type: ignore[attr-defined]


def frame_uniforms(scene: Scene, dtype: np.dtype, eye_from_world: glm.dmat4 | None = None) -> np.ndarray:
    """The FrameUniforms buffer contents for `scene` (pass the view matrix if you have it)."""
    data = np.zeros((), dtype)
    view = glm.dmat4(scene.camera.eye_from_world() if eye_from_world is None else eye_from_world)
    rotation = glm.dmat3(view)
    width, height = scene.size
    data["clip_from_eye"] = clip_from_eye(scene.camera, width / height).T  # column-major
    data["global_ambient"] = scene.ambient
    if "blinn_exponent_scale" in dtype.names:
        data["blinn_exponent_scale"] = scene.shading.blinn_exponent_scale
    counters = {"directional": 0, "positional": 0, "spot": 0}
    for light in uniform_lights(scene):
        kind = light.kind
        index = counters[kind]
        counters[kind] += 1
        lights = data[f"{kind}_lights"]
        _fill_light_colors(lights, index, light)
        if isinstance(light, DirectionalLight):
            lights["direction_to_light"][index] = glm.normalize(rotation * -glm.dvec3(*light.direction))
            continue
        lights["position"][index] = glm.dvec3(view * glm.dvec4(glm.dvec3(*light.position), 1.0))
        if "attenuation" in lights.dtype.names:
            lights["attenuation"][index] = light.attenuation
            lights["inverse_range"][index] = 1.0 / light.range if light.range > 0.0 else 0.0
        if isinstance(light, SpotLight):
            lights["direction"][index] = glm.normalize(rotation * glm.dvec3(*light.direction))
            lights["cutoff_chord_squared"][index] = 4.0 * math.sin(math.radians(light.cutoff) / 2.0) ** 2
            lights["exponent"][index] = light.exponent
    return data


def eye_from_model(scene: Scene, obj: SceneObject) -> glm.dmat4:
    """The model-view matrix in double precision (formed before any rounding to float32)."""
    return glm.dmat4(scene.camera.eye_from_world()) * glm.dmat4(obj.world_from_model())


def object_uniforms(
    model_view: glm.dmat4 | np.ndarray, material: Material, dtype: np.dtype, scene: Scene | None = None
) -> np.ndarray:
    """The ObjectUniforms buffer contents for one object, from its double-precision model-view.

    `scene` supplies the global ambient and the lights for the light × material products
    (LightProducts in wgsl/structs.wgsl); it is required whenever the layout has them."""
    model_view = glm.dmat4(model_view)
    data = np.zeros((), dtype)
    data["eye_from_model"] = np.array(model_view).T  # column-major
    normal_matrix = np.array(glm.inverseTranspose(glm.dmat3(model_view)))  # the seed's norm_matrix
    data["eye_normal_from_model"][:, :3] = _unit_scaled(normal_matrix).T  # columns padded to vec4
    fields = data["material"]
    fields["ambient"] = material.ambient
    fields["diffuse"] = material.diffuse
    fields["specular"] = material.specular
    fields["shininess"] = material.shininess
    if "emission" in fields.dtype.names:
        fields["emission"] = material.emission
    if "alpha_cutoff" in fields.dtype.names:
        fields["alpha_cutoff"] = material.alpha_cutoff
    if "normal_scale" in fields.dtype.names:
        fields["normal_scale"] = material.normal_scale
    if "occlusion_strength" in fields.dtype.names:
        fields["occlusion_strength"] = material.occlusion_strength
    if "global_ambient_product" in dtype.names:
        if scene is None:
            raise ValueError("object_uniforms: this layout has light × material products; pass the scene")
        _fill_light_products(data, material, scene)
    return data


def stroke_uniforms(data: np.ndarray, size: tuple[int, int], pixels: float, edge_color=None) -> np.ndarray:
    """A point's or line's ObjectUniforms (object_uniforms' block) with the target's size and
    the quad's size in pixels, and the edge colour of an edges draw (docs/primitives.md)."""
    data["viewport_size"] = size
    data["stroke_pixels"] = pixels
    if edge_color is not None:
        data["edge_color"] = edge_color
    return data


def _fill_light_products(data: np.ndarray, material: Material, scene: Scene) -> None:
    """Light colors times material colors, in float64 then rounded once: the shader reads
    these instead of multiplying the two uniforms per fragment (docs/performance.md)."""
    ambient, diffuse, specular = (np.asarray(c, np.float64) for c in (material.ambient, material.diffuse, material.specular))
    data["global_ambient_product"] = np.asarray(scene.ambient, np.float64) * ambient
    counters = {"directional": 0, "positional": 0, "spot": 0}
    for light in uniform_lights(scene):
        index = counters[light.kind]
        counters[light.kind] += 1
        products = data[f"{light.kind}_products"]
        products["ambient"][index] = np.asarray(light.ambient, np.float64) * ambient
        products["diffuse"][index] = np.asarray(light.diffuse, np.float64) * diffuse
        products["specular"][index] = np.asarray(light.specular, np.float64) * specular


def _unit_scaled(normal_matrix: np.ndarray) -> np.ndarray:
    """The normal matrix scaled by a power of two towards unit size when it is far from it.

    Only its direction matters (the shaders normalize what it returns), but a tiny object
    scale makes it huge: flat shading multiplies it with a cross product of float32 edges,
    and the squared length of that overflowed float32 (a black, unlit object). Scaling by
    2^k is exact, so matrices of ordinary size are left untouched bit for bit."""
    largest = float(np.abs(normal_matrix).max())
    if 2.0**-20 <= largest <= 2.0**20:
        return normal_matrix
    return normal_matrix * 2.0 ** -math.frexp(largest)[1]


def _float_leaves(data: np.ndarray):
    """Every float array inside a (structured) uniform value."""
    if data.dtype.names is None:
        if data.dtype.base.kind == "f":
            yield data
        return
    for name in data.dtype.names:
        yield from _float_leaves(data[name])


@lru_cache(maxsize=64)
def _float_words(dtype: np.dtype) -> np.ndarray | None:
    """Which 4-byte words of a uniform block are f32 fields; None when no field is an
    integer (most blocks: then every word is checked, as one array)."""
    if not _has_integers(dtype):
        return None
    probe = np.zeros((), dtype)
    for leaf in _float_leaves(probe):
        leaf[...] = 1.0
    return np.frombuffer(probe.tobytes(), np.float32) == 1.0


def _has_integers(dtype: np.dtype) -> bool:
    dtype = dtype.base  # an array field: its element
    if dtype.names is None:
        return dtype.kind in "iu"
    return any(_has_integers(dtype.fields[name][0]) for name in dtype.names)


def finite_uniform_bytes(data: np.ndarray, where: str) -> bytes:
    """The buffer's bytes, after a last check that every f32 value is finite. Scene
    validation keeps them finite; this is the net under it, so that inf or NaN never reaches
    a shader. (Integer fields, such as the shadow maps' layer numbers, are not checked.)"""
    payload = data.tobytes()
    words = np.frombuffer(payload, np.float32)
    floats = _float_words(data.dtype)
    if not np.isfinite(words if floats is None else words[floats]).all():
        raise SceneError(
            f"{where}: a value derived from it (matrix, normal matrix, colour, projection) is not finite in float32"
        )
    return payload


def is_mirrored(model_view: glm.dmat4 | np.ndarray) -> bool:
    """True when the model-view matrix flips handedness (negative determinant): the
    triangles' winding reverses on screen, so the pipeline's front face must too."""
    return glm.determinant(glm.dmat3(glm.dmat4(model_view))) < 0.0
