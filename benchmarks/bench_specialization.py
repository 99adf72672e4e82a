"""Does compiling only the effects a scene uses pay? Specialized shaders vs one uber-shader.

    .venv/bin/python benchmarks/bench_specialization.py [--size 1024] [--frames 15] [--output docs/specialization.md]

For each scene, both variants run through the same harness (same meshes, targets, render
pass, copy and readback); only the pipeline and its uniform data differ:
  specialized  the renderer's shader for the scene's feature set (wgpu_shading.render.gpu.pipelines)
  uber         benchmarks/uber.wgsl: every feature compiled in, switched by uniforms
Reported: median warm frame time (render + readback) with frames of the two variants
interleaved (the machine is shared and noisy, so only side-by-side ratios mean anything),
and the first-use cost of each pipeline (creation + first frame − a warm frame; lavapipe
compiles shaders at the first draw). Mesa's on-disk shader cache is disabled so that
first-use costs are real compilations. Before timing, the two images are compared.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path

os.environ["MESA_SHADER_CACHE_DISABLE"] = "true"  # measure compilation, not cache hits

import numpy as np  # noqa: E402
import wgpu  # noqa: E402

from wgpu_shading import (  # noqa: E402
    DirectionalLight,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    SpotLight,
    Texture,
    load_mesh,
    load_scene,
)
from wgpu_shading.assets import load_texture  # noqa: E402
from wgpu_shading.render.device import default_device, describe_device  # noqa: E402
from wgpu_shading.render.features import FeatureSet, object_features  # noqa: E402
from wgpu_shading.render.shaders.layout import Layouts  # noqa: E402
from wgpu_shading.render.shaders.bindings import binding_plan  # noqa: E402
from wgpu_shading.render.gpu.pipelines import PipelineCache  # noqa: E402
from wgpu_shading.render.passes.color import color_key  # noqa: E402
from wgpu_shading.render.gpu.targets import DEPTH_FORMAT  # noqa: E402
from wgpu_shading.render.shaders.uniforms import clip_from_eye, eye_from_model, frame_uniforms, object_uniforms  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
UBER_SOURCE = (Path(__file__).resolve().parent / "uber.wgsl").read_text()
COLOR_FORMAT = wgpu.TextureFormat.rgba8unorm


# --------------------------------------------------------------------------- scenes


def scenes(size: int) -> dict[str, Scene]:
    gold_torus = load_scene(ROOT / "examples" / "gold_torus_phong.toml")
    sphere = load_mesh("builtin:sphere?slices=96&stacks=48")
    one_light = Scene(
        objects=(SceneObject(sphere, Material(specular=(0.0, 0.0, 0.0, 1.0))),),
        lights=(DirectionalLight(direction=(-1.0, -1.0, -1.0)),),
        ambient=(0.2, 0.2, 0.2, 1.0),
    )
    checker = load_texture(ROOT / "examples" / "textures" / "checker.png")
    mixed_lights = (
        DirectionalLight(direction=(-1, -1, -1), diffuse=(0.3, 0.3, 0.3, 1), specular=(0.3, 0.3, 0.3, 1)),
        DirectionalLight(direction=(1, -0.5, -1), diffuse=(0.2, 0.1, 0.1, 1), specular=(0.2, 0.2, 0.2, 1)),
        DirectionalLight(direction=(0, 1, -1), diffuse=(0.1, 0.1, 0.2, 1), specular=(0.1, 0.1, 0.1, 1)),
        PositionalLight(position=(3, 2, 2), diffuse=(0.4, 0.4, 0.3, 1), attenuation=(1, 0.05, 0.01)),
        PositionalLight(position=(-3, 1, 2), diffuse=(0.2, 0.3, 0.4, 1), attenuation=(1, 0.1, 0.0)),
        PositionalLight(position=(0, -3, 2), diffuse=(0.2, 0.2, 0.2, 1), attenuation=(0.5, 0.0, 0.05)),
        SpotLight(position=(2, 2, 3), direction=(-2, -2, -3), cutoff=25, exponent=8, diffuse=(0.6, 0.2, 0.2, 1)),
        SpotLight(position=(-2, 2, 3), direction=(2, -2, -3), cutoff=15, exponent=2, diffuse=(0.2, 0.6, 0.2, 1)),
    )
    textured = Scene(
        objects=(
            SceneObject(
                sphere,
                Material(
                    ambient=(0.4, 0.4, 0.4, 1), diffuse=(0.9, 0.9, 0.9, 1), specular=(0.6, 0.6, 0.6, 1),
                    shininess=30.0, texture=checker, texture_mode="modulate",
                ),
            ),
        ),
        lights=mixed_lights,
        shading=replace(Scene().shading, reflection="blinn-phong", blinn_exponent_scale=3.0),
    )
    return {
        "1 directional light, no specular": replace(one_light, size=(size, size)),
        "gold torus (1 positional light)": replace(gold_torus, size=(size, size)),
        "8 mixed lights + texture": replace(textured, size=(size, size)),
    }


# --------------------------------------------------------------------------- the uber variant


def uber_uniforms(scene: Scene, layouts: Layouts) -> tuple[np.ndarray, np.ndarray]:
    """UberFrame and UberObject contents, computed like wgpu_shading.render.shaders.uniforms does."""
    frame = np.zeros((), layouts.dtype("UberFrame"))
    view = scene.camera.eye_from_world()
    width, height = scene.size
    frame["clip_from_eye"] = clip_from_eye(scene.camera, width / height).T
    frame["global_ambient"] = scene.ambient
    frame["light_count"] = len(scene.lights)
    frame["blinn_phong"] = scene.shading.reflection == "blinn-phong"
    frame["blinn_exponent_scale"] = scene.shading.blinn_exponent_scale
    frame["local_viewer"] = scene.shading.local_viewer
    frame["two_sided"] = scene.shading.two_sided
    lights = frame["lights"]
    for i, light in enumerate(scene.lights):
        lights["ambient"][i], lights["diffuse"][i], lights["specular"][i] = light.ambient, light.diffuse, light.specular
        lights["attenuation"][i] = getattr(light, "attenuation", (1.0, 0.0, 0.0))
        if isinstance(light, DirectionalLight):
            direction = view[:3, :3] @ -np.asarray(light.direction)
            lights["direction"][i] = direction / np.linalg.norm(direction)
            lights["kind"][i] = 0
            continue
        lights["position"][i] = (view @ np.append(light.position, 1.0))[:3]
        lights["kind"][i] = 1
        if isinstance(light, SpotLight):
            direction = view[:3, :3] @ np.asarray(light.direction)
            lights["direction"][i] = direction / np.linalg.norm(direction)
            lights["cutoff_chord_squared"][i] = 4.0 * np.sin(np.radians(light.cutoff) / 2.0) ** 2
            lights["exponent"][i] = light.exponent
            lights["kind"][i] = 2
    obj = scene.objects[0]
    object_data = np.zeros((), layouts.dtype("UberObject"))
    model_view = view @ obj.world_from_model()
    object_data["eye_from_model"] = model_view.T
    object_data["eye_normal_from_model"][:, :3] = np.linalg.inv(model_view[:3, :3])
    material = obj.material
    for key in ("ambient", "diffuse", "specular", "emission", "shininess"):
        object_data[key] = getattr(material, key)
    object_data["texture_mode"] = {None: 0, "modulate": 1, "modulate_all": 2, "blend": 3}[
        material.texture_mode if material.texture is not None else None
    ]
    return frame, object_data


# --------------------------------------------------------------------------- harness


@dataclass
class Variant:
    pipeline: object
    bind_groups: list
    uses_uvs: bool


class Harness:
    """Renders one-object scenes with a given pipeline: the same work for both variants."""

    def __init__(self, device):
        self.device = device
        self.sampler = device.create_sampler(mag_filter="linear", min_filter="linear", mipmap_filter="linear",
                                             address_mode_u="repeat", address_mode_v="repeat")
        white = device.create_texture(size=(1, 1, 1), format=COLOR_FORMAT,
                                      usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST)
        device.queue.write_texture({"texture": white}, np.full(4, 255, np.uint8), {"bytes_per_row": 4}, (1, 1, 1))
        self.white_view = white.create_view()
        self.pipelines = PipelineCache(device)

    def buffer(self, data: np.ndarray, usage) -> object:
        return self.device.create_buffer_with_data(data=np.ascontiguousarray(data), usage=usage)

    def texture_view(self, texture: Texture):
        pixels = np.ascontiguousarray(texture.pixels[::-1])  # rows bottom-up, as the renderer does
        gpu = self.device.create_texture(size=(pixels.shape[1], pixels.shape[0], 1), format=COLOR_FORMAT,
                                         usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST)
        self.device.queue.write_texture({"texture": gpu}, pixels, {"bytes_per_row": pixels.shape[1] * 4}, (pixels.shape[1], pixels.shape[0], 1))
        return gpu.create_view()

    def prepare(self, scene: Scene):
        obj = scene.objects[0]
        mesh = obj.mesh
        self.vertex_buffers = [
            self.buffer(mesh.positions, wgpu.BufferUsage.VERTEX),
            self.buffer(mesh.normals, wgpu.BufferUsage.VERTEX),
            self.buffer(mesh.uvs if mesh.uvs is not None else np.zeros((len(mesh.positions), 2), np.float32), wgpu.BufferUsage.VERTEX),
        ]
        self.index_buffer = self.buffer(mesh.indices, wgpu.BufferUsage.INDEX)
        self.index_count = mesh.indices.size
        self.view = self.texture_view(obj.material.texture) if obj.material.texture is not None else self.white_view
        width, height = scene.size
        usage = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC
        self.color = self.device.create_texture(size=(width, height, 1), format=COLOR_FORMAT, usage=usage)
        self.depth = self.device.create_texture(size=(width, height, 1), format=DEPTH_FORMAT, usage=wgpu.TextureUsage.RENDER_ATTACHMENT)
        self.row_bytes = (width * 4 + 255) // 256 * 256
        self.readback = self.device.create_buffer(size=self.row_bytes * height, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST)
        self.size = (width, height)
        self.background = scene.background

    def _group(self, layout, resources) -> object:
        entries = []
        for binding, resource in enumerate(resources):
            if isinstance(resource, wgpu.GPUBuffer):
                resource = {"buffer": resource}
            entries.append({"binding": binding, "resource": resource})
        return self.device.create_bind_group(layout=layout, entries=entries)

    def specialized(self, scene: Scene) -> Variant:
        features = object_features(scene, scene.objects[0])
        entry = self.pipelines.get(color_key(features))
        frame = self.buffer(frame_uniforms(scene, entry.uniform_dtypes["frame"]), wgpu.BufferUsage.UNIFORM)
        obj = self.buffer(object_uniforms(eye_from_model(scene, scene.objects[0]), scene.objects[0].material, entry.uniform_dtypes["object"], scene), wgpu.BufferUsage.UNIFORM)
        object_resources = [obj] + ([self.view, self.sampler] if features.texture_mode else [])
        groups = [self._group(entry.bind_group_layouts[0], [frame]), self._group(entry.bind_group_layouts[1], object_resources)]
        return Variant(entry.pipeline, groups, uses_uvs=features.texture_mode is not None)

    def uber(self, scene: Scene) -> Variant:
        module = self.device.create_shader_module(code=UBER_SOURCE)
        layouts = Layouts(UBER_SOURCE)
        pipeline = self.device.create_render_pipeline(
            layout="auto",
            # position, normal and UV buffers, like a textured specialized pipeline
            vertex={"module": module, "entry_point": "vs_main", "buffers": binding_plan(FeatureSet(texture_mode="modulate")).vertex_buffer_layouts()},
            primitive={"topology": "triangle-list", "cull_mode": "none"},
            depth_stencil={"format": DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": "greater"},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": COLOR_FORMAT}]},
        )
        frame_data, object_data = uber_uniforms(scene, layouts)
        frame = self.buffer(frame_data, wgpu.BufferUsage.UNIFORM)
        obj = self.buffer(object_data, wgpu.BufferUsage.UNIFORM)
        groups = [
            self._group(pipeline.get_bind_group_layout(0), [frame]),
            self._group(pipeline.get_bind_group_layout(1), [obj, self.view, self.sampler]),
        ]
        return Variant(pipeline, groups, uses_uvs=True)

    def frame(self, variant: Variant) -> np.ndarray:
        encoder = self.device.create_command_encoder()
        render_pass = encoder.begin_render_pass(
            color_attachments=[{"view": self.color.create_view(), "clear_value": self.background, "load_op": "clear", "store_op": "store"}],
            depth_stencil_attachment={"view": self.depth.create_view(), "depth_clear_value": 0.0, "depth_load_op": "clear", "depth_store_op": "store"},
        )
        render_pass.set_pipeline(variant.pipeline)
        for index, group in enumerate(variant.bind_groups):
            render_pass.set_bind_group(index, group)
        for slot, buffer in enumerate(self.vertex_buffers[: 3 if variant.uses_uvs else 2]):
            render_pass.set_vertex_buffer(slot, buffer)
        render_pass.set_index_buffer(self.index_buffer, wgpu.IndexFormat.uint32)
        render_pass.draw_indexed(self.index_count)
        render_pass.end()
        width, height = self.size
        encoder.copy_texture_to_buffer({"texture": self.color}, {"buffer": self.readback, "bytes_per_row": self.row_bytes, "rows_per_image": height}, (width, height, 1))
        self.device.queue.submit([encoder.finish()])
        self.readback.map_sync(wgpu.MapMode.READ)
        raw = np.frombuffer(self.readback.read_mapped(copy=False), np.uint8).reshape(height, self.row_bytes)
        image = raw[:, : width * 4].copy().reshape(height, width, 4)
        self.readback.unmap()
        return image


def timed(function):
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def run(size: int, frames: int) -> list[dict]:
    device = default_device()
    harness = Harness(device)
    # The process's first pipeline pays a one-time driver start-up (~0.5 s); pay it here.
    # A feature set none of the measured scenes uses (no lights), so their first use stays cold.
    warm = replace(scenes(64)["1 directional light, no specular"], lights=())
    harness.prepare(warm)
    harness.frame(harness.specialized(warm))
    rows = []
    for name, scene in scenes(size).items():
        harness.prepare(scene)
        first_specialized, specialized = timed(lambda: harness.specialized(scene))
        first_frame_specialized, image_specialized = timed(lambda: harness.frame(specialized))
        first_uber, uber = timed(lambda: harness.uber(scene))
        first_frame_uber, image_uber = timed(lambda: harness.frame(uber))
        difference = np.abs(image_specialized.astype(int) - image_uber.astype(int))
        times = {"specialized": [], "uber": []}
        for _ in range(2):  # more warm-up
            harness.frame(specialized), harness.frame(uber)
        for _ in range(frames):  # interleaved, so drifting machine load hits both alike
            times["specialized"].append(timed(lambda: harness.frame(specialized))[0])
            times["uber"].append(timed(lambda: harness.frame(uber))[0])
        median = {key: statistics.median(values) for key, values in times.items()}
        rows.append(
            {
                "scene": name,
                "features": object_features(scene, scene.objects[0]).describe(),
                "specialized_ms": 1e3 * median["specialized"],
                "uber_ms": 1e3 * median["uber"],
                "frame_ratio": median["uber"] / median["specialized"],
                "specialized_first_use_ms": 1e3 * (first_specialized + first_frame_specialized - median["specialized"]),
                "uber_first_use_ms": 1e3 * (first_uber + first_frame_uber - median["uber"]),
                "max_difference": int(difference.max()),
                "pixels_differing": float((difference.max(axis=2) > 1).mean()),
            }
        )
        print(f"  {name}: specialized {rows[-1]['specialized_ms']:.1f} ms, uber {rows[-1]['uber_ms']:.1f} ms", file=sys.stderr)
    return rows


def markdown(rows: list[dict], size: int, frames: int, device_name: str, command: str) -> str:
    lines = [
        f"Measured with `{command}` on {device_name}, {size}×{size} pixels, "
        f"median of {frames} interleaved warm frames (render + readback to numpy).",
        "",
        "| scene | specialized frame | uber frame | uber / specialized | specialized first use | uber first use | images differ (max, > 1/255) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        lines.append(
            f"| {row['scene']} | {row['specialized_ms']:.1f} ms | {row['uber_ms']:.1f} ms | **{row['frame_ratio']:.2f}×** "
            f"| {row['specialized_first_use_ms']:.0f} ms | {row['uber_first_use_ms']:.0f} ms "
            f"| {row['max_difference']}/255, {100 * row['pixels_differing']:.2f} % |"
        )
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--frames", type=int, default=15)
    parser.add_argument("--output", type=Path, help="write the Markdown table into this file between the BENCHMARK markers")
    args = parser.parse_args()
    command = "python benchmarks/bench_specialization.py" + (f" --size {args.size}" if args.size != 1024 else "") + (f" --frames {args.frames}" if args.frames != 15 else "")
    rows = run(args.size, args.frames)
    table = markdown(rows, args.size, args.frames, describe_device(default_device()), command)
    print(table)
    if args.output:
        text = args.output.read_text()
        start, end = "<!-- BENCHMARK START -->", "<!-- BENCHMARK END -->"
        before, _, rest = text.partition(start)
        _, _, after = rest.partition(end)
        args.output.write_text(f"{before}{start}\n{table}{end}{after}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
