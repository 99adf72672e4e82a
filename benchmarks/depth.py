"""Colour + depth, the dataset case: ours against pyrender (OSMesa), side by side.

Every contender returns the colour image and the eye-space depth as numpy arrays:

    wgpu-shading          colour only (`render`), for the cost of depth
    wgpu-shading + depth  `render_frame(scene, depth=True)`: colour + float64 eye depth
    pyrender              `OffscreenRenderer.render(scene)`: colour + float32 eye depth

interleaved in one process like the warm table (benchmarks/measure.py). The target of
issue #21: ours with depth ≤ 0.5× pyrender. Without pyrender (the [bench] extra, and
OSMesa: apt install libosmesa6) the table has our two columns only, and the run says why.
"""

from __future__ import annotations

import gc

from wgpu_shading import Renderer

from .measure import SceneTimings, interleaved, progress
from .peers import WgpuShadingPeer
from .pyrender_peer import PyrenderPeer, WgpuShadingDepthPeer
from .scenes import benchmark_scenes, geometry_draw



def run_depth(
    renderer: Renderer, sizes: tuple[int, ...], *, rounds: int, frames: int, tiny: bool = False, pyrender: bool = True
) -> list[SceneTimings]:
    rows = []
    for label, size, scene in benchmark_scenes(sizes, tiny=tiny):
        draw = geometry_draw(scene, label)
        progress(f"depth: {label} at {size}² ({draw.triangle_count:,} triangles)")
        peers = [WgpuShadingPeer(scene, renderer), WgpuShadingDepthPeer(scene, renderer)]
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
        "| scene | size | wgpu-shading | wgpu-shading + depth | pyrender (colour + depth) | depth costs us | ours + depth ÷ pyrender (≤ 0.5) "
        "| CPU ms: ours + depth / pyrender | CPU ratio |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        ours, with_depth = row.timings["wgpu-shading"].median_ms, row.timings["wgpu-shading + depth"].median_ms
        cpu = row.timings["wgpu-shading + depth"].cpu_median_ms
        if "pyrender" in row.timings:
            pyrender = row.timings["pyrender"].median_ms
            ratio = with_depth / pyrender
            theirs, verdict = f"{pyrender:.1f}", f"{ratio:.2f}× {'✓' if ratio <= 0.5 else '✗'}"
            their_cpu = row.timings["pyrender"].cpu_median_ms
            cpu_cells = f"{cpu:.1f} / {their_cpu:.1f} | {cpu / their_cpu:.2f}×"
        else:
            theirs, verdict, cpu_cells = "–", "–", f"{cpu:.1f} / – | –"
        lines.append(f"| {row.scene} | {row.size}² | {ours:.1f} | {with_depth:.1f} | {theirs} | {with_depth - ours:+.1f} | {verdict} | {cpu_cells} |")
    return "\n".join(lines) + "\n"
