"""The colour pass: a scene's draws (one per object part, with the pipeline, uploads and
textures its binding plan names) into a colour target, with the depth image on request.

Its one pipeline-descriptor builder is `color_pipeline`: the feature set's shader and
binding plan, culling and blending from the material, the target's format and samples.
With MSAA and a depth image the pass runs twice (`encode`): multisampled depth cannot be
copied out, so a single-sample pass first writes the depth that is read (pixel centres, as
without MSAA) and the multisampled pass then overwrites the colour with its resolved image.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu
from pyglm import glm

from ...errors import SceneError
from ...scene import Camera, Scene
from ..features import FeatureSet, object_features
from ..gpu.device_cache import DeviceCache
from ..gpu.mesh_uploads import clusters_enabled, clusters_settled
from ..gpu.pipelines import BLEND_OVER, PassKind, PipelineDescriptor, PipelineKey
from ..gpu.readback import read_buffer, read_mapped_rows
from ..gpu.targets import Target
from ..shaders.bindings import binding_plan
from ..shaders.material_maps import decodes_srgb
from ..shaders.shadergen import generate_wgsl
from ..shaders.uniforms import frame_uniforms, is_mirrored, linear_depth, object_uniforms
from .draws import Draw, encode_draws
from .frame_context import FrameContext
from .turned_away import culls_turned_away, eye_outside, turned_away


def color_pipeline(key: PipelineKey) -> PipelineDescriptor:
    """The colour pass's pipelines: one per feature set, target format, samples and winding."""
    features = key.features
    return PipelineDescriptor(
        label=features.describe(),
        source=generate_wgsl(features),
        plan=binding_plan(features),
        # Flat shading pulls its vertices from storage buffers (wgsl/flat.wgsl says why).
        indexed=features.frequency != "flat",
        # A mirrored model-view reverses the winding on screen; flip what counts as front
        # so `front_facing` still means "the outward side faces the viewer".
        front_face_cw=key.mirrored,
        # No culling, like OpenGL's default: open meshes show their inside; a glTF material
        # with doubleSided false culls its back faces (glTF 2.0 §3.9.6), and so does a closed
        # surface seen from outside (turned_away.culls_turned_away).
        cull_mode=wgpu.CullMode.back if key.cull_back else wgpu.CullMode.none,
        # Blended parts are drawn after the opaque ones, back to front, and do not hide each
        # other (they still hide behind opaque parts).
        depth_write=features.alpha_mode != "blend",
        # Under edges (`--edges`), surfaces are pushed back by their own depth slope over
        # `under_edges` pixels (the edge quads' reach over them), plus one unit, so their
        # edges win the depth test (docs/primitives.md#edges; VTK's polygon offset). Reversed Z: away is minus.
        depth_bias=-1 if features.under_edges else 0,
        depth_bias_slope_scale=-float(features.under_edges),
        color_format=key.target_format,
        blend=BLEND_OVER if features.alpha_mode == "blend" else None,
        samples=key.samples,
    )


COLOR = PassKind("colour", color_pipeline)


def color_key(
    features: FeatureSet, target_format: str = "rgba8", samples: int = 1, mirrored: bool = False, cull_back: bool = False,
) -> PipelineKey:
    """The key of the colour pipeline that draws `features`; its back faces are culled when
    the features ask (a glTF material) or `cull_back` (a closed surface seen from outside)."""
    return PipelineKey(COLOR, features, target_format, samples, mirrored, features.cull_back or cull_back)


@dataclass(frozen=True)
class ColorPass:
    """The colour image of a frame, and its eye-space depth with `read_depth`."""

    color_format: str  # "rgba8" | "float32"
    read_depth: bool

    def take_target(self, cache: DeviceCache, scene: Scene) -> Target:
        return cache.take_target(scene.size, self.color_format, scene.samples)

    def encode(self, cache: DeviceCache, encoder, frame: FrameContext, target: Target) -> None:
        encode_color_frame(cache, encoder, frame, target, read_depth=self.read_depth)

    def read(self, target: Target, scene: Scene) -> dict[str, np.ndarray | None]:
        color, depth = read_color_frame(target, scene.camera, read_depth=self.read_depth)
        return {"color": color, "depth": depth}


@dataclass(frozen=True)
class ColorPlan:
    """What the colour pass draws for one scene: its draws, in order, and the frame's
    uniform block (None without draws). Kept for the next frame of the same Scene object
    (gpu/frame_plans.py)."""

    draws: list[Draw]
    frame_data: np.ndarray | None


