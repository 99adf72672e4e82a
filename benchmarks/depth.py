"""Colour + depth, the dataset case: ours against pyrender (OSMesa), side by side.

Every contender returns the colour image and the eye-space depth as numpy arrays:

    wgpu-shading          colour only (`render`), for the cost of depth
    wgpu-shading + depth  `render_frame(scene, depth=True)`: colour + float64 eye depth
    every triangle        the same with WGPU_SHADING_CLUSTERS=0 and no back-face culling: no
                          cluster of triangles turned away left out (render/gpu/clusters.py),
                          none culled (render/passes/turned_away.py), the A/B of those
    pyrender              `OffscreenRenderer.render(scene)`: colour + float32 eye depth

interleaved in one process like the warm table (benchmarks/measure.py), after
scenes.settle: the steady state of a mesh drawn many times, whose upload then has its
clusters (the closed spheres: the smoke run's 20K one too). The targets: ours with depth
≤ 0.5× pyrender (issue #21), the 1.3M sphere ≤ 0.7× (issue #29). Without pyrender (the
[bench] extra, and OSMesa: apt install libosmesa6) the table has our columns only, and the
run says why.
"""

from __future__ import annotations

import gc
import os
from dataclasses import replace

from wgpu_shading import Renderer
from wgpu_shading.render.passes import turned_away

from .measure import SceneTimings, interleaved, progress
from .peers import WgpuShadingPeer
from .pyrender_peer import PyrenderPeer, WgpuShadingDepthPeer
from .scenes import benchmark_scenes, geometry_draw, settle


class EveryTrianglePeer(WgpuShadingDepthPeer):
    """Colour + depth with every triangle drawn, for its frames only: WGPU_SHADING_CLUSTERS=0
    (no cluster left out) and no mesh small enough to be culled by the rasterizer
    (turned_away.CULLED_MAX_TRIANGLES), on a Scene object of its own (its own frame plan)."""

    name = "every triangle"

    def __init__(self, scene, renderer):
        super().__init__(replace(scene), renderer)

    def render(self):
        os.environ["WGPU_SHADING_CLUSTERS"] = "0"
        shipped = turned_away.CULLED_MAX_TRIANGLES
        turned_away.CULLED_MAX_TRIANGLES = -1
        try:
            return super().render()
        finally:
            os.environ.pop("WGPU_SHADING_CLUSTERS")
            turned_away.CULLED_MAX_TRIANGLES = shipped


def run_depth(
    renderer: Renderer, sizes: tuple[int, ...], *, rounds: int, frames: int, tiny: bool = False, pyrender: bool = True
) -> list[SceneTimings]:
    rows = []
    for label, size, scene in benchmark_scenes(sizes, tiny=tiny):
        draw = geometry_draw(scene, label)
        progress(f"depth: {label} at {size}² ({draw.triangle_count:,} triangles)")
        peers = [WgpuShadingPeer(scene, renderer), WgpuShadingDepthPeer(scene, renderer), EveryTrianglePeer(scene, renderer)]
        settle(renderer, scene)
        if pyrender:
            peers.append(PyrenderPeer(scene))
        timings = interleaved({p.name: p.render for p in peers}, rounds=rounds, frames=frames)
        rows.append(SceneTimings(label, size, draw.triangle_count, timings))
        for peer in peers:
            peer.close()
        del peers
        gc.collect()
    return rows


def depth_table(rows: list[SceneTimings]) -> str:
    lines = [
        "## Colour + depth: ours against pyrender (OSMesa), median ms per frame\n",
        "| scene | size | wgpu-shading | wgpu-shading + depth | every triangle | pyrender (colour + depth) | depth costs us "
        "| ours + depth ÷ pyrender (≤ 0.5) | CPU ms: ours + depth / pyrender | CPU ratio | CPU ms: every triangle | culling: CPU ratio |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        ours, with_depth = row.timings["wgpu-shading"].median_ms, row.timings["wgpu-shading + depth"].median_ms
        cpu = row.timings["wgpu-shading + depth"].cpu_median_ms
        every = row.timings["every triangle"]
        culling = f"{every.median_ms:.1f}", f"{every.cpu_median_ms:.1f} | {cpu / every.cpu_median_ms:.2f}×"
        if "pyrender" in row.timings:
            pyrender = row.timings["pyrender"].median_ms
            ratio = with_depth / pyrender
            theirs, verdict = f"{pyrender:.1f}", f"{ratio:.2f}× {'✓' if ratio <= 0.5 else '✗'}"
            their_cpu = row.timings["pyrender"].cpu_median_ms
            cpu_cells = f"{cpu:.1f} / {their_cpu:.1f} | {cpu / their_cpu:.2f}×"
        else:
            theirs, verdict, cpu_cells = "–", "–", f"{cpu:.1f} / – | –"
        lines.append(
            f"| {row.scene} | {row.size}² | {ours:.1f} | {with_depth:.1f} | {culling[0]} | {theirs} | {with_depth - ours:+.1f} "
            f"| {verdict} | {cpu_cells} | {culling[1]} |"
        )
    return "\n".join(lines) + "\n"
