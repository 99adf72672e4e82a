"""The uniform layout: declared once in wgsl/structs.wgsl, derived into numpy dtypes by
layout.py, and proved on the GPU: a compute shader reads every field by name (the GPU's
own layout rules) and writes the values out; Python filled the buffer through the
derived dtype. A wrong offset anywhere shows up as a misplaced value."""

from __future__ import annotations

import numpy as np
import pytest
import wgpu

from wgpu_shading.render.features import FeatureSet
from wgpu_shading.render.shaders.layout import Layouts, field_offsets
from wgpu_shading.render.shaders.preprocess import preprocess
from wgpu_shading.render.shaders.shadergen import generate_wgsl

EVERY_EXTRA = FeatureSet(
    frequency="phong",
    reflection="blinn-phong",
    directional_lights=2,
    positional_lights=3,
    spot_lights=2,
    attenuation=True,
    specular=True,
    emission=True,
)


def test_seed_structs_keep_the_seed_offsets():
    """docs/conventions.md#uniform-layout: PositionalLight and Material are the seed's structs byte for byte."""
    layouts = Layouts(generate_wgsl(FeatureSet(positional_lights=1)))
    light = layouts.dtype("PositionalLight")
    assert field_offsets(light) == {"ambient": 0, "diffuse": 16, "specular": 32, "position": 48}
    assert light.itemsize == 64
    material = layouts.dtype("Material")
    assert field_offsets(material) == {"ambient": 0, "diffuse": 16, "specular": 32, "shininess": 48}
    assert material.itemsize == 64
    # array<PositionalLight, N> has stride 64
    two = Layouts(generate_wgsl(FeatureSet(positional_lights=2))).dtype("FrameUniforms")
    offsets = field_offsets(two)
    assert offsets["positional_lights[1].ambient"] - offsets["positional_lights[0].ambient"] == 64


def test_extras_come_after_the_seed_fields():
    layouts = Layouts(generate_wgsl(EVERY_EXTRA))
    light = field_offsets(layouts.dtype("PositionalLight"))
    assert light["position"] == 48 and light["attenuation"] == 64
    material = field_offsets(layouts.dtype("Material"))
    assert material["shininess"] == 48 and material["emission"] == 64


def test_absent_effects_have_no_uniform_fields():
    layouts = Layouts(generate_wgsl(FeatureSet(positional_lights=1)))
    assert "attenuation" not in layouts.dtype("PositionalLight").names
    assert "emission" not in layouts.dtype("Material").names
    frame = layouts.dtype("FrameUniforms").names
    assert "spot_lights" not in frame and "directional_lights" not in frame
    assert "blinn_exponent_scale" not in frame


def _leaves(dtype: np.dtype, wgsl_prefix: str, fields: tuple, indices: tuple):
    """(WGSL expression, numpy field chain, numpy index) for every float in `dtype`."""
    for name in dtype.names:
        field_dtype = dtype.fields[name][0]
        path = f"{wgsl_prefix}{name}"
        if field_dtype.names:  # nested struct
            yield from _leaves(field_dtype, path + ".", fields + (name,), indices)
        elif field_dtype.subdtype is not None and field_dtype.base.names:  # array of structs
            for i in range(field_dtype.shape[0]):
                yield from _leaves(field_dtype.base, f"{path}[{i}].", fields + (name,), indices + (i,))
        elif field_dtype.shape == ():
            yield path, fields + (name,), indices
        elif len(field_dtype.shape) == 1:
            for k in range(field_dtype.shape[0]):
                yield f"{path}.{'xyzw'[k]}", fields + (name,), indices + (k,)
        else:  # matrix, numpy shape (columns, padded rows); mat3x3 has 3 real rows of 4
            columns, padded = field_dtype.shape
            rows = 3 if (columns, padded) == (3, 4) else padded
            for c in range(columns):
                for r in range(rows):
                    yield f"{path}[{c}][{r}]", fields + (name,), indices + (c, r)


@pytest.mark.parametrize("struct, variable", [("FrameUniforms", "frame_uniforms"), ("ObjectUniforms", "object_uniforms")])
def test_layout_on_the_gpu(renderer, struct, variable):
    device = renderer.device
    header = generate_wgsl(EVERY_EXTRA).split("\n\n", 1)[0]  # comment + light-count constants
    structs = preprocess("structs.wgsl", EVERY_EXTRA.defines())
    layouts = Layouts(header + "\n" + structs)
    dtype = layouts.dtype(struct)
    leaves = list(_leaves(dtype, f"{variable}.", (), ()))
    data = np.zeros((), dtype)
    for value, (_, fields, index) in enumerate(leaves, start=1):
        view = data
        for name in fields:
            view = view[name]
        view[index] = value
    copies = "\n".join(f"    readback[{i}] = {expression};" for i, (expression, _, _) in enumerate(leaves))
    source = f"""{header}
{structs}
@group(0) @binding(0) var<uniform> {variable}: {struct};
@group(0) @binding(1) var<storage, read_write> readback: array<f32>;
@compute @workgroup_size(1)
fn main() {{
{copies}
}}
"""
    uniform = device.create_buffer_with_data(data=data.tobytes(), usage=wgpu.BufferUsage.UNIFORM)
    storage = device.create_buffer(size=4 * len(leaves), usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC)
    pipeline = device.create_compute_pipeline(
        layout="auto", compute={"module": device.create_shader_module(code=source), "entry_point": "main"}
    )
    group = device.create_bind_group(
        layout=pipeline.get_bind_group_layout(0),
        entries=[{"binding": 0, "resource": {"buffer": uniform}}, {"binding": 1, "resource": {"buffer": storage}}],
    )
    encoder = device.create_command_encoder()
    compute = encoder.begin_compute_pass()
    compute.set_pipeline(pipeline)
    compute.set_bind_group(0, group)
    compute.dispatch_workgroups(1)
    compute.end()
    device.queue.submit([encoder.finish()])
    got = np.frombuffer(device.queue.read_buffer(storage), dtype=np.float32)
    expected = np.arange(1, len(leaves) + 1, dtype=np.float32)
    wrong = [leaves[i][0] for i in np.flatnonzero(got != expected)]
    assert not wrong, f"fields read back wrong on the GPU: {wrong[:10]}"
    assert len(leaves) > 40  # the test really covered the big structs
