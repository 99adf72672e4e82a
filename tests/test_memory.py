"""Memory: uploading a mesh costs one driver-side copy of its arrays, not two.

On lavapipe (a CPU adapter) the default device allows mapping mesh buffers directly
(device.DIRECT_UPLOAD_FEATURE), so wgpu needs no staging buffer for the upload. Resident
memory is read from /proc in a fresh process; nothing is timed.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading.render.device import uses_direct_upload

MEASURE_UPLOAD = """
import gc, numpy as np
from wgpu_shading import Renderer
from wgpu_shading.scene import Mesh

def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS"):
            return int(line.split()[1]) * 1024

renderer = Renderer()
rng = np.random.default_rng(1)
vertices = 1_000_000
mesh = Mesh(
    positions=rng.random((vertices, 3), dtype=np.float32),
    normals=np.tile(np.float32([0, 0, 1]), (vertices, 1)),
    indices=rng.integers(0, vertices, (2_000_000, 3), dtype=np.uint32),
)
gc.collect()
before = rss()
renderer._gpu_mesh(mesh)
renderer.device.queue.submit([])
renderer.device._poll_wait()  # let wgpu finish (and free) any staging copy
print((rss() - before) / mesh.nbytes)
"""


def test_the_default_lavapipe_device_uploads_meshes_in_place(renderer):
    assert uses_direct_upload(renderer.device)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_a_mesh_upload_costs_one_copy_of_the_mesh():
    result = subprocess.run([sys.executable, "-c", MEASURE_UPLOAD], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    growth = float(result.stdout.strip())
    assert 0.8 < growth < 1.3  # one copy (the driver's); a staging buffer would make it ~2


def test_texture_coordinates_are_uploaded_when_a_textured_draw_first_needs_them(renderer):
    from dataclasses import replace

    from wgpu_shading import Renderer, load_scene

    textured = load_scene(Path(__file__).resolve().parent.parent / "examples" / "checker_sphere_modulate.toml")
    (obj,) = textured.objects
    plain = replace(textured, objects=(replace(obj, material=replace(obj.material, texture=None)),))
    fresh = Renderer(device=renderer.device)
    untextured_first = fresh.render(plain)
    assert fresh._meshes[obj.mesh].uvs is None  # an untextured draw leaves them out
    textured_image = fresh.render(textured)
    assert fresh._meshes[obj.mesh].uvs is not None
    np.testing.assert_array_equal(textured_image, Renderer(device=renderer.device).render(textured))
    assert not np.array_equal(textured_image, untextured_first)
