"""The shadow pass (docs/shadows.md#shadow-maps): the maps of every casting light, drawn
before the colour pass that reads them.

A frame whose scene has shadows (scene.has_shadows: a light casts, something casts and
something receives) starts with this pass: it fits one view per directional or spot light
and up to six per positional light (shadow_views.py) to the receivers the camera sees,
draws every caster's depth into one layer of the shadow maps per view (its one
pipeline-descriptor builder is `shadow_map_pipeline`: depth only, nothing culled), and
hands the colour pass what its shaders read, by binding name (FrameContext.bound): the
views ("shadow_uniforms"), the maps and their comparison sampler. Without shadows the
frame has no such pass and its shaders no shadow code.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from ...scene import DirectionalLight, Scene, SceneObject
from ...scene.geometry.solids import winding_number
from ...scene.shadows import AUTO
from ..features import casting_lights
from ..gpu.device_cache import DeviceCache
from ..gpu.pipelines import PassKind, PipelineDescriptor, PipelineKey
from ..gpu.shadow_maps import SHADOW_FORMAT
from ..gpu.targets import Target
from ..shaders.bindings import shadow_map_plan
from ..shaders.shadergen import generate_pass_wgsl, shadow_uniforms_dtype
from .draws import Draw, encode_draws
from .frame_context import FrameContext
from .shadow_resolution import auto_map_size
from .shadow_views import LightShadow, fit_shadow_views
from .visible_regions import world_box

# How many texels beyond the one under a point a filter reads: the margin every view keeps
# around what it must cover (one more for rounding), so a filter never reads past a map.
FILTER_REACH = {"nearest": 0, "bilinear": 1, "pcf3": 2, "pcf5": 3}


def shadow_map_pipeline(key: PipelineKey) -> PipelineDescriptor:
    """One depth-only pipeline for every caster and view: both sides of every triangle cast."""
    return PipelineDescriptor(
        label="shadow map",
        source=generate_pass_wgsl("shadow_map.wgsl", shadow_map_plan()),
        plan=shadow_map_plan(),
        depth_format=SHADOW_FORMAT,
        color_format=None,
        fragment=False,
    )


SHADOW_MAP = PassKind("shadow map", shadow_map_pipeline)
SHADOW_MAP_KEY = PipelineKey(SHADOW_MAP, None, None)


@dataclass(frozen=True)
class ShadowPass:
    """The shadow maps of a frame; the device cache keeps them (no target is lent)."""

    def take_target(self, cache: DeviceCache, scene: Scene) -> Target | None:
        return None

    def encode(self, cache: DeviceCache, encoder, frame: FrameContext, target: Target | None) -> None:
        encode_shadow_maps(cache, encoder, frame)

    def read(self, target: Target | None, scene: Scene) -> dict[str, np.ndarray | None]:
        return {}


def slot_ordered(scene: Scene, shadows: tuple[LightShadow, ...]) -> tuple[LightShadow, ...]:
    """The casting lights' views in the shaders' slot order (features.casting_lights)."""
    by_light = {shadow.light: shadow for shadow in shadows}
    return tuple(by_light[index] for index in casting_lights(scene))


def encode_shadow_maps(cache: DeviceCache, encoder, frame: FrameContext) -> None:
    """Draw every view's map and bind what the colour pass reads into frame.bound."""
    scene = frame.scene
    settings = scene.shadows.resolved()
    size = int(settings.map_size)
    margin = FILTER_REACH[settings.filter] + 1.0
    shadows = slot_ordered(scene, fit_shadow_views(scene, size, margin))
    if scene.shadows.map_size == AUTO:  # as many texels as the image's pixels need (shadow_resolution.py)
        needed = auto_map_size(scene, shadows)
        if needed != size:
            size = needed
            shadows = slot_ordered(scene, fit_shadow_views(scene, size, margin))
    views = [view for shadow in shadows for view in shadow.views if view is not None]
    maps = cache.shadow_maps(size, len(views))
    entry = cache.pipelines.get(SHADOW_MAP_KEY)
    casters = [obj for obj in scene.objects if obj.cast_shadows and obj.mesh.triangle_count]
    dtype = entry.uniform_dtypes["object"]
    layers = []
    for view in views:
        light_clip = view.clip_from_light() @ view.light_from_world
        layer = []
        for obj in casters:
            data = np.zeros((), dtype)
            data["clip_from_model"] = (light_clip @ obj.world_from_model()).T  # float64, then rounded once
            layer.append((obj.mesh, data))
        layers.append(layer)
    # The same casters seen through the same float32 matrices draw the same maps: a frame of a
    # scene and camera that did not change reuses them (a queue runs its frames in order).
    contents = tuple((mesh, data.tobytes()) for layer in layers for mesh, data in layer)
    if maps.contents != contents:
        for index, layer in enumerate(layers):
            draws = [Draw(entry, index * len(casters) + k, cache.gpu_mesh(mesh), data, 0, mesh.triangle_count, {})
                     for k, (mesh, data) in enumerate(layer)]
            render_pass = encoder.begin_render_pass(
                color_attachments=[],
                depth_stencil_attachment={
                    "view": maps.layer_views[index],
                    "depth_clear_value": 0.0,  # reversed depth: 0 is nothing there
                    "depth_load_op": wgpu.LoadOp.clear,
                    "depth_store_op": wgpu.StoreOp.store,
                },
            )
            encode_draws(cache, render_pass, draws, {}, "shadow casters", "shadow caster {}")
            render_pass.end()
        maps.contents = contents
    data = shadow_uniforms(shadows, views, frame.eye_from_world, size, float(settings.bias))
    frame.bound.update(
        shadow_uniforms=cache.uniform_buffer("shadows", 0, data, "shadow maps"),
        shadow_maps=maps.array_view,
        shadow_sampler=cache.comparison_sampler(),
    )


