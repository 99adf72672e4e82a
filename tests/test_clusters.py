"""Clusters of triangles turned away from the camera are left out of a frame
(render/gpu/clusters.py), and not one byte of any output changes.

The reference is the same scene with every triangle drawn (WGPU_SHADING_CLUSTERS=0), on a
renderer of its own: colour, depth, normals and ids must be bit-identical over many random
views of closed meshes (a sphere, a torus, a subdivided cube, real closed meshes from
../shared/models), perspective and orthographic, with a shadowing light, and the frames
must really leave triangles out (else the comparison proves nothing). Frames that cannot
leave any out (open or inside-out meshes, a camera inside or a near plane cutting the mesh,
blended or double-sided materials, --edges) draw every triangle. The bound each cluster's
cone and sphere give is checked against the triangles' own normals in float64. Builds run
on the renderer's worker thread (render/gpu/cluster_builds.py): frames before, during and
after one are the same, and one whose upload or renderer goes meanwhile is dropped unused.
"""

from __future__ import annotations

import gc
import logging
import threading
import weakref
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import trimesh
from pyglm import glm

from wgpu_shading import Camera, Renderer, Scene, SceneObject, load_mesh
from wgpu_shading.render.gpu import cluster_builds, clusters, mesh_uploads
from wgpu_shading.render.gpu.vertex_order import cache_order
from wgpu_shading.render.passes.color import prepare_draws
from wgpu_shading.scene import DirectionalLight, Material, Mesh, PositionalLight, Shading
from wgpu_shading.scene.geometry.builtins import sphere_for_triangles

SHARED_MODELS = next(
    (p / "shared" / "models" for p in Path(__file__).resolve().parents if (p / "shared" / "models").is_dir()), Path("missing")
)
GOLD = Material(diffuse=(0.75, 0.6, 0.2, 1.0), specular=(0.6, 0.6, 0.5, 1.0), shininess=51.0)
SIZE = (96, 80)


@pytest.fixture
def soon(monkeypatch):
    """Clusters from the second frame of any closed mesh (instead of the 16th frame of a mesh
    of 16K triangles), built inside that frame (no worker thread: the frame that asks draws
    with them), so small meshes and few frames test them; and harder than in use:
    clusters of 32 triangles, every one turned away left out (no gap bridged), so that many
    more lie next to a silhouette."""
    monkeypatch.setattr(mesh_uploads, "CLUSTERS_AFTER_FRAMES", 1)
    monkeypatch.setattr(cluster_builds, "BUILD_WORKERS", 0)
    monkeypatch.setattr(mesh_uploads, "CLUSTER_MIN_TRIANGLES", 0)
    monkeypatch.setattr(clusters, "CLUSTER_TRIANGLES", 32)
    monkeypatch.setattr(clusters, "BRIDGED_TRIANGLES", 0)
    monkeypatch.delenv("WGPU_SHADING_CLUSTERS", raising=False)


def subdivided_cube() -> Mesh:
    """A cube of 3,072 triangles (shared corners: closed with exact welding), smooth normals."""
    box = trimesh.creation.box(extents=(1.4, 1.4, 1.4)).subdivide().subdivide().subdivide().subdivide()
    return Mesh(positions=np.asarray(box.vertices, np.float32), normals=np.asarray(box.vertex_normals, np.float32),
                indices=np.asarray(box.faces, np.uint32), name="subdivided cube")


def closed_meshes() -> list[tuple[str, Mesh]]:
    meshes = [
        ("sphere", load_mesh("builtin:sphere?slices=96&stacks=48")),
        ("torus", load_mesh("builtin:torus?segments=64")),
        ("cube", subdivided_cube()),
    ]
    for name in ("fandisk.obj", "spot.obj"):  # closed, with creases (split normals) and a texture
        if (SHARED_MODELS / name).exists():
            meshes.append((name, load_mesh(str(SHARED_MODELS / name))))
    return meshes


