"""Where a cold `wgpu-shading render builtin:torus -o OUT.png` spends its time: the CLI's
own steps, timed one by one in a fresh process. Prints one JSON object of seconds:
{"wall": {phase: s}, "cpu": {phase: s}} (CPU: this process's user + system time, every thread).

    python benchmarks/scripts/cold_phases.py OUT.png [SIZE]

SIZE: the image side, as the CLI's --size (default 512, the CLI's default).
"""

import time

start, start_cpu = time.perf_counter(), time.process_time()
import importlib  # noqa: E402  (loaded by the interpreter's start-up already)
import json  # noqa: E402
import sys  # noqa: E402

phases, phases_cpu = {}, {}
last, last_cpu = start, start_cpu


def mark(name):
    """Wall and CPU (this process, every thread) since the last mark."""
    global last, last_cpu
    now, now_cpu = time.perf_counter(), time.process_time()
    phases[name], phases_cpu[name] = now - last, now_cpu - last_cpu
    last, last_cpu = now, now_cpu


# What the program sets for itself first (one BLAS thread, imports without the garbage
# collector, pyglm's typing aliases deferred: cli/process_start.py).
from wgpu_shading.cli.process_start import command_starts, start_process  # noqa: E402

start_process()
importlib.import_module("numpy")  # imported for its cost only (a bare import reads as unused)

mark("import numpy")
from wgpu_shading.assets.mesh_scene import mesh_scene  # noqa: E402

command_starts("render", None)  # collector on, start-up objects frozen, lavapipe's driver only
mark("import wgpu_shading (+cli)")
size = int(sys.argv[2]) if len(sys.argv) > 2 else 512
scene = mesh_scene("builtin:torus", (size, size), None)
mark("scene and mesh")
from wgpu_shading.render._prebuilt_ffi import load_wgpu_native  # noqa: E402

load_wgpu_native()
importlib.import_module("wgpu.backends.wgpu_native")  # already loaded unless the prebuilt FFI is off

mark("import wgpu + its native backend (cffi)")
from wgpu_shading.render import device as device_module  # noqa: E402

adapter = device_module.select_adapter()
mark("instance + adapter enumeration")
device = device_module.default_device()
mark("device")
from wgpu_shading.render.passes.color import color_key  # noqa: E402
from wgpu_shading.render.renderer import Renderer  # noqa: E402

renderer = Renderer(device=device)
mark("import renderer + Renderer()")
renderer.device_cache.pipelines.get(color_key(renderer.features(scene)[0]))
mark("first pipeline (WGSL -> SPIR-V -> NIR)")
image = renderer.render(scene)
mark("first draw + readback (LLVM JIT of shader variants)")
from pathlib import Path  # noqa: E402

from wgpu_shading.assets.image_writers import write_image  # noqa: E402

write_image(Path(sys.argv[1]), image)
mark("PNG write (as the CLI does it)")
print(json.dumps({"wall": phases, "cpu": phases_cpu}))