def shadow_uniforms(shadows: tuple[LightShadow, ...], views: list, eye_from_world, size: int, bias: float) -> np.ndarray:
    """The ShadowUniforms block (wgsl/structs.wgsl): for each casting light by slot, its
    transform from eye space (its view's, or its cube frame's), texel mapping, depth range
    and bias in world units, and the layer of each of its maps."""
    data = np.zeros((), shadow_uniforms_dtype(len(shadows)))
    world_from_eye = np.linalg.inv(np.array(eye_from_world))
    layer_of = {id(view): layer for layer, view in enumerate(views)}
    for slot, shadow in enumerate(shadows):
        record = data["lights"][slot]
        layers = [layer_of[id(view)] if view is not None else -1 for view in shadow.views]
        view = next((view for view in shadow.views if view is not None), None)
        if shadow.cube_from_world is not None:  # every face has the same window and near plane
            record["light_from_eye"] = (shadow.cube_from_world @ world_from_eye).T
            record["layers"], record["more_layers"] = layers[:4], layers[4:] + [1, 0]
        else:
            record["layers"], record["more_layers"] = layers + [-1, -1, -1], [-1, -1, 0, 0]
            if view is not None:
                record["light_from_eye"] = (view.light_from_world @ world_from_eye).T
        if view is None:
            continue
        x0, y0, x1, y1 = view.window
        # texel coordinates (x right, y down the map's rows) of window units
        across, down = size / (x1 - x0), -size / (y1 - y0)
        record["texels"] = (across, down, -x0 * across, -y1 * down)
        reach = 1.0 / (view.far - view.near) if view.orthographic else view.near
        record["depth"] = (reach, bias * view.texel_size(size), 0.0, 0.0)
    return data


def receiver_uniforms(data: np.ndarray, scene: Scene, obj: SceneObject) -> None:
    """A receiver's own shadow fields in its object block (wgsl/structs.wgsl): which casting
    lights (bits by slot) its closed surface hides from its own points facing away from them
    (docs/shadows.md#closed-surfaces), and the sign that turns its winding normal outward."""
    orientation = obj.mesh.solid if obj.cast_shadows else 0
    data["outward_sign"] = -1.0 if orientation < 0 else 1.0
    bits = 0
    if orientation:
        box = world_box(obj)
        lower, upper = box.min(axis=0), box.max(axis=0)
        for slot, index in enumerate(casting_lights(scene)[:32]):
            light = scene.lights[index]
            if isinstance(light, DirectionalLight) or _outside_solid(obj, light.position, lower, upper):
                bits |= 1 << slot
    data["self_shadowing_lights"] = bits


def _outside_solid(obj: SceneObject, position, lower: np.ndarray, upper: np.ndarray) -> bool:
    """Whether a point-like light is outside the closed object: outside its world box, or
    inside the box and wound around 0 times by its surface (scene/geometry/solids.py). A
    light near a solid, inside its box but not in it, needs the rule most: there the faces
    turned from it meet the lit ones at a grazing angle (random scene 57)."""
    if not np.all((lower <= position) & (position <= upper)):
        return True
    model = np.linalg.inv(obj.world_from_model())
    local = model[:3, :3] @ np.asarray(position, dtype=np.float64) + model[:3, 3]
    return abs(winding_number(obj.mesh.positions, obj.mesh.indices, local)) < 0.5
