"""Scaling curves: warm frame time against triangle count (spheres at 512²) and against
pixel count (the 10K torus from 128² to 2048²), for us, the trivial-shader limit and moderngl."""

from __future__ import annotations

import gc
from dataclasses import dataclass, replace

from wgpu_shading import Renderer

from .measure import Timing, interleaved, progress
from .peers import ModernGLPeer, TrivialLimitPeer, WgpuShadingPeer
from .scenes import geometry_draw, sphere_scene, torus_scene


@dataclass
class CurvePoint:
    x: int  # triangles or pixels
    timings: dict[str, Timing]


def _measure(renderer: Renderer, scene, rounds: int, frames: int) -> dict[str, Timing]:
    draw = geometry_draw(scene, "curve")
    peers = [WgpuShadingPeer(scene, renderer), TrivialLimitPeer(scene, renderer, draw), ModernGLPeer(draw)]
    timings = interleaved({p.name: p.render for p in peers}, rounds=rounds, frames=frames)
    for peer in peers:
        peer.close()
    gc.collect()
    return timings


def triangle_curve(renderer: Renderer, counts: tuple[int, ...], *, rounds: int, frames: int) -> list[CurvePoint]:
    points = []
    for count in counts:
        scene = sphere_scene(512, count)
        triangles = scene.objects[0].mesh.triangle_count
        progress(f"scaling: sphere with {triangles:,} triangles at 512²")
        points.append(CurvePoint(triangles, _measure(renderer, scene, rounds, frames)))
    return points


def pixel_curve(renderer: Renderer, sides: tuple[int, ...], *, rounds: int, frames: int) -> list[CurvePoint]:
    points = []
    base = torus_scene(512)
    for side in sides:
        progress(f"scaling: torus 10K at {side}²")
        points.append(CurvePoint(side * side, _measure(renderer, replace(base, size=(side, side)), rounds, frames)))
    return points
