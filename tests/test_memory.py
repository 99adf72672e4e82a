"""Memory: uploading a mesh costs one driver-side copy of its arrays, not two.

On lavapipe (a CPU adapter) the default device allows mapping mesh buffers directly
(device.DIRECT_UPLOAD_FEATURE), so wgpu needs no staging buffer for the upload. Resident
memory is read from /proc in a fresh process; nothing is timed.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading.render.device import uses_direct_upload

MEASURE_UPLOAD = """
import gc, numpy as np
from wgpu_shading import Renderer
from wgpu_shading.scene import Mesh

def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS"):
            return int(line.split()[1]) * 1024

renderer = Renderer()
rng = np.random.default_rng(1)
vertices = 1_000_000
mesh = Mesh(
    positions=rng.random((vertices, 3), dtype=np.float32),
    normals=np.tile(np.float32([0, 0, 1]), (vertices, 1)),
    indices=rng.integers(0, vertices, (2_000_000, 3), dtype=np.uint32),
)
gc.collect()
before = rss()
renderer.device_cache.gpu_mesh(mesh)  # the upload alone
renderer.device.queue.submit([])
renderer.device._poll_wait()  # let wgpu finish (and free) any staging copy
print((rss() - before) / mesh.nbytes)
"""


def test_the_default_lavapipe_device_uploads_meshes_in_place(renderer):
    assert uses_direct_upload(renderer.device)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_a_mesh_upload_costs_one_copy_of_the_mesh():
    result = subprocess.run([sys.executable, "-c", MEASURE_UPLOAD], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    growth = float(result.stdout.strip())
    assert 0.8 < growth < 1.3  # one copy (the driver's); a staging buffer would make it ~2


def test_texture_coordinates_are_uploaded_when_a_textured_draw_first_needs_them(renderer):
    from dataclasses import replace

    from wgpu_shading import Renderer, load_scene

    textured = load_scene(Path(__file__).resolve().parent.parent / "examples" / "checker_sphere_modulate.toml")
    (obj,) = textured.objects
    plain = replace(textured, objects=(replace(obj, material=replace(obj.material, texture=None)),))
    fresh = Renderer(device=renderer.device)
    untextured_first = fresh.render(plain)
    assert fresh.device_cache.meshes.get(obj.mesh).uvs is None  # an untextured draw leaves them out
    textured_image = fresh.render(textured)
    assert fresh.device_cache.meshes.get(obj.mesh).uvs is not None
    np.testing.assert_array_equal(textured_image, Renderer(device=renderer.device).render(textured))
    assert not np.array_equal(textured_image, untextured_first)


def _live_gpu_objects() -> dict[str, int]:
    import gc

    import wgpu

    gc.collect()
    counts = wgpu.diagnostics.object_counts.get_dict()
    return {kind: value["count"] for kind, value in counts.items() if kind != "total"}


def test_a_long_run_with_new_sizes_meshes_and_feature_sets_levels_off(renderer):
    """Every frame has a new output size and a new (still referenced) mesh, and the feature
    set cycles through more pipelines than the cache holds: the number of live GPU objects
    must stop growing once the caches are full."""
    from wgpu_shading import PositionalLight, Renderer, Scene, SceneObject, Shading
    from wgpu_shading.render.gpu.caches import MESH_CACHE_ENTRIES, TARGET_CACHE_ENTRIES
    from wgpu_shading.render.gpu.pipelines import PipelineCache
    from wgpu_shading.scene.geometry.builtins import uv_sphere

    long_run = Renderer(device=renderer.device)
    long_run.device_cache.pipelines = PipelineCache(renderer.device, max_entries=2)  # 4 feature sets below
    kept_meshes = []  # the caller keeps every mesh alive: only eviction can free the uploads
    shadings = [Shading(frequency=f, reflection=r) for f in ("flat", "gouraud") for r in ("phong", "blinn-phong")]

    def frames(start: int, count: int) -> dict[str, int]:
        for index in range(start, start + count):
            mesh = uv_sphere(slices=6 + index % 5, stacks=4)
            kept_meshes.append(mesh)
            scene = Scene(
                objects=(SceneObject(mesh),), lights=(PositionalLight(),),
                shading=shadings[index % len(shadings)], size=(16 + index, 16 + index % 7),
            )
            assert long_run.render(scene)[8, 8, 3] == 255  # the sphere covers the centre
        return _live_gpu_objects()

    frames(0, MESH_CACHE_ENTRIES + 8)  # fill every cache
    full = frames(100, 40)
    later = frames(200, 40)
    assert later == full, f"live GPU objects still grow: {full} → {later}"
    assert long_run.device_cache.free_target_count == TARGET_CACHE_ENTRIES
    assert len(long_run.device_cache.meshes) == MESH_CACHE_ENTRIES and long_run.device_cache.meshes.evictions > 0
    assert long_run.pipeline_count == 2


def test_the_first_mip_level_is_computed_in_strips_with_the_same_values():
    """A 16384² texture would need 4 GiB as float32 at once; strips of rows give the same
    exact means (odd sizes: the last row and column are repeated, then dropped)."""
    from wgpu_shading.render.gpu.mips import _first_level

    rng = np.random.default_rng(3)
    for height, width in [(1, 1), (7, 1), (5, 5), (1025, 3), (130, 77)]:
        pixels = rng.integers(0, 256, (height, width, 4), dtype=np.uint8)
        whole = _first_level(pixels, rows_per_strip=10**9)
        padded = pixels
        if height % 2:
            padded = np.concatenate([padded, padded[-1:]], axis=0)
        if width % 2:
            padded = np.concatenate([padded, padded[:, -1:]], axis=1)
        exact = padded.astype(np.float64).reshape(padded.shape[0] // 2, 2, padded.shape[1] // 2, 2, 4).mean(axis=(1, 3))
        np.testing.assert_array_equal(whole, exact[: max(1, height // 2), : max(1, width // 2)])
        for rows in (2, 4, 64):
            np.testing.assert_array_equal(_first_level(pixels, rows_per_strip=rows), whole)


def test_one_byte_bound_holds_for_every_stored_format_of_an_object():
    """A texture stored in two formats (rgba8unorm, and rgba8unorm-srgb for a linear-space
    draw) is two entries of ONE cache, so TEXTURE_CACHE_BYTES bounds both together."""
    import gc

    from wgpu_shading.render.gpu.caches import ObjectCache

    class Image:  # any weak-referenceable object
        pass

    cache: ObjectCache[int] = ObjectCache(max_entries=8, max_bytes=100, size_of=lambda value: value)
    first, second = Image(), Image()
    cache.put(first, 40, "rgba8unorm")
    cache.put(first, 30, "rgba8unorm-srgb")
    assert (cache.get(first, "rgba8unorm"), cache.get(first, "rgba8unorm-srgb"), cache.get(first)) == (40, 30, None)
    assert len(cache) == 2 and cache.nbytes == 70
    cache.put(second, 50, "rgba8unorm")  # 120 > 100: the least recently used entry goes
    assert cache.nbytes == 80 and cache.get(first, "rgba8unorm") is None and cache.get(first, "rgba8unorm-srgb") == 30
    del first
    gc.collect()
    assert len(cache) == 1 and cache.nbytes == 50  # a dead object's every variant goes


def test_a_renderer_keeps_its_textures_in_one_bounded_cache(renderer, monkeypatch):
    """Every texture upload counts against one byte bound (docs/reliability.md), whatever
    format it is stored in: a 4×4 texture with its mip chain (4², 2², 1² texels × 4 bytes)
    is 84 bytes per format. Drawn in display and in linear colour space (rgba8unorm and
    rgba8unorm-srgb), two textures are four uploads; a bound of 200 bytes keeps two."""
    from dataclasses import replace

    from wgpu_shading import Renderer, Texture, load_scene
    from wgpu_shading.render.gpu import device_cache
    from wgpu_shading.render.gpu.caches import ObjectCache

    textured = load_scene(Path(__file__).resolve().parent.parent / "examples" / "checker_sphere_modulate.toml")
    (obj,) = textured.objects
    textures = [Texture(np.full((4, 4, 4), 60 * (k + 1), dtype=np.uint8), name=f"t{k}") for k in range(2)]

    def draw(into: Renderer, texture: Texture, color_space: str) -> None:
        scene = replace(textured, objects=(replace(obj, material=replace(obj.material, texture=texture)),), size=(16, 16))
        into.render(replace(scene, shading=replace(scene.shading, color_space=color_space)))

    unbounded = Renderer(device=renderer.device)
    draw(unbounded, textures[0], "display")
    draw(unbounded, textures[0], "linear")
    assert unbounded.device_cache.textures.nbytes == 2 * 84 and len(unbounded.device_cache.textures) == 2

    monkeypatch.setattr(device_cache, "TEXTURE_CACHE_BYTES", 200)
    bounded = Renderer(device=renderer.device)
    for texture in textures:
        for color_space in ("display", "linear"):
            draw(bounded, texture, color_space)
    kept = bounded.device_cache
    assert kept.textures.nbytes == 2 * 84 and len(kept.textures) == 2 and kept.textures.evictions == 2
    # A second cache of uploads (e.g. one per stored format) would double the bound.
    assert [name for name, value in vars(kept).items() if isinstance(value, ObjectCache)] == ["meshes", "textures"]
