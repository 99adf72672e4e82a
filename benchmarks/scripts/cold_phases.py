"""Where a cold `wgpu-shading render builtin:torus -o OUT.png` spends its time: the CLI's
own steps, timed one by one in a fresh process. Prints one JSON object of seconds.

    python benchmarks/scripts/cold_phases.py OUT.png
"""

import time

start = time.perf_counter()
import json  # noqa: E402
import sys  # noqa: E402

phases = {}
last = start


def mark(name):
    global last
    now = time.perf_counter()
    phases[name] = now - last
    last = now


import numpy  # noqa: E402,F401

mark("import numpy")
from wgpu_shading.assets.mesh_scene import mesh_scene  # noqa: E402

mark("import wgpu_shading (+cli)")
scene = mesh_scene("builtin:torus", (512, 512), None)
mark("scene and mesh")
from wgpu_shading.render._prebuilt_ffi import load_wgpu_native  # noqa: E402

load_wgpu_native()
import wgpu.backends.wgpu_native  # noqa: E402,F401  (already loaded unless the prebuilt FFI is off)

mark("import wgpu + its native backend (cffi)")
from wgpu_shading.render import device as device_module  # noqa: E402

adapter = device_module.select_adapter()
mark("instance + adapter enumeration")
device = device_module.default_device()
mark("device")
from wgpu_shading.render.renderer import Renderer  # noqa: E402

renderer = Renderer(device=device)
mark("import renderer + Renderer()")
renderer._pipelines.get(renderer.features(scene)[0])
mark("first pipeline (WGSL -> SPIR-V -> NIR)")
image = renderer.render(scene)
mark("first draw + readback (LLVM JIT of shader variants)")
from pathlib import Path  # noqa: E402

from wgpu_shading.assets.images import write_image  # noqa: E402

write_image(Path(sys.argv[1]), image)
mark("PNG write (as the CLI does it)")
print(json.dumps(phases))
