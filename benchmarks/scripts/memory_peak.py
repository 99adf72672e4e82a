"""Peak resident memory of rendering one big mesh, in a fresh process (Linux).

    python benchmarks/scripts/memory_peak.py MESH.npz SIZE

Baseline: the process after start-up, device creation and one small render (pipeline
compiled). Then the mesh's arrays are loaded from MESH.npz straight into a Mesh (no
temporaries), the kernel's peak-RSS mark is reset (/proc/self/clear_refs), the mesh is
rendered, and the peak read back (VmHWM). Prints one JSON object of bytes.
"""

import gc
import json
import sys
from dataclasses import replace

import numpy as np

from wgpu_shading import Renderer
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.scene import Mesh

from load_peak import status  # (this folder: the same peak measurement)

size = int(sys.argv[2])
renderer = Renderer()
small = mesh_scene("builtin:sphere", (size, size), None)
renderer.render(small)
small_uploaded = renderer.device_cache.meshes.nbytes
gc.collect()
baseline = status("VmRSS")
arrays = np.load(sys.argv[1])
mesh = Mesh(positions=arrays["positions"], normals=arrays["normals"], indices=arrays["indices"], uvs=arrays["uvs"])
with_mesh = status("VmRSS")
with open("/proc/self/clear_refs", "w") as file:
    file.write("5")  # reset the peak-RSS mark to the current RSS
image = renderer.render(replace(small, objects=(replace(small.objects[0], mesh=mesh),)))
assert (image[:, :, :3] > 0).any()
print(json.dumps({
    "triangles": mesh.triangle_count,
    "mesh_bytes": mesh.nbytes,
    "baseline": baseline,
    "with_mesh": with_mesh,
    "peak": status("VmHWM"),
    "after": status("VmRSS"),
    # Our GPU buffers for the mesh (driver memory; on lavapipe the buffers are host memory).
    "uploaded": renderer.device_cache.meshes.nbytes - small_uploaded,
}))
