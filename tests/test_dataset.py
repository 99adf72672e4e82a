"""Dataset rendering (`wgpu-shading batch`, wgpu_shading.dataset) in one process: the same
pixels as `wgpu-shading render`, outputs checked against geometry, resumability, failures."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import pickle
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.cli import main
from wgpu_shading.dataset import Outputs, mesh_jobs, read_manifest, render_dataset, sphere_views, turntable_views

ROOT = Path(__file__).resolve().parent.parent
TORUS = "builtin:torus?segments=24"


def pixels(path: Path) -> np.ndarray:
    return np.array(Image.open(path))


def write_lines(path: Path, rows: list[dict]) -> Path:
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    return path


def test_batch_pixels_equal_render_of_the_same_job(tmp_path, capsys):
    """A manifest row with render's flags gives the PNG `render` writes, pixel for pixel:
    overrides, the default view, and a view turned with --camera-azimuth/--camera-elevation
    (the bare mesh's depth range and viewer lights follow the camera in both)."""
    manifest = tmp_path / "jobs.csv"
    manifest.write_text(
        f"mesh,size,material,frequency,azimuth,elevation\n{TORUS},80x64,silver,gouraud,,\n{TORUS},80x64,,,,\n{TORUS},80x64,,,130,-55\n"
    )
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    assert main(["render", TORUS, "--size", "80x64", "--material", "silver", "--frequency", "gouraud", "-o", str(tmp_path / "a.png"), "-q"]) == 0
    assert main(["render", TORUS, "--size", "80x64", "-o", str(tmp_path / "b.png"), "-q"]) == 0
    assert main(["render", TORUS, "--size", "80x64", "--camera-azimuth", "130", "--camera-elevation", "-55", "-o", str(tmp_path / "c.png"), "-q"]) == 0
    folder = tmp_path / "out" / "torus"
    batch = [pixels(folder / f"view_00{i}.png") for i in range(3)]
    for image, reference in zip(batch, "abc"):
        assert np.array_equal(image, pixels(tmp_path / f"{reference}.png")), reference
    assert not np.array_equal(batch[0], batch[1]) and not np.array_equal(batch[1], batch[2])  # each row did something


def test_camera_keys_equal_render_of_a_scene_file_with_that_camera(tmp_path):
    """Camera keys of a row = a scene file whose [camera] says the same; depth too (float32)."""
    scene = (ROOT / "examples" / "gold_torus_phong.toml").read_text()
    scene = scene.replace("eye = [0.0, 0.0, 1.0]", "eye = [0.6, 0.5, 0.8]").replace("[512, 512]", "[72, 56]")
    (tmp_path / "moved.toml").write_text(scene)
    row = {"scene": str(ROOT / "examples" / "gold_torus_phong.toml"), "eye": [0.6, 0.5, 0.8], "size": "72x56"}
    manifest = write_lines(tmp_path / "jobs.jsonl", [row])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--depth", "npy", "-q"]) == 0
    assert main(["render", str(tmp_path / "moved.toml"), "-o", str(tmp_path / "ref.png"), "--depth", str(tmp_path / "ref.npy"), "-q"]) == 0
    folder = tmp_path / "out" / "gold_torus_phong"
    assert np.array_equal(pixels(folder / "view_000.png"), pixels(tmp_path / "ref.png"))
    assert np.array_equal(np.load(folder / "view_000_depth.npy"), np.load(tmp_path / "ref.npy"))


def test_png16_is_the_float_render_rounded_to_16_bits(tmp_path):
    manifest = write_lines(tmp_path / "jobs.jsonl", [{"mesh": TORUS, "size": 48}])
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--color", "png16", "-q"]) == 0
    assert main(["render", TORUS, "--size", "48", "-o", str(tmp_path / "ref.npy"), "-q"]) == 0
    import png

    width, height, rows, info = png.Reader(filename=str(tmp_path / "out" / "torus" / "view_000.png")).asDirect()
    assert info["bitdepth"] == 16 and info["alpha"]
    image = np.vstack([np.asarray(row, np.uint16) for row in rows]).reshape(height, width, 4)
    expected = np.round(np.clip(np.load(tmp_path / "ref.npy"), 0, 1) * 65535).astype(np.uint16)
    assert np.array_equal(image, expected)


SPHERES = """
[output]
size = [96, 72]
[camera]
eye = [0.5, 1.0, 4.0]
target = [0.5, 0.0, 0.0]
fov_y = 40.0
near = 1.0
far = 8.0
[[lights]]
type = "directional"
direction = [0.0, 0.0, -1.0]
[[objects]]
mesh = "builtin:sphere?slices=256&stacks=128"
translate = [0.5, 0.0, 0.0]
[[objects]]
mesh = "builtin:sphere?slices=16&stacks=8"
translate = [1.2, 0.7, 0.9]
scale = [0.15, 0.15, 0.15]
"""


@pytest.fixture(scope="module")
def sphere_dataset(tmp_path_factory, renderer):
    """A finely tessellated unit sphere off the origin, from 3 orbit views, every output."""
    tmp = tmp_path_factory.mktemp("sphere")
    scene = SPHERES
    (tmp / "spheres.toml").write_text(scene)
    views = [{"azimuth": 0}, {"azimuth": 100, "elevation": -30}, {"azimuth": 250, "elevation": 60, "distance": 3.0}]
    rows = [{"scene": "spheres.toml", **view} for view in views]
    jobs = read_manifest(write_lines(tmp / "jobs.jsonl", rows), Outputs(depth="npy", normals="world", ids=True))
    result = render_dataset(jobs, tmp / "out", progress=False, renderer=renderer)
    assert not result.failed and len(result.rendered) == 3
    jobs_eye = read_manifest(tmp / "jobs.jsonl", Outputs(color="none", normals="eye"))
    render_dataset(jobs_eye, tmp / "eye", progress=False, renderer=renderer)
    return tmp


def unproject(view: dict, depth: np.ndarray) -> np.ndarray:
    """World points of every pixel through the documented convention (OpenCV K and pose)."""
    height, width = depth.shape
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    z = np.where(np.isfinite(depth), depth, 0.0).astype(np.float64)
    camera = np.stack([(u - view["cx"]) / view["fx"] * z, (v - view["cy"]) / view["fy"] * z, z, np.ones_like(z)], -1)
    world_from_camera = np.linalg.inv(np.array(view["world_to_camera_opencv"]))
    return (camera @ world_from_camera.T)[..., :3]


def test_cameras_json_unprojects_depth_onto_the_surface(sphere_dataset):
    """Each covered pixel, unprojected with cameras.json's K and pose and its depth, lies on
    the unit sphere (0.01 % of the radius: the tessellation is finer than that); a half-pixel
    error in cx/cy or a flipped axis would miss by far more at the silhouette."""
    cameras = json.loads((sphere_dataset / "out" / "spheres" / "cameras.json").read_text())
    assert len(cameras["views"]) == 3
    for name, view in cameras["views"].items():
        depth = np.load(sphere_dataset / "out" / "spheres" / f"{name}_depth.npy")
        ids = pixels(sphere_dataset / "out" / "spheres" / f"{name}_ids.png")
        big = ids == 1
        assert big.sum() > 500
        radius = np.linalg.norm(unproject(view, depth)[big] - [0.5, 0.0, 0.0], axis=1)
        assert np.abs(radius - 1.0).max() < 2e-3, name
        opengl = np.array(view["camera_to_world_opengl"])
        assert np.allclose(opengl[:3, 3], view["eye"])
        assert np.allclose(np.diag([1, -1, -1, 1]) @ np.linalg.inv(opengl), view["world_to_camera_opencv"])


def test_orbit_keeps_the_target_and_moves_as_documented(sphere_dataset):
    views = json.loads((sphere_dataset / "out" / "spheres" / "cameras.json").read_text())["views"]
    target = np.array([0.5, 0.0, 0.0])
    base = np.array([0.5, 1.0, 4.0])
    assert np.allclose(views["view_000"]["eye"], base)  # azimuth 0 alone is the scene's camera
    offset = np.array(views["view_001"]["eye"]) - target
    distance = np.linalg.norm(base - target)
    assert math.isclose(np.linalg.norm(offset), distance)
    # elevation −30 turns the camera down from the scene's 14.04° above the horizon
    base_elevation = math.degrees(math.asin(1.0 / distance))
    assert math.isclose(math.degrees(math.asin(offset[1] / distance)), base_elevation - 30.0, abs_tol=1e-9)
    # azimuth 100°: from +z (the base camera's side) counter-clockwise seen from +y, towards +x
    assert math.isclose(math.degrees(math.atan2(offset[0], offset[2])), 100.0, abs_tol=1e-9)
    assert math.isclose(np.linalg.norm(np.array(views["view_002"]["eye"]) - target), 3.0)


def test_normals_and_ids_match_the_geometry(sphere_dataset):
    out = sphere_dataset / "out" / "spheres"
    cameras = json.loads((out / "cameras.json").read_text())["views"]
    for name, view in cameras.items():
        depth = np.load(out / f"{name}_depth.npy")
        ids = pixels(out / f"{name}_ids.png")
        world_normals = np.load(out / f"{name}_normals_world.npy")
        # ids cover exactly what the colour pass covered; the small sphere is object 2.
        assert np.array_equal(ids > 0, np.isfinite(depth))
        assert set(np.unique(ids)) == {0, 1, 2} or name == "view_002" and set(np.unique(ids)) <= {0, 1, 2}
        big = ids == 1
        expected = unproject(view, depth)[big] - [0.5, 0.0, 0.0]
        expected /= np.linalg.norm(expected, axis=1, keepdims=True)
        assert np.abs(world_normals[big] - expected).max() < 0.02
        assert not world_normals[ids == 0].any()
        # eye-space normals: the view rotation (OpenGL eye axes) applied to the world normals
        eye_normals = np.load(sphere_dataset / "eye" / "spheres" / f"{name}_normals_eye.npy")
        rotation = np.linalg.inv(np.array(view["camera_to_world_opengl"]))[:3, :3]
        assert np.abs(eye_normals[big] - world_normals[big] @ rotation.T).max() < 1e-5
        assert (eye_normals[big][:, 2] > -0.05).all()  # visible surface faces the camera (+z)


def test_rerun_skips_finished_jobs_and_redoes_changed_or_missing_ones(tmp_path, renderer):
    out = tmp_path / "out"
    jobs = mesh_jobs([TORUS, "builtin:sphere?slices=12&stacks=6"], turntable_views(3), Outputs(depth="png16"), {"size": 40})
    first = render_dataset(jobs, out, progress=False, renderer=renderer)
    assert sorted(first.rendered) == sorted(job.id for job in jobs) and not first.skipped
    stamp = {path: path.stat().st_mtime_ns for path in out.rglob("view_*")}
    (out / "torus" / "view_002_depth.png").unlink()  # a lost file
    (out / "sphere" / ".view_001.png.wgpu-shading-tmp-batch-123-ab12cd34-0.png").write_bytes(b"partial")  # a killed writer
    changed = mesh_jobs([TORUS, "builtin:sphere?slices=12&stacks=6"], turntable_views(3), Outputs(depth="png16"), {"size": 40})
    changed[0] = type(changed[0])(**{**changed[0].__dict__, "overrides": {"material": "ruby"}})  # an edited row
    second = render_dataset(changed, out, progress=False, renderer=renderer)
    assert sorted(second.rendered) == ["torus/view_000", "torus/view_002"]
    assert len(second.skipped) == 4 and not second.failed
    assert not list(out.rglob("*wgpu-shading-tmp*"))
    untouched = [path for path in stamp if "torus/view_000" not in str(path) and "torus/view_002" not in str(path)]
    assert all(path.stat().st_mtime_ns == stamp[path] for path in untouched)
    report = json.loads((out / "report.json").read_text())
    assert report["rendered"] == 2 and report["skipped"] == 4 and report["failed"] == {}
    # cameras.json, written from what the run holds (views skipped and rendered), lists what
    # each view's record file on disk says.
    for folder in ("torus", "sphere"):
        views = json.loads((out / folder / "cameras.json").read_text())["views"]
        assert sorted(views) == ["view_000", "view_001", "view_002"]
        for name, view in views.items():
            record = json.loads((out / folder / f"{name}.json").read_text())
            assert view == {"id": record["id"], "files": record["files"], **record["camera"]}


def test_a_mesh_folder_gone_by_the_end_gets_no_cameras_json(tmp_path, renderer, monkeypatch):
    """cameras.json is written from the run's records, not read back: a mesh folder that is
    not there at the end (removed meanwhile; here a writer that writes nothing) gets no
    cameras.json and the run ends normally, as before when the records were read back."""
    from wgpu_shading.dataset import chunk as chunk_module

    def names_only(out_dir, job, frame, extra, camera):
        return [f"{job.folder}/{name}" for name in job.outputs.file_names(job.name)]

    monkeypatch.setattr(chunk_module, "write_view", names_only)
    jobs = mesh_jobs([TORUS], turntable_views(2), Outputs(), {"size": 32})
    result = render_dataset(jobs, tmp_path / "out", progress=False, renderer=renderer)
    assert len(result.rendered) == 2 and not (tmp_path / "out" / "torus").exists()


def test_a_run_stopped_early_lists_the_views_it_finished(tmp_path, renderer, monkeypatch):
    """Ctrl-C while the second chunk is prepared: the first chunk's files and records are
    complete (close() waits for its writes) though its records never reached the run's loop,
    and cameras.json lists those views, as the next run would."""
    from wgpu_shading.dataset import chunk as chunk_module

    real_job_scene = chunk_module.job_scene

    def interrupted(base, job):
        if job.name == "view_002":
            raise KeyboardInterrupt
        return real_job_scene(base, job)

    monkeypatch.setattr(chunk_module, "job_scene", interrupted)
    jobs = mesh_jobs([TORUS], turntable_views(4), Outputs(), {"size": 32})
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        render_dataset(jobs, out, chunk_size=2, progress=False, renderer=renderer)
    views = json.loads((out / "torus" / "cameras.json").read_text())["views"]
    assert sorted(views) == ["view_000", "view_001"]
    assert all((out / file).is_file() for name in views for file in views[name]["files"])


def test_a_bad_mesh_fails_its_own_jobs_and_the_rest_finish(tmp_path, capsys):
    (tmp_path / "broken.obj").write_text("v 0 0 0\nv 1 nope 0\nf 1 2 3\n")
    rows = [
        {"mesh": TORUS, "size": 32},
        {"mesh": "broken.obj"},
        {"mesh": "missing.ply"},
        {"mesh": TORUS, "size": 32, "eye": [0, 0, 1e16]},  # out of range: found when the scene is built
    ]
    manifest = write_lines(tmp_path / "jobs.jsonl", rows)
    status = main(["batch", str(manifest), "-o", str(tmp_path / "out")])
    assert status == 1
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["rendered"] == 1
    assert set(report["failed"]) == {"broken/view_000", "missing/view_000", "torus/view_001"}
    assert "broken.obj" in report["failed"]["broken/view_000"]
    assert "missing.ply" in report["failed"]["missing/view_000"]
    assert "camera.eye" in report["failed"]["torus/view_001"]
    assert (tmp_path / "out" / "torus" / "view_000.png").is_file()
    captured = capsys.readouterr()
    assert "3 job(s) failed" in captured.err and "1 rendered" in captured.out


@pytest.mark.parametrize(
    "content, message",
    [
        ("mesh,colour\nbuiltin:torus,red\n", "line 2: unknown column 'colour'"),
        ("mesh,azimuth\nbuiltin:torus,left\n", "line 2: azimuth: expected a number, got 'left'"),
        ("name\nx\n", "line 2: expected exactly one of mesh, scene, source"),
        ("mesh,size\nbuiltin:torus,0\n", "size"),
        ("mesh,name,id\nbuiltin:torus,a,one\nbuiltin:torus,a,two\n", "line 3: folder 'torus' name 'a' is also job 'one'"),
    ],
)
def test_bad_manifest_rows_are_one_line_errors(tmp_path, capsys, content, message):
    manifest = tmp_path / "jobs.csv"
    manifest.write_text(content)
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out")]) == 2
    error = capsys.readouterr().err
    assert message in error and "jobs.csv" in error and "Traceback" not in error


def test_sphere_views_cover_the_sphere_evenly(renderer):
    """The framed camera of a bare mesh, turned by each view, looks from directions spread
    evenly over the sphere."""
    from wgpu_shading.dataset.views import base_scene, job_scene

    jobs = mesh_jobs([TORUS], sphere_views(200), Outputs(), {"size": 16})
    base = base_scene(jobs[0])
    target = np.array(base.camera.target)
    directions = np.array([np.subtract(job_scene(base, job).camera.eye, target) for job in jobs])
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    assert np.linalg.norm(directions.mean(axis=0)) < 0.02  # balanced
    # every direction's nearest neighbour lies at a similar angle (no clumps, no holes)
    cosines = directions @ directions.T
    np.fill_diagonal(cosines, -1)
    nearest = np.degrees(np.arccos(cosines.max(axis=1)))
    assert nearest.max() < 1.6 * nearest.min() + 2.0 and nearest.max() < 20
    assert [v["azimuth"] for v in turntable_views(4)] == [0.0, 90.0, 180.0, 270.0]


def test_workers_need_the_dask_extra(tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "distributed", None)  # as if it were not installed
    jobs = mesh_jobs([TORUS], turntable_views(1), Outputs(), {"size": 16})
    from wgpu_shading.errors import WgpuShadingError

    with pytest.raises(WgpuShadingError, match=r"\[dask\] extra into this environment: .* -m pip install 'distributed"):
        render_dataset(jobs, tmp_path / "out", workers=2, progress=False)
    assert os.path.isdir(tmp_path / "out")


def test_one_chunk_renderer_serves_several_threads(tmp_path, renderer):
    """A Dask worker started with --nthreads 4 runs tasks on threads that share its renderer:
    they take turns, and every file is what a lone run writes."""
    import threading

    from wgpu_shading.dataset.chunk import ChunkRenderer

    jobs = mesh_jobs([TORUS, "builtin:cube"], turntable_views(4), Outputs(ids=True), {"size": 40})
    shared = ChunkRenderer(renderer)
    records: list = []
    threads = [
        threading.Thread(target=lambda part=part: records.extend(shared.render(part, tmp_path / "threads")))
        for part in (jobs[:4], jobs[4:])
    ]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    shared.close()
    assert sorted(r["id"] for r in records if r["ok"]) == sorted(job.id for job in jobs)
    render_dataset(jobs, tmp_path / "alone", progress=False, renderer=renderer)
    for job in jobs:
        for file in job.files():
            assert np.array_equal(pixels(tmp_path / "threads" / file), pixels(tmp_path / "alone" / file)), file


TRIANGLE_OBJ = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n"
SQUARE_OBJ = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n"


def test_a_chunk_renderer_reads_a_mesh_again_in_the_next_run(tmp_path, renderer):
    """A Dask worker's ChunkRenderer serves run after run: a mesh file edited between two
    runs is drawn as it is now, not as the last run kept it (it was, until the runs were
    told apart). Within one run, the chunks of a mesh share its one load."""
    from wgpu_shading.dataset import chunk as chunk_module

    mesh = tmp_path / "m.obj"
    mesh.write_text(TRIANGLE_OBJ)
    jobs = mesh_jobs([str(mesh)], turntable_views(2), Outputs(), {"size": 24})
    shared = chunk_module.ChunkRenderer(renderer)
    try:
        assert all(r["ok"] for r in shared.render(jobs[:1], tmp_path / "first", run="a"))
        mesh.write_text(SQUARE_OBJ)
        assert all(r["ok"] for r in shared.render(jobs[1:], tmp_path / "same-run", run="a"))  # kept: still the triangle
        assert all(r["ok"] for r in shared.render(jobs[1:], tmp_path / "next-run", run="b"))
    finally:
        shared.close()
    triangle_dir, square_dir = tmp_path / "triangle", tmp_path / "square"
    mesh.write_text(TRIANGLE_OBJ)
    render_dataset(jobs, triangle_dir, progress=False, renderer=renderer)
    mesh.write_text(SQUARE_OBJ)
    render_dataset(jobs, square_dir, progress=False, renderer=renderer)
    file = jobs[1].files()[0]
    assert not np.array_equal(pixels(triangle_dir / file), pixels(square_dir / file))  # the edit shows
    assert np.array_equal(pixels(tmp_path / "same-run" / file), pixels(triangle_dir / file))
    assert np.array_equal(pixels(tmp_path / "next-run" / file), pixels(square_dir / file))


def test_prefetch_loads_the_next_chunk_once_and_its_errors_stay_with_its_jobs(tmp_path, renderer, monkeypatch):
    """The in-process run loads chunk i+1's mesh on the loader thread while chunk i renders;
    each mesh is still loaded once, a broken one fails only its own jobs, and the files are
    those of a run without prefetching."""
    import threading

    from wgpu_shading.dataset import chunk as chunk_module

    (tmp_path / "broken.obj").write_text("v 0 0 0\nv 1 nope 0\nf 1 2 3\n")
    loads: list[tuple[str, str]] = []
    real_load = chunk_module.base_scene

    def counted(job):
        loads.append((job.source, threading.current_thread().name))
        return real_load(job)

    monkeypatch.setattr(chunk_module, "base_scene", counted)
    sources = [TORUS, str(tmp_path / "broken.obj"), "builtin:cube"]
    jobs = mesh_jobs(sources, turntable_views(3), Outputs(depth="npy"), {"size": 24})
    result = render_dataset(jobs, tmp_path / "prefetched", progress=False, renderer=renderer, chunk_size=3)
    assert sorted(source for source, _ in loads) == sorted(sources)  # each mesh once
    on_loader = {source: thread.startswith("wgpu-shading-load") for source, thread in loads}
    assert on_loader == {TORUS: False, str(tmp_path / "broken.obj"): True, "builtin:cube": True}
    assert set(result.failed) == {job.id for job in jobs if "broken" in job.source}
    monkeypatch.setattr(chunk_module.ChunkRenderer, "prefetch", lambda self, jobs: None)
    render_dataset(jobs, tmp_path / "plain", progress=False, renderer=renderer, chunk_size=3)
    for job in jobs:
        if "broken" not in job.source:
            for file in job.files():
                assert (tmp_path / "prefetched" / file).read_bytes() == (tmp_path / "plain" / file).read_bytes(), file


def test_ids_number_the_parts_of_a_multi_part_mesh(tmp_path, renderer):
    """An OBJ with two materials (usemtl) is one object of two parts: ids 1 and 2, named in
    cameras.json, each where its part lies (left square left of the image centre)."""
    (tmp_path / "two.obj").write_text(
        "v -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 0 -1 0.2\nv 1 -1 0.2\nv 1 1 0.2\nv 0 1 0.2\n"
        "usemtl left\nf 1 2 3\nf 1 3 4\nusemtl right\nf 5 6 7\nf 5 7 8\n"
    )
    jobs = mesh_jobs([str(tmp_path / "two.obj")], turntable_views(1), Outputs(ids=True, depth="npy"), {"size": 48})
    assert not render_dataset(jobs, tmp_path / "out", progress=False, renderer=renderer).failed
    view = json.loads((tmp_path / "out" / "two" / "cameras.json").read_text())["views"]["view_000"]
    assert [(entry["id"], entry["object"], entry["part"], entry["part_name"]) for entry in view["ids"]] == [(1, 0, 0, "left"), (2, 0, 1, "right")]
    ids = pixels(tmp_path / "out" / "two" / "view_000_ids.png")
    assert np.array_equal(ids > 0, np.isfinite(np.load(tmp_path / "out" / "two" / "view_000_depth.npy")))
    columns = np.arange(48)[None, :].repeat(48, axis=0)
    assert columns[ids == 1].max() <= view["cx"] + 1 < columns[ids == 2].min() + 2
    assert (ids == 1).sum() > 200 and (ids == 2).sum() > 200


def test_orthographic_cameras_unproject_with_pixels_per_unit(tmp_path, renderer):
    """projection = orthographic in a row: cameras.json has no K but pixels_per_unit, and
    depth pixels unprojected with it land on the sphere."""
    (tmp_path / "spheres.toml").write_text(SPHERES)
    rows = [{"scene": "spheres.toml", "projection": "orthographic", "azimuth": 40, "elevation": 20}]
    jobs = read_manifest(write_lines(tmp_path / "jobs.jsonl", rows), Outputs(depth="npy", ids=True))
    assert not render_dataset(jobs, tmp_path / "out", progress=False, renderer=renderer).failed
    view = json.loads((tmp_path / "out" / "spheres" / "cameras.json").read_text())["views"]["view_000"]
    assert view["projection"] == "orthographic" and view["K"] is None
    depth = np.load(tmp_path / "out" / "spheres" / "view_000_depth.npy")
    big = pixels(tmp_path / "out" / "spheres" / "view_000_ids.png") == 1
    height, width = depth.shape
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    scale = view["pixels_per_unit"]
    z = np.where(big, depth, 0.0)
    camera = np.stack([(u - view["cx"]) / scale, (v - view["cy"]) / scale, z, np.ones_like(z)], -1)
    world = (camera @ np.linalg.inv(np.array(view["world_to_camera_opencv"])).T)[..., :3]
    radius = np.linalg.norm(world[big] - [0.5, 0.0, 0.0], axis=1)
    assert big.sum() > 300 and np.abs(radius - 1.0).max() < 2e-3


def test_the_next_chunk_renders_while_the_last_one_s_writes_end(tmp_path, renderer, monkeypatch):
    """ChunkRenderer.start returns once its frames are rendered and their writes queued (the
    in-process run starts the next chunk before it finishes this one); finish() waits for
    the writes, and only then are there records, each for complete files."""
    import threading

    from wgpu_shading.dataset import chunk as chunk_module

    release = threading.Event()
    real_write = chunk_module.write_view

    def held_write(*args):
        assert release.wait(60), "the writes were never released"
        return real_write(*args)

    monkeypatch.setattr(chunk_module, "write_view", held_write)
    jobs = mesh_jobs([TORUS], turntable_views(3), Outputs(depth="npy"), {"size": 32})
    chunks = chunk_module.ChunkRenderer(renderer)
    try:
        pending = chunks.start(jobs, tmp_path)  # returns although no write could run yet
        assert not any((tmp_path / file).exists() for job in jobs for file in job.files())
        release.set()
        records = pending.finish()
    finally:
        release.set()
        chunks.close()
    assert [record["id"] for record in records] == [job.id for job in jobs] and all(record["ok"] for record in records)
    assert all((tmp_path / file).is_file() for job in jobs for file in job.files())


def test_view_records_are_json_a_key_per_line_with_each_matrix_on_one(sphere_dataset):
    """name.json (and cameras.json) read back as written, a key per line and a list per line
    (dataset/writer.py json_text); the record names the job's digest and files."""
    for path in (sphere_dataset / "out" / "spheres" / "view_000.json", sphere_dataset / "out" / "spheres" / "cameras.json"):
        text = path.read_text()
        data = json.loads(text)
        assert json.loads(json.dumps(data)) == data
        lines = text.splitlines()
        assert lines[0] == "{" and lines[-1] == "}"
        matrices = [line for line in lines if '"world_to_camera_opencv": [[' in line]
        assert matrices and all(line.rstrip(",").endswith("]]") for line in matrices)
    record = json.loads((sphere_dataset / "out" / "spheres" / "view_000.json").read_text())
    assert record["files"][0] == "spheres/view_000.png" and len(record["digest"]) == 32
    assert len(record["camera"]["world_to_camera_opencv"]) == 4


def test_a_job_s_digest_is_its_fields_hash_computed_once(tmp_path):
    job = mesh_jobs([TORUS], turntable_views(2), Outputs(depth="npy"), {"size": 40})[1]
    same = type(job)(**{name: getattr(job, name) for name in job.__dataclass_fields__})
    assert job.digest() == same.digest() and job.digest() is job.digest()
    other = dataclasses.replace(job, outputs=Outputs())
    assert other.digest() != job.digest()
    assert pickle.loads(pickle.dumps(job)).digest() == job.digest()


@pytest.mark.parametrize("cores, threads", [(None, 1), (1, 1), (2, 1), (3, 1), (6, 3), (8, 4), (64, 4)])
def test_encoder_threads_are_half_the_cores_from_one_to_four(monkeypatch, cores, threads):
    """On 2 cores one encoder thread (a second slowed the frames it competes with); more
    where there are cores to keep up with faster frames."""
    from wgpu_shading.dataset import chunk

    monkeypatch.setattr(chunk.os, "cpu_count", lambda: cores)
    assert chunk.default_encoder_threads() == threads


def test_time_inside_chunks_counts_overlapping_spans_of_a_worker_once():
    """On Dask a worker renders its next chunk while the last one waits for its writes:
    the run's time inside chunks is the union of each worker's spans, summed over workers."""
    from wgpu_shading.dataset.run import busy_time

    assert busy_time([]) == 0.0
    assert busy_time([(0.0, 1.0), (2.0, 3.0)]) == pytest.approx(2.0)
    assert busy_time([(0.0, 2.0), (1.0, 3.0), (1.0, 3.0)]) == pytest.approx(3.0)  # a chunk's jobs share spans
    assert busy_time([(1.0, 2.0), (0.0, 5.0), (4.0, 6.0)]) == pytest.approx(6.0)


def test_time_inside_chunks_is_within_the_run(tmp_path, renderer):
    jobs = mesh_jobs(["builtin:torus?segments=16", "builtin:cube"], turntable_views(3), Outputs(depth="npy"), {"size": 24})
    result = render_dataset(jobs, tmp_path / "out", renderer=renderer, chunk_size=2, progress=False)
    assert not result.failed
    assert 0.0 < result.busy_seconds <= result.seconds


def _lsattr(folder: Path) -> str | None:
    """The folder's attribute letters as e2fsprogs' lsattr prints them; None where it cannot
    tell (no lsattr, or a file system without these attributes)."""
    import shutil
    import subprocess

    if shutil.which("lsattr") is None:
        return None
    result = subprocess.run(["lsattr", "-d", str(folder)], capture_output=True, text=True)
    return result.stdout.split()[0] if result.returncode == 0 and result.stdout.strip() else None


def test_a_run_marks_the_output_folder_it_makes_for_ext4_to_spread_its_mesh_folders(tmp_path, renderer):
    """dataset/output_folder.py: a folder the run makes, or finds empty, gets ext4's `T`
    attribute (read back with lsattr, not with our own ioctl); one holding files already is
    the user's and is left as it is."""
    jobs = mesh_jobs([TORUS], turntable_views(1), Outputs(), {"size": 16})
    made, empty, used = tmp_path / "made" / "out", tmp_path / "empty", tmp_path / "used"
    empty.mkdir()
    used.mkdir()
    (used / "notes.txt").write_text("mine")
    probe = tmp_path / "probe"
    probe.mkdir()
    attributes = _lsattr(probe)
    if attributes is None or not _can_mark(probe):
        pytest.skip(f"no ext4-style folder attributes at {tmp_path} (lsattr: {attributes})")
    for folder in (made, empty, used):
        result = render_dataset(jobs, folder, progress=False, renderer=renderer)
        assert len(result.rendered) == 1
    assert "T" in _lsattr(made) and "T" in _lsattr(empty)
    assert "T" not in _lsattr(used) and "T" not in _lsattr(made.parent)  # only the output folder itself
    assert "T" not in _lsattr(made / "torus")  # not inherited: the mesh folders are plain
    again = render_dataset(jobs, made, progress=False, renderer=renderer)  # a rerun into the marked folder
    assert again.skipped == [jobs[0].id] and "T" in _lsattr(made)


def _can_mark(folder: Path) -> bool:
    from wgpu_shading.dataset.output_folder import spread_subfolders

    return spread_subfolders(folder)


def test_a_file_system_that_refuses_the_mark_gets_a_plain_folder(tmp_path, renderer, monkeypatch):
    """tmpfs, xfs, NFS refuse the attribute's ioctl (ENOTTY, EOPNOTSUPP): the run goes on."""
    import errno

    from wgpu_shading.dataset import output_folder

    def refused(*args, **kwargs):
        raise OSError(errno.ENOTTY, "Inappropriate ioctl for device")

    monkeypatch.setattr(output_folder.fcntl, "ioctl", refused)
    out = tmp_path / "out"
    assert output_folder.spread_subfolders(tmp_path) is False and output_folder.has_spread_mark(tmp_path) is None
    result = render_dataset(mesh_jobs([TORUS], turntable_views(1), Outputs(), {"size": 16}), out, progress=False, renderer=renderer)
    assert len(result.rendered) == 1 and (out / "torus" / "view_000.png").is_file()


def test_an_output_path_that_is_a_file_is_a_usage_error(tmp_path, capsys):
    target = tmp_path / "out"
    target.write_text("not a folder")
    manifest = tmp_path / "jobs.csv"
    manifest.write_text(f"mesh,size\n{TORUS},16\n")
    assert main(["batch", str(manifest), "-o", str(target), "-q"]) == 2
    assert str(target) in capsys.readouterr().err and target.read_text() == "not a folder"
