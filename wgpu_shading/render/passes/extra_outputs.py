"""Extra per-pixel outputs for datasets: surface normals (eye or world space) and object ids.

`Renderer.submit(scene, normals="eye", ids=True)` (and `render_many`, `render_frame`) add a
second, small render pass (wgsl/extra_outputs.wgsl) into an rgba32float target: normal in
xyz, the segment id in w (1 + the index of the object's part in `segments`; 0 = background).
Every part is drawn opaque: alpha masks and blending of the colour pass do not apply (ids
and normals are of the nearest surface). It runs on the colour pass's path: the same
DeviceCache (gpu/device_cache.py) gives its pipeline (its one pipeline-descriptor builder is
`extra_outputs_pipeline`), mesh uploads, uniform buffers, bind groups and its render target
(lent and returned like the colour pass's, within the same bound), and it uses the same
float32 matrices as the lit pass, so its coverage and depth order are those of the colour image.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu
from pyglm import glm

from ...errors import SceneError
from ...scene import Scene, SceneObject
from ...scene.geometry.mesh import MeshPart
from ..features import FeatureSet
from ..gpu.device_cache import DeviceCache
from ..gpu.pipelines import PassKind, PipelineDescriptor, PipelineKey
from ..gpu.readback import read_buffer
from ..gpu.targets import Target
from ..shaders.bindings import extra_outputs_plan
from ..shaders.shadergen import generate_pass_wgsl
from ..shaders.uniforms import clip_from_eye, is_mirrored, stroke_uniforms
from .draws import Draw, encode_draws
from .frame_context import FrameContext
from .turned_away import culls_turned_away, eye_outside

NORMAL_SPACES = ("eye", "world")
# Its entry shader by primitive: triangles, and the colour pass's quads of points and lines.
_ENTRY = {"triangles": "extra_outputs.wgsl", "points": "points_outputs.wgsl", "lines": "lines_outputs.wgsl"}
TARGET_FORMAT = "float32"  # an rgba32float target, like `render --float`'s: the same pool


def extra_outputs_pipeline(key: PipelineKey) -> PipelineDescriptor:
    """One shader for every triangle draw; `cull_back` for the parts the lit pass culls (glTF
    doubleSided false), whose winding then depends on `mirrored`. Points and lines (the
    key's features: which primitive, discs or not) are the colour pass's quads."""
    plan = extra_outputs_plan(key.features)
    return PipelineDescriptor(
        label="extra outputs" + ("" if key.features is None else f" ({key.features.primitive})"),
        source=generate_pass_wgsl(_ENTRY[key.features.primitive if key.features else "triangles"], plan),
        plan=plan,
        indexed=key.features is None,
        quads=key.features is not None,
        topology=wgpu.PrimitiveTopology.triangle_list if key.features is None else wgpu.PrimitiveTopology.triangle_strip,
        front_face_cw=key.mirrored,
        cull_mode=wgpu.CullMode.back if key.cull_back else wgpu.CullMode.none,
        color_format=key.target_format,
    )


EXTRA_OUTPUTS = PassKind("extra outputs", extra_outputs_pipeline)


def extra_outputs_key(cull_back: bool = False, mirrored: bool = False) -> PipelineKey:
    # The winding matters only where back faces are culled: one pipeline for both otherwise.
    return PipelineKey(EXTRA_OUTPUTS, None, TARGET_FORMAT, 1, mirrored and cull_back, cull_back)


def segments(scene: Scene) -> list[tuple[SceneObject, MeshPart]]:
    """What the ids number: every part of every object, in scene order (objects in order,
    each mesh's parts in file order; a mesh without parts is one part). Id k is entry k-1."""
    return [(obj, part) for obj in scene.objects for part in obj.mesh.parts if part.count > 0]


@dataclass(frozen=True)
class ExtraFrame:
    """normals: (height, width, 3) float32 unit vectors, 0 where nothing was drawn.
    ids: (height, width) uint16, 0 = background, k = segments(scene)[k-1] (object and part)."""

    normals: np.ndarray
    ids: np.ndarray


def check_space(space: str) -> None:
    if space not in NORMAL_SPACES:
        raise SceneError(f"normals: expected eye or world, got {space!r}")


@dataclass(frozen=True)
class ExtraOutputsPass:
    """The normals (in `space`) and ids of a frame."""

    space: str  # "eye" | "world"

    def take_target(self, cache: DeviceCache, scene: Scene) -> Target:
        return cache.take_target(scene.size, TARGET_FORMAT)

    def encode(self, cache: DeviceCache, encoder, frame: FrameContext, target: Target) -> None:
        encode_extra_outputs(cache, encoder, frame, self.space, target)

    def read(self, target: Target, scene: Scene) -> dict[str, np.ndarray]:
        normals, ids = read_extra_outputs(target)
        return {"normals": normals, "ids": ids}


def prepare_draws(cache: DeviceCache, frame: FrameContext, space: str, aspect: float) -> list[Draw]:
    """One draw per segment, its uniforms holding the segment's id."""
    scene = frame.scene
    # The same float64 → float32 values as uniforms.frame_uniforms / object_uniforms.
    clip = clip_from_eye(scene.camera, aspect).T
    materials = {id(obj): dict(zip(map(id, obj.mesh.parts), obj.part_materials())) for obj in scene.objects}
    draws = []
    closed_and_outside: dict[int, bool] = {}  # by object: culls_turned_away, asked once
    for segment, (obj, part) in enumerate(segments(scene), 1):
        model = glm.dmat4(obj.world_from_model())
        model_view = frame.eye_from_world * model
        # the back faces the lit pass culls (glTF doubleSided false; a closed surface seen
        # from outside: turned_away.py) are culled here too
        cull = materials[id(obj)][id(part)].double_sided is False and not scene.shading.two_sided
        if part.primitive == "triangles" and not cull:
            if id(obj) not in closed_and_outside:
                view = eye_outside(scene, obj, obj.part_materials(), model_view)
                closed_and_outside[id(obj)] = culls_turned_away(view, obj.mesh)
            cull = closed_and_outside[id(obj)]
        if part.primitive == "triangles":
            entry = cache.pipelines.get(extra_outputs_key(cull, is_mirrored(model_view)))
        else:
            entry = cache.pipelines.get(PipelineKey(EXTRA_OUTPUTS, _stroke_outputs(obj, part), TARGET_FORMAT))
        normal_from_model = glm.inverseTranspose(glm.dmat3(model_view if space == "eye" else model))
        data = np.zeros((), entry.uniform_dtypes["object"])
        data["clip_from_eye"] = clip
        data["eye_from_model"] = np.array(model_view).T
        data["output_normal_from_model"][:, :3] = np.array(normal_from_model).T
        data["object_id"] = segment
        if part.primitive == "triangles":
            draws.append(Draw(entry, segment, cache.gpu_mesh(obj.mesh, entry.plan), data, part.first, part.count, {}))
        else:
            draws.append(_stroke_draw(cache, scene, obj, part, entry, segment, data, model_view))
    return draws


def _stroke_outputs(obj: SceneObject, part: MeshPart) -> FeatureSet:
    """What the outputs of a point or line part need: which quad, and discs where points have normals."""
    return FeatureSet(primitive=part.primitive, point_normals=part.primitive == "points" and obj.mesh.has_point_normals(part))


def _stroke_draw(cache: DeviceCache, scene: Scene, obj: SceneObject, part: MeshPart, entry, segment: int, data: np.ndarray,
                 model_view: glm.dmat4) -> Draw:
    """A point or line part's draw: the colour pass's quads (passes/strokes.py), the same sizes."""
    points = part.primitive == "points"
    stroke_uniforms(data, scene.size, scene.shading.point_size if points else scene.shading.line_width)
    if "eye_normal_from_model" in data.dtype.names:
        data["eye_normal_from_model"][:, :3] = np.array(glm.inverseTranspose(glm.dmat3(model_view))).T
    upload = cache.gpu_points(obj.mesh) if points else cache.gpu_segments(obj.mesh, "lines")
    return Draw(entry, segment, upload, data, part.first - (upload.base if points else 0), part.count, {})


def encode_extra_outputs(cache: DeviceCache, encoder, frame: FrameContext, space: str, target: Target) -> None:
    """The normals-and-ids pass of the frame's scene into `target` (a float32 target), and
    the copy into its readback buffer."""
    draws = prepare_draws(cache, frame, space, target.width / target.height)
    render_pass = encoder.begin_render_pass(
        color_attachments=[
            {"view": target.color_view, "clear_value": (0, 0, 0, 0), "load_op": wgpu.LoadOp.clear, "store_op": wgpu.StoreOp.store}
        ],
        depth_stencil_attachment={
            "view": target.depth_view,
            "depth_clear_value": 0.0,  # reversed Z, like the lit pass
            "depth_load_op": wgpu.LoadOp.clear,
            "depth_store_op": wgpu.StoreOp.discard,
        },
    )
    encode_draws(cache, render_pass, draws, {}, "extra outputs", "segment {}")
    render_pass.end()
    encoder.copy_texture_to_buffer(
        {"texture": target.color},
        {"buffer": target.color_readback, "bytes_per_row": target.color_row_bytes, "rows_per_image": target.height},
        (target.width, target.height, 1),
    )


def read_extra_outputs(target: Target) -> tuple[np.ndarray, np.ndarray]:
    """Normals (height, width, 3) float32 and ids (height, width) uint16 from the target."""
    pixels = read_buffer(target.color_readback, target.color_row_bytes, target.height, target.width, np.float32, 4)
    return np.ascontiguousarray(pixels[:, :, :3]), pixels[:, :, 3].astype(np.uint16)
