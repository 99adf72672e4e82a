"""Warm frame time: render + readback to numpy, after compilation, for every peer.

Also the breakdown of our own frame into its parts (the floor of an empty frame, the
trivial-shader limit, Gouraud, Phong) and the CPU time of each thread, which together
say where the time beyond the limit goes.
"""

from __future__ import annotations

import gc
from dataclasses import dataclass, replace

from wgpu_shading import Renderer

from .measure import SceneTimings, Timing, interleaved, progress, thread_breakdown
from .peers import ModernGLPeer, PygfxPeer, RawWgslPeer, TrivialLimitPeer, WgpuShadingPeer
from .scenes import benchmark_scenes, geometry_draw, settle



def run_warm(
    renderer: Renderer,
    sizes: tuple[int, ...],
    *,
    rounds: int,
    frames: int,
    pygfx: bool = True,
    moderngl: bool = True,
    tiny: bool = False,
) -> list[SceneTimings]:
    """moderngl / pygfx False leave those peers out (the smoke run, without the [bench]
    extra); tiny: the smoke run's small stand-in meshes."""
    rows = []
    for label, size, scene in benchmark_scenes(sizes, tiny=tiny):
        draw = geometry_draw(scene, label)
        progress(f"warm: {label} at {size}² ({draw.triangle_count:,} triangles)")
        settle(renderer, scene)
        peers = [
            WgpuShadingPeer(scene, renderer),
            TrivialLimitPeer(scene, renderer, draw),
        ]
        if moderngl:
            peers.append(ModernGLPeer(draw))
        if pygfx:
            peers += [PygfxPeer(draw, lean=False), PygfxPeer(draw, lean=True)]
        # pygfx's default frame is 10-50x slower: fewer of its frames keep the run short.
        counts = {p.name: (1 if p.name == "pygfx" else frames) for p in peers}
        timings = interleaved({p.name: p.render for p in peers}, rounds=rounds, frames=counts)
        rows.append(SceneTimings(label, size, draw.triangle_count, timings))
        for peer in peers:
            peer.close()
        del peers
        gc.collect()
    return rows


@dataclass
class BreakdownRow:
    scene: str
    size: int
    timings: dict[str, Timing]
    threads: dict[str, dict[str, float]]  # contender -> thread role -> ms CPU per frame


def run_breakdown(
    renderer: Renderer,
    size: int,
    *,
    rounds: int,
    frames: int,
    moderngl: bool = True,
    tiny: bool = False,
    thread_frames: int = 5,
    thread_seconds: float = 1.0,
) -> list[BreakdownRow]:
    """Floor (clear + copy + readback), limit (trivial shaders), Gouraud, Phong, the seed's
    shader ported to WGSL, moderngl; and the CPU of each thread (each contender runs at
    least thread_frames frames and thread_seconds for that)."""
    rows = []
    for label, _, scene in benchmark_scenes((size,), tiny=tiny):
        progress(f"breakdown: {label} at {size}²")
        draw = geometry_draw(scene, label)
        gouraud = replace(scene, shading=replace(scene.shading, frequency="gouraud"))
        floor = RawWgslPeer(scene, renderer, draw, "floor")
        limit = RawWgslPeer(scene, renderer, draw, "limit")
        seed = RawWgslPeer(scene, renderer, draw, "seed")
        gl = ModernGLPeer(draw) if moderngl else None
        contenders = {
            "floor": floor.render,
            "limit": limit.render,
            "gouraud": lambda: renderer.render(gouraud),
            "phong": lambda: renderer.render(scene),
            "seed WGSL": seed.render,
        }
        if gl is not None:
            contenders["moderngl"] = gl.render
        timings = interleaved(contenders, rounds=rounds, frames=frames)
        threads = {
            name: thread_breakdown(contenders[name], min_frames=thread_frames, min_seconds=thread_seconds)
            for name in ("phong", "seed WGSL", "moderngl")
            if name in contenders
        }
        rows.append(BreakdownRow(label, size, timings, threads))
        if gl is not None:
            gl.close()
        gc.collect()
    return rows