def random_view(mesh: Mesh, rng: np.random.Generator, orthographic: bool = False) -> Camera:
    """A camera outside the mesh's bounding box, with the whole mesh beyond the near plane."""
    lower, upper = mesh.bounds()
    centre, radius = (lower + upper) / 2.0, float(np.linalg.norm(upper - lower)) / 2.0
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    eye = centre + direction * radius * rng.uniform(1.3, 4.0)
    target = centre + rng.uniform(-0.3, 0.3, 3) * radius
    up = rng.normal(size=3)
    common = dict(eye=tuple(eye), target=tuple(target), up=tuple(up), near=0.02 * radius, far=20.0 * radius)
    if orthographic:
        return Camera(projection="orthographic", ortho_height=rng.uniform(1.5, 3.0) * radius, **common)
    return Camera(fov_y=rng.uniform(25.0, 70.0), **common)


def scene_of(mesh: Mesh, camera: Camera, **changes) -> Scene:
    lights = (PositionalLight(position=(2.0, 3.0, 4.0)), DirectionalLight(direction=(-0.3, -1.0, -0.4), shadows=True))
    scene = Scene(objects=(SceneObject(mesh, material=GOLD),), lights=lights, camera=camera, size=SIZE)
    return replace(scene, **changes)


def outputs(renderer: Renderer, scene: Scene) -> dict[str, np.ndarray]:
    frame = renderer.render_frame(scene, depth=True, normals="eye", ids=True)
    return {"color": frame.color, "depth": frame.depth, "normals": frame.normals, "ids": frame.ids}


def drawn_share(renderer: Renderer, scene: Scene) -> float:
    """Triangles the colour pass draws this frame, as a share of the mesh's."""
    draws = prepare_draws(renderer.device_cache, scene, "rgba8", glm.dmat4(scene.camera.eye_from_world()))
    triangles = [draw for draw in draws if not draw.entry.descriptor.quads]  # (not --edges' segments)
    drawn = sum(count for draw in triangles for _, count in (draw.ranges or [(draw.first_triangle, draw.triangle_count)]))
    return drawn / scene.objects[0].mesh.triangle_count


def every_triangle(renderer: Renderer, scene: Scene, monkeypatch) -> dict[str, np.ndarray]:
    monkeypatch.setenv("WGPU_SHADING_CLUSTERS", "0")
    try:
        return outputs(renderer, scene)
    finally:
        monkeypatch.delenv("WGPU_SHADING_CLUSTERS")


def assert_same(expected: dict, actual: dict, what: str) -> None:
    for name, array in expected.items():
        assert np.array_equal(array, actual[name], equal_nan=True), f"{what}: {name} differs in {np.sum(array != actual[name])} values"


@pytest.mark.parametrize("name, mesh", closed_meshes(), ids=lambda v: v if isinstance(v, str) else "")
def test_closed_meshes_leave_out_triangles_turned_away_with_every_output_bit_identical(renderer, soon, monkeypatch, name, mesh):
    rng = np.random.default_rng(29)
    culling, reference = Renderer(renderer.device), Renderer(renderer.device)
    cameras = [random_view(mesh, rng, orthographic=k % 4 == 3) for k in range(12)]
    outputs(culling, scene_of(mesh, cameras[0]))  # the upload; the next frame builds the clusters
    shares = []
    for number, camera in enumerate(cameras):
        scene = scene_of(mesh, camera)
        assert_same(every_triangle(reference, scene, monkeypatch), outputs(culling, scene), f"{name}, view {number}")
        shares.append(drawn_share(culling, scene))
    assert culling.device_cache.meshes.get(mesh).order.clusters is not None
    # (coarse meshes keep most clusters: a 32-triangle cluster's ring spans a wide cone)
    assert max(shares) < 1.0 and min(shares) < 0.9, f"{name}: frames drew {shares} of the triangles: too little left out"


