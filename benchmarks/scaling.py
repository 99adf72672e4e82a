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


def _measure(renderer: Renderer, scene, rounds: int, frames: int, moderngl: bool) -> dict[str, Timing]:
    draw = geometry_draw(scene, "curve")
    peers = [WgpuShadingPeer(scene, renderer), TrivialLimitPeer(scene, renderer, draw)]
    if moderngl:
        peers.append(ModernGLPeer(draw))
    timings = interleaved({p.name: p.render for p in peers}, rounds=rounds, frames=frames)
    for peer in peers:
        peer.close()
    gc.collect()
    return timings


def triangle_curve(
    renderer: Renderer, counts: tuple[int, ...], *, rounds: int, frames: int, size: int = 512, moderngl: bool = True
) -> list[CurvePoint]:
    points = []
    for count in counts:
        scene = sphere_scene(size, count)
        triangles = scene.objects[0].mesh.triangle_count
        progress(f"scaling: sphere with {triangles:,} triangles at {size}²")
        points.append(CurvePoint(triangles, _measure(renderer, scene, rounds, frames, moderngl)))
    return points


def pixel_curve(
    renderer: Renderer, sides: tuple[int, ...], *, rounds: int, frames: int, segments: int = 72, moderngl: bool = True
) -> list[CurvePoint]:
    """The torus with `segments`² × 2 triangles (72: the 10K torus) at each side²."""
    points = []
    base = torus_scene(512, segments)
    label = "10K" if segments == 72 else f"{base.objects[0].mesh.triangle_count}"
    for side in sides:
        progress(f"scaling: torus {label} at {side}²")
        points.append(CurvePoint(side * side, _measure(renderer, replace(base, size=(side, side)), rounds, frames, moderngl)))
    return points
