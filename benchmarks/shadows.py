"""A shadowed frame, side by side (issue #26): ours against pyrender (OSMesa,
`RenderFlags.SHADOWS_DIRECTIONAL` / `SHADOWS_SPOT`) and pygfx (`cast_shadow`), the same
scene — a sphere over a ground plane under one casting light — and the same shadow-map
size (pygfx's fixed 1024 texels: pyrender's `SHADOW_TEX_SZ` is set to it, ours is
`--shadow-map-size 1024`); and what our shadow pass costs by map size.

Every peer draws its maps every frame: pyrender and pygfx always do; ours would reuse maps
that cannot have changed, so our light turns by a millionth of a radian between frames (as
in an animation) — "maps reused" is our frame of an unchanged scene, shown beside it.
Interleaved in one process like the warm table (benchmarks/measure.py); goals: ours ≤ 0.5×
pyrender and ≤ 1.0× pygfx (lean: no supersampling or FXAA, like ours).
"""

from __future__ import annotations

import gc
import math
from dataclasses import replace

import numpy as np

from wgpu_shading import Renderer
from wgpu_shading.scene import Camera, DirectionalLight, Material, Scene, SceneObject, ShadowSettings, SpotLight, plane, uv_sphere
from wgpu_shading.study.accuracy.shadow_sweep import turned_lights

from .measure import SceneTimings, interleaved, progress
from .peers import Peer, select_pygfx_adapter
from .pyrender_peer import PyrenderScenes

MAP_SIZE = 1024  # pygfx's (renderstate.shadow_map_size): the size every peer uses here
MAP_SIZES = (256, 512, 1024, 2048, 4096)


def shadow_scene(size: int, light: str, tiny: bool = False) -> Scene:
    """A sphere (20K triangles; 512 tiny) one radius over an 8 × 8 ground, one casting light."""
    slices, stacks = (16, 16) if tiny else (100, 100)
    ball = SceneObject(uv_sphere(1.0, slices, stacks), Material(diffuse=(0.8, 0.55, 0.3, 1.0), specular=(0.3, 0.3, 0.3, 1.0)),
                       translate=(0.0, 2.0, 0.0))
    ground = SceneObject(plane(8.0), Material(diffuse=(0.7, 0.7, 0.7, 1.0)), rotate=(-90.0, 0.0, 0.0))
    if light == "spot":
        lit = SpotLight(position=(3.0, 7.0, 2.0), direction=(-3.0, -7.0, -2.0), cutoff=35.0, exponent=1.0, shadows=True)
    else:
        lit = DirectionalLight(direction=(-0.5, -1.0, -0.3), shadows=True)
    return Scene(objects=(ball, ground), lights=(lit,), camera=Camera(eye=(0.0, 5.0, 9.0), target=(0.0, 0.7, 0.0), near=0.5, far=40.0),
                 size=(size, size), shadows=ShadowSettings(map_size=MAP_SIZE, filter="pcf3", bias=3.0))


class OursMoving(Peer):
    """Our frame drawing its maps: the light turns by 1e-6 rad between frames."""

    def __init__(self, scene: Scene, renderer: Renderer, name: str = "wgpu-shading"):
        self.scenes = (scene, turned_lights(scene))
        self.renderer, self.name, self.count = renderer, name, 0

    def render(self) -> np.ndarray:
        self.count += 1
        return self.renderer.render(self.scenes[self.count % 2])


class OursStatic(Peer):
    def __init__(self, scene: Scene, renderer: Renderer, name: str):
        self.scene, self.renderer, self.name = scene, renderer, name

    def render(self) -> np.ndarray:
        return self.renderer.render(self.scene)


class PyrenderShadowPeer(Peer):
    """pyrender with shadows of the light's kind, maps of MAP_SIZE texels."""

    name = "pyrender"

    def __init__(self, scene: Scene):
        import pyrender
        from pyrender import light as pyrender_light, renderer as pyrender_renderer

        for module in (pyrender_light, pyrender_renderer):  # the map size (pyrender/constants.py SHADOW_TEX_SZ)
            module.SHADOW_TEX_SZ = MAP_SIZE
        self.scene, self.scenes = scene, PyrenderScenes()
        kind = scene.lights[0].kind
        self.flags = pyrender.RenderFlags.SHADOWS_SPOT if kind == "spot" else pyrender.RenderFlags.SHADOWS_DIRECTIONAL

    def render(self) -> np.ndarray:
        return self.scenes.render(self.scene, flags=self.flags)[0]

    def close(self) -> None:
        self.scenes.close()