def test_the_clusters_bound_is_conservative_against_every_triangles_own_normal(soon):
    """A cluster is left out only when its triangles and every triangle sharing a corner with
    them face away from the eye: checked in float64 from the triangles themselves."""
    mesh = load_mesh("builtin:torus?segments=64")
    scratch, order = cache_order(mesh.indices, mesh.vertex_count, mesh.parts, frozenset(), mesh.positions)  # as uploaded
    triangles = order.gather[scratch.array.reshape(-1, 3)]  # the mesh's own vertex numbers
    scratch.close()
    table = order.clusters
    places, at = np.unique(mesh.positions, axis=0, return_inverse=True)  # the seam's twin vertices are one place
    at = at.reshape(-1)
    corners = mesh.positions.astype(np.float64)[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    rng = np.random.default_rng(7)
    left_out = 0
    for _ in range(40):
        orthographic = rng.random() < 0.25
        eye = rng.normal(size=3) * (1.0 if orthographic else rng.uniform(0.8, 3.0))
        away = table.facing_away(eye, orthographic)
        towards = eye if orthographic else eye - corners  # per corner (perspective), or one direction
        facing = np.einsum("tj,tcj->tc", normals, np.broadcast_to(towards, corners.shape)) >= 0.0
        seen_corner = np.zeros(len(places), bool)
        seen_corner[at[triangles[facing.any(axis=1)]].reshape(-1)] = True  # places of a triangle not wholly turned away
        for cluster in np.flatnonzero(away):
            rows = at[triangles[table.first[cluster] : table.first[cluster] + table.count[cluster]]]
            assert not seen_corner[rows].any(), "a cluster left out touches a triangle turned towards the eye"
        left_out += int(away.sum())
    assert left_out > 0


def test_a_benchmark_sphere_leaves_out_its_back_half_after_the_frames_that_pay_for_it(renderer, monkeypatch):
    """Without the test's shortcut: the smoke run's 20K sphere gets its clusters at the
    CLUSTERS_AFTER_FRAMES-th frame (benchmarks/scenes.settle) and then draws about half."""
    from benchmarks.scenes import TINY_SPHERE_TRIANGLES, settle, sphere_scene

    monkeypatch.delenv("WGPU_SHADING_CLUSTERS", raising=False)
    scene = sphere_scene(64, TINY_SPHERE_TRIANGLES)
    ours = Renderer(renderer.device)
    ours.render(scene)
    assert drawn_share(ours, scene) == 1.0
    settle(ours, scene)
    assert drawn_share(ours, scene) < 0.85
    assert len(ours.device_cache.meshes) == 1  # the upload without clusters was replaced, not kept beside
    rng = np.random.default_rng(5)  # the clusters as used (128 triangles, short gaps drawn): the same pixels
    for camera in [scene.camera] + [random_view(scene.objects[0].mesh, rng) for _ in range(4)]:
        view = replace(scene, camera=camera)
        assert_same(every_triangle(ours, view, monkeypatch), outputs(ours, view), "benchmark sphere")


def open_sphere() -> Mesh:
    sphere = load_mesh("builtin:sphere?slices=48&stacks=24")
    return replace(sphere, indices=sphere.indices[: sphere.triangle_count - 40], parts=())


def inside_out_sphere() -> Mesh:
    sphere = load_mesh("builtin:sphere?slices=48&stacks=24")
    return replace(sphere, indices=np.ascontiguousarray(sphere.indices[:, ::-1]), normals=-sphere.normals, parts=())


def sphere_and_a_flipped_small_one() -> Mesh:
    """Closed, and +1 by total volume, but one piece inside out: its faces turned away show."""
    sphere = load_mesh("builtin:sphere?slices=48&stacks=24")
    positions = np.concatenate([sphere.positions, sphere.positions * 0.3 + np.float32(1.5)])
    indices = np.concatenate([sphere.indices, sphere.indices[:, ::-1] + np.uint32(sphere.vertex_count)])
    return Mesh(positions=positions, normals=np.concatenate([sphere.normals, -sphere.normals]), indices=indices)


@pytest.mark.parametrize("mesh", [open_sphere(), inside_out_sphere(), sphere_and_a_flipped_small_one()], ids=["open", "inside out", "flipped piece"])
def test_meshes_that_are_not_closed_solids_get_no_clusters(renderer, soon, monkeypatch, mesh):
    ours, reference = Renderer(renderer.device), Renderer(renderer.device)
    scene = scene_of(mesh, Camera(eye=(0.5, 1.0, 4.0), target=(0.5, 0.5, 0.0)))
    for _ in range(3):
        outputs(ours, scene)
    assert ours.device_cache.meshes.get(mesh).order.clusters is None
    assert drawn_share(ours, scene) == 1.0
    assert_same(every_triangle(reference, scene, monkeypatch), outputs(ours, scene), "not a closed solid")


SPHERE = load_mesh("builtin:sphere?slices=96&stacks=48")
OUTSIDE = Camera(eye=(0.4, 0.9, 3.0), near=0.1)
FRAMES_THAT_DRAW_EVERYTHING = {
    "camera inside": scene_of(SPHERE, Camera(eye=(0.1, 0.2, 0.3), target=(0.0, 0.0, -1.0), near=0.05)),
    "near plane cuts the mesh": scene_of(SPHERE, Camera(eye=(0.0, 0.0, 1.5), near=0.8)),
    "blended": replace(scene_of(SPHERE, OUTSIDE), objects=(SceneObject(SPHERE, material=replace(GOLD, diffuse=(0.8, 0.6, 0.2, 0.5), alpha_mode="blend")),)),
    "double sided": replace(scene_of(SPHERE, OUTSIDE), objects=(SceneObject(SPHERE, material=replace(GOLD, double_sided=True)),)),
    "two sided lighting": scene_of(SPHERE, OUTSIDE, shading=Shading(two_sided=True)),
    "edges": scene_of(SPHERE, OUTSIDE, shading=Shading(edges=True)),
}


@pytest.mark.parametrize("case", list(FRAMES_THAT_DRAW_EVERYTHING))
def test_frames_where_a_face_turned_away_could_show_draw_every_triangle(renderer, soon, monkeypatch, case):
    scene = FRAMES_THAT_DRAW_EVERYTHING[case]
    ours, reference = Renderer(renderer.device), Renderer(renderer.device)
    outputs(ours, scene_of(SPHERE, OUTSIDE))
    outputs(ours, scene_of(SPHERE, OUTSIDE))  # the clusters are built
    assert drawn_share(ours, scene_of(SPHERE, OUTSIDE)) < 0.8
    assert drawn_share(ours, scene) == 1.0
    assert_same(every_triangle(reference, scene, monkeypatch), outputs(ours, scene), case)


def test_threads_drawing_the_same_closed_mesh_get_the_same_images(renderer, soon, monkeypatch):
    """One renderer, four threads, views of one sphere while its clusters are built on the
    renderer's worker and its upload is replaced by the one with them: every image is the
    one a single thread draws."""
    rng = np.random.default_rng(3)
    scenes = [scene_of(SPHERE, random_view(SPHERE, rng)) for _ in range(8)]
    alone = Renderer(renderer.device)
    expected = [alone.render(scene) for scene in scenes + scenes]  # (the second round with clusters)
    monkeypatch.setattr(cluster_builds, "BUILD_WORKERS", 1)
    shared, results, failures = Renderer(renderer.device), {}, []

    def draw(worker: int) -> None:
        try:
            for k in range(worker, len(scenes), 4):
                results[k] = shared.render(scenes[k])
        except Exception as error:  # pragma: no cover - reported below
            failures.append(error)

    threads = [threading.Thread(target=draw, args=(w,)) for w in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not failures
    for k, image in results.items():
        assert np.array_equal(image, expected[k]), f"view {k}"


# ---------------------------------------------------------------- builds on the worker thread

JUST_ABOVE = sphere_for_triangles(clusters.CLUSTER_MIN_TRIANGLES + 4000)  # clustered as in use (128-triangle clusters)


@pytest.fixture
def gate(monkeypatch):
    """Cluster builds on the renderer's worker (as in use), started at a mesh's third frame,
    each held before its vertex-cache step until the test opens the gate: frames drawn
    meanwhile are frames during a build. Yields (a build is held, open the gate)."""
    monkeypatch.setattr(mesh_uploads, "CLUSTERS_AFTER_FRAMES", 2)
    monkeypatch.setattr(cluster_builds, "BUILD_WORKERS", 1)
    monkeypatch.delenv("WGPU_SHADING_CLUSTERS", raising=False)
    held, opened = threading.Event(), threading.Event()
    cache_order_itself = cluster_builds.cache_order

    def held_cache_order(*args):
        held.set()
        assert opened.wait(60), "the test never opened the gate"
        return cache_order_itself(*args)

    monkeypatch.setattr(cluster_builds, "cache_order", held_cache_order)
    yield held, opened
    opened.set()


def test_frames_before_during_and_after_a_build_on_the_worker_are_those_drawing_every_triangle(renderer, gate, monkeypatch):
    held, opened = gate
    rng = np.random.default_rng(11)
    views = [scene_of(JUST_ABOVE, random_view(JUST_ABOVE, rng, orthographic=k == 7)) for k in range(9)]
    ours, reference = Renderer(renderer.device), Renderer(renderer.device)
    expected = [every_triangle(reference, scene, monkeypatch) for scene in views]
    for k in range(3):  # the upload, then the frames that ask: the third starts the build
        assert_same(expected[k], outputs(ours, views[k]), f"before the build, view {k}")
    assert held.wait(30), "no build started at the third frame"
    for k in range(3, 6):
        assert_same(expected[k], outputs(ours, views[k]), f"during the build, view {k}")
        assert drawn_share(ours, views[k]) == 1.0  # the upload without clusters, drawn meanwhile
    build = ours.device_cache.meshes.get(JUST_ABOVE).cluster_build
    assert build is not None and not build.done()
    opened.set()
    ours.device_cache.cluster_builds.wait(60)
    for k in range(6, 9):  # the first of these swaps to the clustered upload
        assert_same(expected[k], outputs(ours, views[k]), f"after the build, view {k}")
    assert ours.device_cache.meshes.get(JUST_ABOVE).order.clusters is not None
    assert drawn_share(ours, views[8]) < 0.85


def test_a_build_whose_upload_is_replaced_meanwhile_is_never_applied(renderer, gate, monkeypatch):
    """The same mesh drawn with a blended part while its build runs: that upload (in
    triangle order) replaces the one the build was for, whose result is then dropped."""
    held, opened = gate
    ours, reference = Renderer(renderer.device), Renderer(renderer.device)
    opaque = scene_of(JUST_ABOVE, OUTSIDE)
    for _ in range(3):
        outputs(ours, opaque)
    assert held.wait(30)
    future = ours.device_cache.meshes.get(JUST_ABOVE).cluster_build.future
    blended = replace(opaque, objects=(SceneObject(JUST_ABOVE, material=replace(GOLD, diffuse=(0.8, 0.6, 0.2, 0.5), alpha_mode="blend")),))
    assert_same(every_triangle(reference, blended, monkeypatch), outputs(ours, blended), "blended, during the build")
    opened.set()
    assert future.result(timeout=60) is None  # it saw its upload gone and stopped
    assert_same(every_triangle(reference, opaque, monkeypatch), outputs(ours, opaque), "opaque again")
    upload = ours.device_cache.meshes.get(JUST_ABOVE)
    assert upload.order.in_order == {0} and upload.order.clusters is None


def test_a_renderer_dropped_during_a_build_is_collected_and_its_worker_ends(renderer, gate):
    held, opened = gate
    before = set(threading.enumerate())
    ours = Renderer(renderer.device)
    mesh = sphere_for_triangles(clusters.CLUSTER_MIN_TRIANGLES + 4000)
    for _ in range(3):
        ours.render(scene_of(mesh, OUTSIDE))
    assert held.wait(30)
    future = ours.device_cache.meshes.get(mesh).cluster_build.future
    (worker,) = [thread for thread in set(threading.enumerate()) - before if thread.name.startswith("wgpu-shading-clusters")]
    cache = weakref.ref(ours.device_cache)
    del ours, mesh
    gc.collect()  # (returns at once: nothing waits for the worker)
    assert cache() is None, "the renderer's caches outlive it"
    opened.set()
    assert future.result(timeout=60) is None  # its upload and mesh gone: nothing made, nothing kept
    worker.join(timeout=60)
    assert not worker.is_alive(), "the worker thread outlives its renderer"


def test_a_build_that_fails_is_logged_and_the_mesh_drawn_without_clusters(renderer, gate, monkeypatch, caplog):
    held, opened = gate
    opened.set()

    def failing(*args):
        raise MemoryError("no room for the clusters")

    monkeypatch.setattr(cluster_builds, "cache_order", failing)
    ours, reference = Renderer(renderer.device), Renderer(renderer.device)
    scene = scene_of(JUST_ABOVE, OUTSIDE)
    with caplog.at_level(logging.ERROR):
        for _ in range(3):
            outputs(ours, scene)
        ours.device_cache.cluster_builds.wait(60)
        assert_same(every_triangle(reference, scene, monkeypatch), outputs(ours, scene), "after a failed build")
    assert any(record.exc_info and "no room for the clusters" in str(record.exc_info[1]) for record in caplog.records)
    upload = ours.device_cache.meshes.get(JUST_ABOVE)
    assert upload.cluster_build is None and upload.cluster_asks == -1 and drawn_share(ours, scene) == 1.0


def test_a_batch_on_two_devices_shares_one_worker_and_draws_every_frame_as_one_device_does(renderer, gate, monkeypatch):
    """render_many's helper device builds on the renderer's worker (one big build at a time):
    frames of a turntable before, during and after the builds are the reference's."""
    from wgpu_shading.scene.view.turntable import turntable

    held, opened = gate
    opened.set()
    mesh = sphere_for_triangles(clusters.CLUSTER_MIN_TRIANGLES + 4000)
    views = list(turntable(scene_of(mesh, OUTSIDE), 12))
    reference = Renderer(renderer.device)
    expected = [every_triangle(reference, scene, monkeypatch) for scene in views]
    frames = list(renderer.render_many(views + views, depth=True, normals="eye", ids=True, parallel=2))
    renderer.device_cache.cluster_builds.wait(60)
    frames += list(renderer.render_many(views, depth=True, normals="eye", ids=True, parallel=2))
    for number, frame in enumerate(frames):
        actual = {"color": frame.color, "depth": frame.depth, "normals": frame.normals, "ids": frame.ids}
        assert_same(expected[number % len(views)], actual, f"turntable frame {number}")
    devices = renderer.parallel_renderers(2)
    assert devices[1].device_cache.cluster_builds is renderer.device_cache.cluster_builds
    assert all(d.device_cache.meshes.get(mesh).order.clusters is not None for d in devices)  # both swapped


EXIT_DURING_A_BUILD = """
import time
from wgpu_shading.render.gpu import cluster_builds
from wgpu_shading.scene.geometry.builtins import sphere_for_triangles


class SlowFirstStep:  # (a sibling device's orders, looked up in the build's first step)
    def take(self, *args, **kwargs):
        print("in the first step", flush=True)
        time.sleep(1.0)


def next_step(*args):
    time.sleep(60)
    print("the build went on after exit began", flush=True)


cluster_builds.cache_order = next_step
mesh = sphere_for_triangles(20000)
builds = cluster_builds.ClusterBuilds(workers=1)
build = builds.start(mesh, frozenset(), SlowFirstStep())
time.sleep(0.3)
"""


def test_the_interpreter_exits_during_a_build_after_its_current_step(tmp_path):
    """Exit joins the worker thread: it stops after the step it is in, not a whole build later."""
    import subprocess
    import sys
    import time

    start = time.perf_counter()
    result = subprocess.run([sys.executable, "-c", EXIT_DURING_A_BUILD], capture_output=True, text=True, timeout=50)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "in the first step"
    assert time.perf_counter() - start < 30  # (the next step alone would take 60 s)
