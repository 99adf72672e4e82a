"""The renderers compared: wgpu-shading itself, its trivial-shader limit, and two peers.

Every peer renders the same GeometryDraw (same triangles, camera, light, material) into
an RGBA8 image with a depth buffer and returns it as a numpy array: a warm frame is
"render + readback to numpy", whatever the peer needs for that.

    wgpu-shading   Renderer.render(scene), Phong shading (the seed's per-fragment lighting)
    limit          our device and readback path, same vertex buffers and depth test, but a
                   vertex shader that only transforms positions and a constant-color
                   fragment shader: what lavapipe needs for the geometry and the pixels alone
                   (RawWgslPeer; its "floor" and "seed WGSL" variants serve the breakdown)
    moderngl       Mesa's llvmpipe OpenGL (EGL, headless) running the seed's GLSL Phong shader
    pygfx          pygfx's offscreen WgpuRenderer with MeshPhongMaterial on the same lavapipe
                   adapter; "default" keeps pygfx's defaults (2× supersampling, FXAA), "lean"
                   turns those off (pixel_ratio=1, ppaa="none") to compare like with like
"""

from __future__ import annotations

import numpy as np

from wgpu_shading import Renderer, Scene
from wgpu_shading.render.gpu.readback import map_for_reading

from .scenes import GeometryDraw


class Peer:
    name = "peer"

    def render(self) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError

    def close(self) -> None:
        pass


# --------------------------------------------------------------------------- wgpu-shading


class WgpuShadingPeer(Peer):
    name = "wgpu-shading"

    def __init__(self, scene: Scene, renderer: Renderer):
        self.scene = scene
        self.renderer = renderer

    def render(self) -> np.ndarray:
        return self.renderer.render(self.scene)


# --------------------------------------------------------------------------- raw WGSL on our device

_TRIVIAL_WGSL = """
struct Uniforms { clip_from_model: mat4x4<f32> }
@group(0) @binding(0) var<uniform> uniforms: Uniforms;

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return uniforms.clip_from_model * vec4<f32>(position, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(0.75, 0.61, 0.23, 1.0);
}
"""

# The seed's GLSL Phong shaders (seed_glsl.py) ported line by line to WGSL, with the
# seed's uniforms in one block: the same math as the moderngl peer, through naga, SPIR-V
# and lavapipe instead of Mesa's GLSL compiler and llvmpipe's OpenGL.
_SEED_WGSL = """
struct Seed {
    mv_matrix: mat4x4<f32>, proj_matrix: mat4x4<f32>, norm_matrix: mat4x4<f32>,
    global_ambient: vec4<f32>,
    light_ambient: vec4<f32>, light_diffuse: vec4<f32>, light_specular: vec4<f32>, light_position: vec4<f32>,
    material_ambient: vec4<f32>, material_diffuse: vec4<f32>, material_specular: vec4<f32>, shininess: vec4<f32>,
}
@group(0) @binding(0) var<uniform> u: Seed;

struct Varyings {
    @builtin(position) position: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) light_dir: vec3<f32>,
    @location(2) vert_pos: vec3<f32>,
}

@vertex
fn vs_main(@location(0) vert_pos: vec3<f32>, @location(1) vert_normal: vec3<f32>) -> Varyings {
    var out: Varyings;
    out.vert_pos = (u.mv_matrix * vec4<f32>(vert_pos, 1.0)).xyz;
    out.light_dir = u.light_position.xyz - out.vert_pos;
    out.normal = (u.norm_matrix * vec4<f32>(vert_normal, 1.0)).xyz;
    out.position = u.proj_matrix * u.mv_matrix * vec4<f32>(vert_pos, 1.0);
    return out;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4<f32> {
    let L = normalize(in.light_dir);
    let N = normalize(in.normal);
    let V = normalize(-in.vert_pos);
    let R = normalize(reflect(-L, N));
    let cos_theta = dot(L, N);
    let cos_phi = dot(V, R);
    let ambient = ((u.global_ambient * u.material_ambient) + (u.light_ambient * u.material_ambient)).xyz;
    let diffuse = u.light_diffuse.xyz * u.material_diffuse.xyz * max(cos_theta, 0.0);
    let specular = u.light_specular.xyz * u.material_specular.xyz * pow(max(cos_phi, 0.0), u.shininess.x);
    return vec4<f32>(ambient + diffuse + specular, 1.0);
}
"""


