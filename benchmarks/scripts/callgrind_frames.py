"""Warm frames of one contender, for deterministic A/B measurements with callgrind.

Wall time on a shared 2-core machine is noisy; instruction counts are not. Run under
valgrind with instrumentation switched on only around the warm frames:

    gcc -shared -fPIC -O2 -o /tmp/callgrind_toggle.so -x c - <<'C'
    #include <valgrind/callgrind.h>
    void start(void) { CALLGRIND_ZERO_STATS; CALLGRIND_START_INSTRUMENTATION; }
    void stop(void) { CALLGRIND_STOP_INSTRUMENTATION; CALLGRIND_DUMP_STATS; }
    C
    CALLGRIND_TOGGLE=/tmp/callgrind_toggle.so valgrind --tool=callgrind --instr-atstart=no \\
        python benchmarks/scripts/callgrind_frames.py ours --mesh torus --size 512 --frames 3
    callgrind_annotate callgrind.out.*.1 | head -30    # JIT code shows as ???:0x... [???]

Contenders: ours (Renderer.render), depth (render_frame(depth=True)), seed / limit (the raw
WGSL peers of benchmarks/peers.py), gl (moderngl, the seed's GLSL). WGPU_SHADING_VERTEX_ORDER=0
uploads meshes in their own order. Without valgrind it just renders (what --smoke checks).
docs/performance.md quotes the counts.
"""

from __future__ import annotations

import argparse
import ctypes
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository (benchmarks/ and the package)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("contender", choices=("ours", "depth", "seed", "limit", "gl"))
    parser.add_argument("--mesh", choices=("torus", "bunny", "sphere"), default="torus")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--smoke", action="store_true", help="a tiny torus at 32², one frame of every contender but gl")
    args = parser.parse_args(argv)

    from benchmarks.peers import RawWgslPeer, WgpuShadingPeer
    from benchmarks.scenes import bunny_scene, geometry_draw, sphere_scene, torus_scene
    from wgpu_shading import Renderer

    if args.smoke:
        scene, contenders, frames = torus_scene(32, 8), ("ours", "depth", "seed", "limit"), 1
    else:
        scene = {"torus": torus_scene, "bunny": bunny_scene, "sphere": sphere_scene}[args.mesh](args.size)
        if scene is None:
            parser.error("the bunny needs ../shared/models/stanford-bunny.obj")
        contenders, frames = (args.contender,), args.frames
    renderer = Renderer()
    toggle = ctypes.CDLL(os.environ["CALLGRIND_TOGGLE"]) if os.environ.get("CALLGRIND_TOGGLE") else None
    for contender in contenders:
        draw = geometry_draw(scene, args.mesh)
        if contender == "gl":
            from benchmarks.peers import ModernGLPeer

            render = ModernGLPeer(draw).render
        elif contender == "ours":
            render = WgpuShadingPeer(scene, renderer).render
        elif contender == "depth":
            render = lambda: renderer.render_frame(scene, depth=True).color  # noqa: E731
        else:
            render = RawWgslPeer(scene, renderer, draw, contender).render
        for _ in range(2):  # compiled, uploaded, caches warm
            render()
        if toggle is not None:
            toggle.start()
        for _ in range(frames):
            image = render()
        if toggle is not None:
            toggle.stop()
        print(f"{contender}: {frames} frame(s) of {args.mesh if not args.smoke else 'tiny torus'}, image mean {image.mean():.6f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
