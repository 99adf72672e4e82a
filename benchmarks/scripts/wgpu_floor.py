"""The cold-start floor of wgpu on lavapipe: the least a wgpu-py program must do to draw.

Import wgpu, get the lavapipe adapter and a device, build a trivial render pipeline, draw
one triangle into a 512×512 texture and read it back; no scene, no lighting, no PNG.

    python benchmarks/scripts/wgpu_floor.py [--prebuilt-ffi]

--prebuilt-ffi loads wgpu-py's backend with wgpu-shading's cached cffi type table first
(wgpu_shading/render/_prebuilt_ffi.py); without it, this is plain wgpu-py.
"""

import os
import sys

os.environ.setdefault("NODEVICE_SELECT", "1")
if "--prebuilt-ffi" in sys.argv:
    from wgpu_shading.render._prebuilt_ffi import load_wgpu_native

    load_wgpu_native()
import wgpu  # noqa: E402
import wgpu.backends.wgpu_native.extras as extras  # noqa: E402

extras.set_instance_extras(backends=["Vulkan"])
adapter = next(a for a in wgpu.gpu.enumerate_adapters_sync() if "llvmpipe" in a.info["device"])
device = adapter.request_device_sync()
module = device.create_shader_module(code="""
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(f32(i) - 1.0, f32(i & 1u) * 2.0 - 1.0, 0.5, 1.0);
}
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(1.0, 0.5, 0.0, 1.0); }
""")
pipeline = device.create_render_pipeline(
    layout="auto", vertex={"module": module, "entry_point": "vs"}, primitive={"topology": "triangle-list"},
    fragment={"module": module, "entry_point": "fs", "targets": [{"format": "rgba8unorm"}]},
)
texture = device.create_texture(size=(512, 512, 1), format="rgba8unorm", usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC)
readback = device.create_buffer(size=512 * 512 * 4, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST)
encoder = device.create_command_encoder()
render_pass = encoder.begin_render_pass(color_attachments=[{"view": texture.create_view(), "clear_value": (0, 0, 0, 1), "load_op": "clear", "store_op": "store"}])
render_pass.set_pipeline(pipeline)
render_pass.draw(3)
render_pass.end()
encoder.copy_texture_to_buffer({"texture": texture}, {"buffer": readback, "bytes_per_row": 2048, "rows_per_image": 512}, (512, 512, 1))
device.queue.submit([encoder.finish()])
readback.map_sync(wgpu.MapMode.READ)
assert readback.read_mapped()[512 * 256 * 4 + 1024] != 0  # something was drawn