class RawWgslPeer(Peer):
    """Our device, render target formats, depth test (reversed Z) and readback call, with
    hand-written shaders instead of the Renderer's:

        floor   no draw at all: clear, copy and readback only
        limit   the same vertex and index buffers, a position-only vertex shader and a
                constant-color fragment shader: the floor for this geometry and size
        seed    the seed's Phong shaders ported literally to WGSL (the moderngl peer's math)
    """

    def __init__(self, scene: Scene, renderer: Renderer, draw: GeometryDraw, kind: str = "limit"):
        import wgpu

        from wgpu_shading.render.gpu.targets import COLOR_FORMATS, DEPTH_FORMAT
        from wgpu_shading.render.shaders.uniforms import clip_from_eye

        if kind not in ("floor", "limit", "seed"):
            raise ValueError(kind)
        self.name = {"floor": "floor", "limit": "limit", "seed": "seed WGSL"}[kind]
        self.kind = kind
        self.wgpu = wgpu
        device = self.device = renderer.device
        width, height = self.size = scene.size
        projection = clip_from_eye(scene.camera, width / height)  # reversed Z, like the Renderer
        if kind == "seed":
            code = _SEED_WGSL
            light_position = np.append(draw.light_eye_position, 0.0)
            self.uniform_data = np.concatenate(
                [
                    draw.eye_from_model.T.ravel(), projection.T.ravel(), np.linalg.inv(draw.eye_from_model).ravel(),
                    draw.global_ambient, draw.light_ambient, draw.light_diffuse, draw.light_specular, light_position,
                    draw.material_ambient, draw.material_diffuse, draw.material_specular, (draw.shininess, 0, 0, 0),
                ]
            ).astype(np.float32)
            visibility = wgpu.ShaderStage.VERTEX | wgpu.ShaderStage.FRAGMENT
        else:
            code = _TRIVIAL_WGSL
            self.uniform_data = np.ascontiguousarray((projection @ draw.eye_from_model).T, dtype=np.float32)
            visibility = wgpu.ShaderStage.VERTEX
        size = self.uniform_data.nbytes
        self.uniforms = device.create_buffer(size=size, usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)
        self.positions = device.create_buffer_with_data(data=draw.positions, usage=wgpu.BufferUsage.VERTEX)
        self.normals = device.create_buffer_with_data(data=draw.normals, usage=wgpu.BufferUsage.VERTEX)
        self.indices = device.create_buffer_with_data(data=draw.indices, usage=wgpu.BufferUsage.INDEX)
        self.index_count = draw.indices.size
        module = device.create_shader_module(code=code)
        layout = device.create_bind_group_layout(
            entries=[{"binding": 0, "visibility": visibility, "buffer": {"type": wgpu.BufferBindingType.uniform}}]
        )
        self.bind_group = device.create_bind_group(
            layout=layout, entries=[{"binding": 0, "resource": {"buffer": self.uniforms, "offset": 0, "size": size}}]
        )
        buffers = [{"array_stride": 12, "attributes": [{"format": "float32x3", "offset": 0, "shader_location": 0}]}]
        if kind == "seed":
            buffers.append({"array_stride": 12, "attributes": [{"format": "float32x3", "offset": 0, "shader_location": 1}]})
        self.pipeline = device.create_render_pipeline(
            layout=device.create_pipeline_layout(bind_group_layouts=[layout]),
            vertex={"module": module, "entry_point": "vs_main", "buffers": buffers},
            primitive={"topology": "triangle-list", "cull_mode": "none"},
            depth_stencil={"format": DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": "greater"},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": COLOR_FORMATS["rgba8"]}]},
        )
        usage = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC
        self.color = device.create_texture(size=(width, height, 1), format=COLOR_FORMATS["rgba8"], usage=usage)
        self.depth = device.create_texture(size=(width, height, 1), format=DEPTH_FORMAT, usage=usage)
        self.color_view, self.depth_view = self.color.create_view(), self.depth.create_view()
        self.row_bytes = -(-width * 4 // 256) * 256
        self.readback = device.create_buffer(
            size=self.row_bytes * height, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST
        )

    def render(self) -> np.ndarray:
        wgpu, device = self.wgpu, self.device
        width, height = self.size
        device.queue.write_buffer(self.uniforms, 0, self.uniform_data.tobytes())
        encoder = device.create_command_encoder()
        render_pass = encoder.begin_render_pass(
            color_attachments=[
                {"view": self.color_view, "clear_value": (0, 0, 0, 1), "load_op": "clear", "store_op": "store"}
            ],
            depth_stencil_attachment={
                "view": self.depth_view,
                "depth_clear_value": 0.0,
                "depth_load_op": "clear",
                "depth_store_op": "store",
            },
        )
        if self.kind != "floor":
            render_pass.set_pipeline(self.pipeline)
            render_pass.set_bind_group(0, self.bind_group)
            render_pass.set_vertex_buffer(0, self.positions)
            if self.kind == "seed":
                render_pass.set_vertex_buffer(1, self.normals)
            render_pass.set_index_buffer(self.indices, wgpu.IndexFormat.uint32)
            render_pass.draw_indexed(self.index_count)
        render_pass.end()
        encoder.copy_texture_to_buffer(
            {"texture": self.color},
            {"buffer": self.readback, "bytes_per_row": self.row_bytes, "rows_per_image": height},
            (width, height, 1),
        )
        device.queue.submit([encoder.finish()])
        map_for_reading(self.readback)  # the Renderer's own readback call
        try:
            raw = np.frombuffer(self.readback.read_mapped(copy=False), dtype=np.uint8).reshape(height, self.row_bytes)
            image = raw[:, : width * 4].copy().reshape(height, width, 4)
        finally:
            self.readback.unmap()
        return image


def TrivialLimitPeer(scene: Scene, renderer: Renderer, draw: GeometryDraw) -> RawWgslPeer:
    return RawWgslPeer(scene, renderer, draw, "limit")


# --------------------------------------------------------------------------- moderngl

from .seed_glsl import SEED_FRAGMENT_SHADER, SEED_VERTEX_SHADER  # noqa: E402

_MODERNGL_CONTEXT = None
_OTHER_GL_CONTEXT = False


def note_other_gl_context() -> None:
    """Another OpenGL context lives in this process (pyrender's OSMesa): Mesa's GL dispatch
    is shared, so moderngl must make its own EGL context current again before each frame."""
    global _OTHER_GL_CONTEXT
    _OTHER_GL_CONTEXT = True


def _make_current(ctx) -> None:
    """Our EGL context current again if another GL context may have taken the dispatch.
    EGL still reports ours current then, so entering alone would be a no-op: release first."""
    if _OTHER_GL_CONTEXT:
        ctx.__enter__()
        ctx.__exit__(None, None, None)
        ctx.__enter__()


def moderngl_context():
    """One headless llvmpipe OpenGL 4.3+ context per process (EGL, no display needed)."""
    global _MODERNGL_CONTEXT
    if _MODERNGL_CONTEXT is None:
        import moderngl

        _MODERNGL_CONTEXT = moderngl.create_standalone_context(backend="egl", require=430)
    return _MODERNGL_CONTEXT


class ModernGLPeer(Peer):
    name = "moderngl"

    def __init__(self, draw: GeometryDraw):
        import moderngl

        ctx = self.ctx = moderngl_context()
        _make_current(ctx)
        self.program = ctx.program(vertex_shader=SEED_VERTEX_SHADER, fragment_shader=SEED_FRAGMENT_SHADER)
        self.draw = draw
        self._set("globalAmbient", draw.global_ambient)
        self._set("light.ambient", draw.light_ambient)
        self._set("light.diffuse", draw.light_diffuse)
        self._set("light.specular", draw.light_specular)
        self._set("light.position", tuple(draw.light_eye_position))
        self._set("material.ambient", draw.material_ambient)
        self._set("material.diffuse", draw.material_diffuse)
        self._set("material.specular", draw.material_specular)
        self._set("material.shininess", draw.shininess)
        self.buffers = [
            ctx.buffer(np.ascontiguousarray(draw.positions).tobytes()),
            ctx.buffer(np.ascontiguousarray(draw.normals).tobytes()),
            ctx.buffer(np.ascontiguousarray(draw.indices).tobytes()),
        ]
        self.vao = ctx.vertex_array(
            self.program,
            [(self.buffers[0], "3f", "vertPos"), (self.buffers[1], "3f", "vertNormal")],
            index_buffer=self.buffers[2],
            index_element_size=4,
        )
        width, height = self.size = draw.size
        self.fbo = ctx.framebuffer(
            color_attachments=[ctx.renderbuffer((width, height), components=4)],
            depth_attachment=ctx.depth_renderbuffer((width, height)),
        )
        self.mode = moderngl.TRIANGLES

    def _set(self, name: str, value) -> None:
        if name in self.program:  # the GLSL compiler drops unused uniforms
            self.program[name].value = value

    def render(self) -> np.ndarray:
        ctx, draw = self.ctx, self.draw
        _make_current(ctx)
        # Matrices every frame, like an application that animates (and like our render()).
        model_view = draw.eye_from_model
        self.program["mv_matrix"].write(np.ascontiguousarray(model_view.T, dtype="f4").tobytes())
        self.program["proj_matrix"].write(np.ascontiguousarray(draw.gl_projection().T, dtype="f4").tobytes())
        self.program["norm_matrix"].write(np.ascontiguousarray(np.linalg.inv(model_view), dtype="f4").tobytes())
        self.fbo.use()
        ctx.enable(ctx.DEPTH_TEST)
        self.fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
        self.vao.render(self.mode)
        width, height = self.size
        pixels = np.frombuffer(self.fbo.read(components=4), dtype=np.uint8).reshape(height, width, 4)
        return pixels[::-1]  # OpenGL's rows run bottom-up

    def close(self) -> None:
        for resource in (self.vao, self.fbo, *self.buffers, self.program):
            resource.release()


# --------------------------------------------------------------------------- pygfx


class PygfxPeer(Peer):
    def __init__(self, draw: GeometryDraw, *, lean: bool):
        import pygfx as gfx
        from rendercanvas.offscreen import RenderCanvas

        from wgpu_shading.render.device import select_adapter

        select_pygfx_adapter(gfx, select_adapter)
        self.name = "pygfx lean" if lean else "pygfx"
        width, height = draw.size
        self.canvas = RenderCanvas(size=(width, height), pixel_ratio=1)
        options = {"pixel_ratio": 1, "ppaa": "none"} if lean else {}
        self.renderer = gfx.renderers.WgpuRenderer(self.canvas, **options)
        self.scene = gfx.Scene()
        material = gfx.MeshPhongMaterial(
            color=draw.material_diffuse[:3], specular=draw.material_specular[:3], shininess=draw.shininess
        )
        geometry = gfx.Geometry(positions=draw.positions, normals=draw.normals, indices=draw.indices)
        mesh = gfx.Mesh(geometry, material)
        mesh.local.matrix = draw.world_from_model
        light = gfx.PointLight(color=draw.light_diffuse[:3], intensity=1.0, decay=0)
        light.local.position = draw.light_world_position
        ambient = gfx.AmbientLight(color=draw.global_ambient[:3], intensity=1.0)
        self.scene.add(mesh, light, ambient)
        self.camera = gfx.PerspectiveCamera(draw.fov_y, width / height, depth_range=(draw.near, draw.far))
        self.camera.local.position = draw.camera_eye
        self.camera.look_at(draw.camera_target)
        self.canvas.request_draw(lambda: self.renderer.render(self.scene, self.camera))

    def render(self) -> np.ndarray:
        return np.asarray(self.canvas.draw())

    def close(self) -> None:
        self.canvas.close()


_PYGFX_ADAPTER_SELECTED = False


def select_pygfx_adapter(gfx, select_adapter) -> None:
    """pygfx picks its own adapter unless told; give it the lavapipe adapter we use."""
    global _PYGFX_ADAPTER_SELECTED
    if not _PYGFX_ADAPTER_SELECTED:
        gfx.renderers.wgpu.select_adapter(select_adapter("lavapipe"))
        _PYGFX_ADAPTER_SELECTED = True