class PygfxShadowPeer(Peer):
    """pygfx (lean: pixel_ratio 1, no FXAA) with the light's `cast_shadow`, every object
    casting and receiving, its 1024-texel maps; the directional light's shadow camera
    covers the ground (pygfx does not fit it)."""

    name = "pygfx lean"

    def __init__(self, scene: Scene):
        import pygfx as gfx
        from rendercanvas.offscreen import RenderCanvas

        from wgpu_shading.render.device import select_adapter

        select_pygfx_adapter(gfx, select_adapter)
        width, height = scene.size
        self.canvas = RenderCanvas(size=(width, height), pixel_ratio=1)
        self.renderer = gfx.renderers.WgpuRenderer(self.canvas, pixel_ratio=1, ppaa="none")
        self.scene = gfx.Scene()
        for obj in scene.objects:
            mesh = obj.mesh
            geometry = gfx.Geometry(positions=mesh.positions, normals=mesh.normals, indices=mesh.indices)
            material = gfx.MeshPhongMaterial(color=obj.material.diffuse[:3], specular=obj.material.specular[:3],
                                             shininess=obj.material.shininess)
            node = gfx.Mesh(geometry, material)
            node.local.matrix = obj.world_from_model()
            node.cast_shadow = node.receive_shadow = True
            self.scene.add(node)
        light = scene.lights[0]
        if light.kind == "spot":
            lit = gfx.SpotLight(color=light.diffuse[:3], intensity=1.0, angle=math.radians(light.cutoff), decay=0, cast_shadow=True)
            lit.local.position = light.position
        else:
            lit = gfx.DirectionalLight(color=light.diffuse[:3], intensity=1.0, cast_shadow=True)
            lit.local.position = -10.0 * np.asarray(light.direction) / np.linalg.norm(light.direction)
            lit.shadow.camera.width = lit.shadow.camera.height = 12.0
        lit.shadow.bias = 0.0 if light.kind == "spot" else 1e-4
        target = gfx.WorldObject()
        target.local.position = (0.0, 0.0, 0.0) if light.kind != "spot" else tuple(np.add(light.position, light.direction))
        self.scene.add(target)
        lit.target = target
        self.scene.add(lit, gfx.AmbientLight(color=scene.ambient[:3], intensity=1.0))
        camera = scene.camera
        self.camera = gfx.PerspectiveCamera(camera.fov_y, width / height, depth_range=(camera.near, camera.far))
        self.camera.local.position = camera.eye
        self.camera.look_at(camera.target)
        self.canvas.request_draw(lambda: self.renderer.render(self.scene, self.camera))

    def render(self) -> np.ndarray:
        return np.asarray(self.canvas.draw())

    def close(self) -> None:
        self.canvas.close()


def run_shadows(renderer: Renderer, sizes: tuple[int, ...], *, rounds: int, frames: int, tiny: bool = False,
                pyrender: bool = True, pygfx: bool = True) -> dict:
    """{"peers": [SceneTimings per light kind and size], "map_sizes": [SceneTimings of our
    frame by map size, the largest size]}."""
    peers_rows, map_rows = [], []
    for size in sizes:
        for kind in ("directional", "spot"):
            scene = shadow_scene(size, kind, tiny)
            progress(f"shadows: {kind} light at {size}²")
            plain = replace(scene, lights=tuple(replace(light, shadows=False) for light in scene.lights))
            peers: list[Peer] = [OursMoving(scene, renderer), OursStatic(scene, renderer, "wgpu-shading, maps reused"),
                                 OursStatic(plain, renderer, "wgpu-shading, no shadows")]
            if pyrender:
                peers.append(PyrenderShadowPeer(scene))
            if pygfx:
                peers.append(PygfxShadowPeer(scene))
            timings = interleaved({p.name: p.render for p in peers}, rounds=rounds, frames=frames)
            peers_rows.append(SceneTimings(f"{kind} light", size, sum(o.mesh.triangle_count for o in scene.objects), timings))
            for peer in peers:
                peer.close()
            gc.collect()
    size = max(sizes)
    scene = shadow_scene(size, "directional", tiny)
    plain = replace(scene, lights=tuple(replace(light, shadows=False) for light in scene.lights))
    progress(f"shadows: the shadow pass by map size at {size}²")
    contenders = {"no shadows": OursStatic(plain, renderer, "no shadows").render}
    for map_size in MAP_SIZES[:2] if tiny else MAP_SIZES:
        contenders[f"{map_size}"] = OursMoving(replace(scene, shadows=replace(scene.shadows, map_size=map_size)), renderer).render
    map_rows.append(SceneTimings("directional light", size, 0, interleaved(contenders, rounds=rounds, frames=frames)))
    return {"peers": peers_rows, "map_sizes": map_rows}


def shadows_table(result: dict) -> str:
    lines = [
        f"## A shadowed frame: ours against pyrender and pygfx, {MAP_SIZE}-texel maps, median ms per frame (CPU ms)\n",
        "| light | size | wgpu-shading (maps drawn) | maps reused | no shadows | pyrender | pygfx lean | ÷ pyrender (≤ 0.5) | ÷ pygfx (≤ 1.0) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in result["peers"]:
        t = row.timings
        ours = t["wgpu-shading"].median_ms

        def cell(name):
            return f"{t[name].median_ms:.1f} ({t[name].cpu_median_ms:.1f})" if name in t else "–"

        def ratio(name, goal):
            return f"{ours / t[name].median_ms:.2f}× {'✓' if ours / t[name].median_ms <= goal else '✗'}" if name in t else "–"

        lines.append(f"| {row.scene} | {row.size}² | {cell('wgpu-shading')} | {cell('wgpu-shading, maps reused')} | "
                     f"{cell('wgpu-shading, no shadows')} | {cell('pyrender')} | {cell('pygfx lean')} | "
                     f"{ratio('pyrender', 0.5)} | {ratio('pygfx lean', 1.0)} |")
    for row in result["map_sizes"]:
        base = row.timings["no shadows"].median_ms
        sizes = [name for name in row.timings if name != "no shadows"]
        lines += ["", f"The shadow pass by map size ({row.scene}, {row.size}², maps drawn every frame), median ms per frame:", "",
                  "| map | frame | shadows cost | CPU ms |", "|---:|---:|---:|---:|",
                  f"| none | {base:.1f} | – | {row.timings['no shadows'].cpu_median_ms:.1f} |"]
        for name in sizes:
            t = row.timings[name]
            lines.append(f"| {name} | {t.median_ms:.1f} | {t.median_ms - base:+.1f} | {t.cpu_median_ms:.1f} |")
    return "\n".join(lines) + "\n"