def color_plan(cache: DeviceCache, scene: Scene, color_format: str, eye_from_world: glm.dmat4, samples: int = 1) -> ColorPlan:
    """The colour pass's plan for `scene`: the one made for this scene object by an earlier
    frame when the caches its draws use are unchanged, else a new one."""
    variant = (COLOR.name, color_format, samples, clusters_enabled())
    plan = cache.frame_plans.get(scene, variant)
    if plan is None:
        draws, settled = _prepare_draws(cache, scene, color_format, eye_from_world, samples)
        frame_data = None
        if draws:
            # Every object shares the frame uniforms; their layout depends only on scene-level features.
            frame_dtype = draws[0].entry.uniform_dtypes["frame"]
            assert all(draw.entry.uniform_dtypes["frame"] == frame_dtype for draw in draws)
            frame_data = frame_uniforms(scene, frame_dtype, eye_from_world)
        plan = ColorPlan(draws, frame_data)
        if settled:
            for block in [frame_data] + [draw.object_data for draw in draws]:
                if block is not None:
                    block.flags.writeable = False  # a kept plan's uniform values are read, never changed
            cache.frame_plans.put(scene, variant, plan)
    return plan


def prepare_draws(cache: DeviceCache, scene: Scene, color_format: str, eye_from_world: glm.dmat4, samples: int = 1) -> list[Draw]:
    """One draw per (object, part): opaque and masked parts first, in scene order, then
    blended parts back to front (by the eye-space depth of each part's centre), so
    that what lies behind a translucent part is already drawn (docs/conventions.md)."""
    return _prepare_draws(cache, scene, color_format, eye_from_world, samples)[0]


def _prepare_draws(
    cache: DeviceCache, scene: Scene, color_format: str, eye_from_world: glm.dmat4, samples: int = 1,
) -> tuple[list[Draw], bool]:
    """prepare_draws, and whether later frames of the scene may reuse the draws: False while
    a mesh's clusters may still start or finish building (each frame asks for them)."""
    settled = True
    opaque: list[Draw] = []
    blended: list[tuple[float, Draw]] = []
    edges: list[Draw] = []  # --edges: over every opaque surface, under the blended ones
    for index, obj in enumerate(scene.objects):
        model_view = eye_from_world * glm.dmat4(obj.world_from_model())  # double precision, once per object
        mirrored = is_mirrored(model_view)
        materials = obj.part_materials()
        # Blended parts keep their triangle order in the upload (they blend in index order).
        blended_parts = frozenset(k for k, m in enumerate(materials) if m.alpha_mode == "blend")
        # The clusters of the upload this frame leaves out (turned_away.py; None: none).
        away, cull = None, False
        if obj.mesh.triangle_count:
            view = eye_outside(scene, obj, materials, model_view)
            upload = cache.gpu_mesh(obj.mesh, None, blended_parts, clusters=view is not None)
            settled = settled and (view is None or clusters_settled(upload, obj.mesh))
            away = turned_away(view, upload)
            cull = culls_turned_away(view, obj.mesh)
        for number, (part, material) in enumerate(zip(obj.mesh.parts, materials)):
            if part.count == 0:
                continue
            if part.primitive != "triangles":  # points and lines (passes/strokes.py)
                from .strokes import stroke_draw  # imported by the scenes that have them (cold start)

                draw = stroke_draw(cache, scene, obj, part, material, model_view, color_format, samples,
                                   len(opaque) + len(blended) + len(edges))
                if draw.entry.key.features.alpha_mode == "blend":
                    blended.append(((model_view * glm.dvec4(*obj.mesh.part_centre(part), 1.0)).z, draw))
                else:
                    opaque.append(draw)
                continue
            features = object_features(scene, obj, index, material)
            entry = cache.pipelines.get(color_key(features, color_format, samples, mirrored, cull))
            textures: dict[str, object] = {}
            owner = None
            for sampled in entry.plan.textures:
                texture = sampled.of_material(material)
                gpu_texture = cache.gpu_texture(texture, sampled.color and decodes_srgb(texture, features))
                owner = owner or gpu_texture
                textures[f"{sampled.name}_texture"] = gpu_texture.view
                textures[f"{sampled.name}_sampler"] = cache.sampler(texture)
            object_data = object_uniforms(model_view, material, entry.uniform_dtypes["object"], scene)
            if features.shadow_lights:
                from .shadow import receiver_uniforms  # imported by the scenes that have shadows (cold start)

                receiver_uniforms(object_data, scene, obj)
            gpu_mesh = cache.gpu_mesh(obj.mesh, entry.plan, blended_parts)
            draw = Draw(
                entry=entry,
                draw_index=len(opaque) + len(blended) + len(edges),
                gpu_mesh=gpu_mesh,
                object_data=object_data,
                first_triangle=part.first,
                triangle_count=part.count,
                textures=textures,
                texture_owner=owner,
                ranges=None if away is None else gpu_mesh.order.clusters.kept_ranges(number, away),
            )
            if features.alpha_mode == "blend":
                centre = obj.mesh.part_centre(part)
                depth = (model_view * glm.dvec4(*centre, 1.0)).z  # eye looks along −z: far is very negative
                blended.append((depth, draw))
            else:
                opaque.append(draw)
        if scene.shading.edges and obj.mesh.triangle_count:
            from .strokes import edge_draw

            edges.append(edge_draw(cache, scene, obj, model_view, color_format, samples, len(opaque) + len(blended) + len(edges)))
    blended.sort(key=lambda item: item[0])
    return opaque + edges + [draw for _, draw in blended], settled


def encode_color_frame(cache: DeviceCache, encoder, frame: FrameContext, target: Target, *, read_depth: bool) -> None:
    """The colour pass of the frame's scene into `target`, and the copies into its readback buffers."""
    scene, eye_from_world = frame.scene, frame.eye_from_world
    if target.samples > 1 and read_depth:
        single = color_plan(cache, scene, target.color_format, eye_from_world, 1)
        encode_pass(cache, encoder, frame, single, target.color_view, None, target.depth_view, store_depth=True)
    if target.samples > 1:
        plan = color_plan(cache, scene, target.color_format, eye_from_world, target.samples)
        encode_pass(cache, encoder, frame, plan, target.msaa_color_view, target.color_view, target.msaa_depth_view)
    else:
        plan = color_plan(cache, scene, target.color_format, eye_from_world)
        encode_pass(cache, encoder, frame, plan, target.color_view, None, target.depth_view, store_depth=read_depth)
    size = (target.width, target.height, 1)
    encoder.copy_texture_to_buffer(
        {"texture": target.color},
        {"buffer": target.color_readback, "bytes_per_row": target.color_row_bytes, "rows_per_image": target.height},
        size,
    )
    if read_depth:
        encoder.copy_texture_to_buffer(
            {"texture": target.depth, "aspect": wgpu.TextureAspect.depth_only},
            {"buffer": target.depth_readback, "bytes_per_row": target.depth_row_bytes, "rows_per_image": target.height},
            size,
        )


def encode_pass(
    cache: DeviceCache, encoder, frame: FrameContext, plan: ColorPlan, color_view, resolve_view, depth_view,
    *, store_depth: bool = False,
) -> None:
    """One render pass drawing the plan's draws; with `resolve_view`, the multisampled color is
    averaged into it at the end of the pass. The depth attachment is kept after the
    pass only with `store_depth` (a frame whose depth is read back): otherwise it is
    scratch, and StoreOp.discard tells the driver it need not write it out."""
    scene = frame.scene
    color_attachment = {
        "view": color_view,
        "clear_value": scene.background,
        "load_op": wgpu.LoadOp.clear,
        "store_op": wgpu.StoreOp.store,
    }
    if resolve_view is not None:
        color_attachment["resolve_target"] = resolve_view
    render_pass = encoder.begin_render_pass(
        color_attachments=[color_attachment],
        depth_stencil_attachment={
            "view": depth_view,
            "depth_clear_value": 0.0,  # reversed Z: 0 is the far plane
            "depth_load_op": wgpu.LoadOp.clear,
            "depth_store_op": wgpu.StoreOp.store if store_depth else wgpu.StoreOp.discard,
        },
    )
    shared = frame.bound
    frame_data = plan.frame_data
    if frame_data is not None:
        uniform_limit = cache.device.limits["max-uniform-buffer-binding-size"]
        if frame_data.nbytes > uniform_limit:
            render_pass.end()
            raise SceneError(
                f"lights: the {len(scene.lights)} lights need {frame_data.nbytes} bytes of uniforms; this adapter "
                f"binds at most {uniform_limit} (use fewer lights)"
            )
        shared = {**shared, "frame": cache.uniform_buffer("frame", 0, frame_data, "camera and lights")}
    encode_draws(cache, render_pass, plan.draws, shared, "object", "objects[{}]")
    render_pass.end()


def read_color_frame(target: Target, camera: Camera, *, read_depth: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """Colour and (with read_depth) eye-space depth from the target's readback buffers."""
    color = read_buffer(
        target.color_readback, target.color_row_bytes, target.height, target.width,
        np.uint8 if target.color_format == "rgba8" else np.float32, 4,
    )
    depth = None
    if read_depth:
        depth = read_mapped_rows(
            target.depth_readback, target.depth_row_bytes, target.height, target.width, np.float32,
            lambda rows: linear_depth(rows, camera),
        )
    return color, depth
