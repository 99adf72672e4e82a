"""The cache folder (assets/disk_cache.py): a mesh file's Mesh (mesh_cache.py) and a mesh's
vertex-cache order (render/gpu/order_cache.py) read back in a later load are the ones the
file and meshoptimizer give, never a stale one; damaged entries, a full or unwritable
folder and concurrent writers only mean the work is done again."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading.assets import meshes
from wgpu_shading.assets.disk_cache import CACHE_VARIABLE, SIZE_VARIABLE, SUFFIX, TEMPORARY_TAG, trim
from wgpu_shading.assets.meshes import load_mesh
from wgpu_shading.render.gpu import vertex_order
from wgpu_shading.render.gpu.vertex_order import cache_order
from wgpu_shading.scene.geometry.builtins import builtin

ARRAYS = ("positions", "normals", "indices", "uvs", "colors", "tangents", "line_indices", "extra_uvs")


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv(CACHE_VARIABLE, str(folder))
    monkeypatch.delenv(SIZE_VARIABLE, raising=False)
    return folder


def _entries(folder: Path) -> list[Path]:
    return sorted(folder.glob(f"*{SUFFIX}")) if folder.is_dir() else []


def _parsed(path: Path, monkeypatch, **options):
    """The file's Mesh with the cache off: what every hit must equal."""
    with monkeypatch.context() as local:
        local.setenv(CACHE_VARIABLE, "off")
        return load_mesh(path, **options)


def _assert_same(found, expected) -> None:
    for key in ARRAYS:
        a, b = getattr(found, key), getattr(expected, key)
        assert (a is None) == (b is None), key
        if a is not None:
            assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b), key
    assert found.parts == expected.parts and found.origin == expected.origin and found.name == expected.name


def _torus_obj(path: Path, segments: int = 64, header: str = "") -> Path:
    """A torus as OBJ text without normals (the loader gives crease normals), > 16 KiB."""
    mesh = builtin(f"builtin:torus?segments={segments}")
    lines = [header] if header else []
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in mesh.positions]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.indices]
    path.write_text("\n".join(lines) + "\n")
    return path


def _binary_stl(path: Path, segments: int = 48) -> Path:
    mesh = builtin(f"builtin:torus?segments={segments}")
    corners = mesh.positions[mesh.indices].astype("<f4")
    records = np.zeros(len(corners), [("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    records["corners"] = corners
    path.write_bytes(b"\0" * 80 + np.uint32(len(records)).tobytes() + records.tobytes())
    return path


def _coloured_ply(path: Path, segments: int = 48) -> Path:
    mesh = builtin(f"builtin:torus?segments={segments}")
    vertices = np.zeros(len(mesh.positions), [("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("red", "u1"), ("green", "u1"), ("blue", "u1")])
    for k, axis in enumerate("xyz"):
        vertices[axis] = mesh.positions[:, k]
    vertices["red"] = np.arange(len(vertices)) % 251
    faces = np.zeros(len(mesh.indices), [("n", "u1"), ("corners", "<i4", (3,))])
    faces["n"], faces["corners"] = 3, mesh.indices
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\nproperty float x\nproperty float y\n"
              f"property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face {len(faces)}\n"
              "property list uchar int vertex_indices\nend_header\n")
    path.write_bytes(header.encode() + vertices.tobytes() + faces.tobytes())
    return path


@pytest.mark.parametrize("make", [_torus_obj, _binary_stl, _coloured_ply])
def test_a_hit_gives_the_parsed_mesh_without_parsing(tmp_path, cache, monkeypatch, make):
    path = make(tmp_path / f"mesh.{make.__name__.split('_')[-1]}")
    expected = _parsed(path, monkeypatch)
    first = load_mesh(path)
    assert len(_entries(cache)) == 1
    _assert_same(first, expected)

    def no_reader(reader):
        raise AssertionError("parsed again")

    monkeypatch.setattr(meshes, "mesh_reader", no_reader)
    hit = load_mesh(path)
    _assert_same(hit, expected)
    assert not hit.positions.flags.writeable and hit.positions.flags.owndata  # kept by the Mesh without a copy


def test_a_changed_file_another_angle_or_another_name_is_parsed_again(tmp_path, cache, monkeypatch):
    path = _torus_obj(tmp_path / "torus.obj", 48)
    load_mesh(path)
    _torus_obj(path, 40)  # new bytes, same name
    _assert_same(load_mesh(path), _parsed(path, monkeypatch))
    _assert_same(load_mesh(path, crease_angle=10.0), _parsed(path, monkeypatch, crease_angle=10.0))
    assert len(_entries(cache)) == 3
    stl = _binary_stl(tmp_path / "a.stl")
    renamed = tmp_path / "b.stl"
    renamed.write_bytes(stl.read_bytes())
    load_mesh(stl)
    assert load_mesh(renamed).parts[0].name == "b.stl"  # the part is named after the file read


def test_notes_are_said_again_on_a_hit(tmp_path, cache):
    path = _torus_obj(tmp_path / "named.obj", header="usemtl shiny")
    for _ in range(2):
        with pytest.warns(UserWarning, match="names no material library"):
            load_mesh(path)
    assert len(_entries(cache)) == 1


def test_files_that_depend_on_other_files_are_never_kept(tmp_path, cache):
    (tmp_path / "looks.mtl").write_text("newmtl shiny\nKd 1 0 0\n")
    load_mesh(_torus_obj(tmp_path / "with_library.obj", header="mtllib looks.mtl\nusemtl shiny"))
    small = tmp_path / "small.obj"  # under MIN_FILE_BYTES: parsed faster than looked up
    small.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    load_mesh(small)
    assert _entries(cache) == []


def test_a_damaged_entry_is_removed_and_the_file_parsed(tmp_path, cache, monkeypatch):
    path = _torus_obj(tmp_path / "torus.obj")
    expected = _parsed(path, monkeypatch)
    load_mesh(path)
    (entry,) = _entries(cache)
    data = bytearray(entry.read_bytes())
    for damage in (lambda d: d.__setitem__(len(d) - 5, d[len(d) - 5] ^ 0xFF),  # a flipped byte: the CRC
                   lambda d: d.__delitem__(slice(len(d) - 100, None)),  # truncated
                   lambda d: d.__setitem__(slice(0, 10), b"x" * 10)):  # not an entry
        damaged = bytearray(data)
        damage(damaged)
        entry.write_bytes(damaged)
        _assert_same(load_mesh(path), expected)  # parsed, and written again whole
        assert entry.read_bytes() == data
    entry.unlink()
    os.mkfifo(entry)  # never waited on
    _assert_same(load_mesh(path), expected)
    assert entry.is_file() and entry.read_bytes() == data


def test_an_entry_of_the_right_form_but_no_mesh_is_removed_and_the_file_parsed(tmp_path, cache, monkeypatch):
    from wgpu_shading.assets.disk_cache import DiskCache

    path = _torus_obj(tmp_path / "torus.obj")
    expected = _parsed(path, monkeypatch)
    load_mesh(path)
    (entry,) = _entries(cache)
    keeper = DiskCache(cache, 1 << 30)
    mesh = expected
    for arrays, fields in (
        ({"positions": mesh.positions, "normals": mesh.normals, "indices": mesh.indices + 10**6}, None),  # indices past the vertices
        ({"positions": mesh.positions}, None),  # no normals, no indices
        ({"positions": mesh.positions, "normals": mesh.normals, "indices": mesh.indices, "weights": mesh.normals}, None),
        ({"positions": mesh.positions, "normals": mesh.normals, "indices": mesh.indices}, {"origin": [0, 0], "parts": [], "notes": []}),
        ({"positions": mesh.positions, "normals": mesh.normals, "indices": mesh.indices}, {"parts": "x"}),
    ):
        good = {"origin": list(mesh.origin), "parts": [[p.first, p.count, p.name, p.primitive] for p in mesh.parts], "notes": []}
        keeper.write(entry.name[: -len(".entry")], arrays, good if fields is None else fields)
        _assert_same(load_mesh(path), expected)  # parsed again, and its entry written again whole
        assert len(_entries(cache)) == 1


def test_the_cache_keeps_to_its_size_least_recently_used_first(tmp_path, cache, monkeypatch):
    paths = [_torus_obj(tmp_path / f"t{k}.obj", 48, header=f"# copy {k}") for k in range(3)]  # three entries of one size
    load_mesh(paths[0])
    size = _entries(cache)[0].stat().st_size
    monkeypatch.setenv(SIZE_VARIABLE, str(2.5 * size / 2**20))  # room for two entries of about this size
    load_mesh(paths[1])
    time.sleep(0.01)
    load_mesh(paths[0])  # a hit: used now, so t1 is the least recently used
    time.sleep(0.01)
    load_mesh(paths[2])
    assert len(_entries(cache)) == 2 and sum(e.stat().st_size for e in _entries(cache)) <= 2.5 * size

    def no_reader(reader):
        raise AssertionError("parsed again")

    with monkeypatch.context() as local:
        local.setattr(meshes, "mesh_reader", no_reader)
        load_mesh(paths[0]), load_mesh(paths[2])  # kept
    monkeypatch.setenv(SIZE_VARIABLE, str(0.4 * size / 2**20))  # an entry over half of it is not written
    load_mesh(_torus_obj(tmp_path / "t9.obj", 60))
    assert len(_entries(cache)) == 2


def test_off_and_unwritable_folders_only_mean_parsing(tmp_path, monkeypatch):
    path = _torus_obj(tmp_path / "torus.obj")
    expected = _parsed(path, monkeypatch)
    blocked = tmp_path / "a file"
    blocked.write_text("not a folder")
    for setting in ("off", str(blocked), str(blocked / "below")):
        monkeypatch.setenv(CACHE_VARIABLE, setting)
        _assert_same(load_mesh(path), expected)
    assert blocked.read_text() == "not a folder"
    monkeypatch.setenv(CACHE_VARIABLE, str(tmp_path / "zero"))
    monkeypatch.setenv(SIZE_VARIABLE, "0")  # no room: off
    load_mesh(path)
    assert not (tmp_path / "zero").exists()
    for bad in ("lots", "-5", "nan"):  # not a number of MiB: the default, and said
        monkeypatch.setenv(SIZE_VARIABLE, bad)
        with pytest.warns(UserWarning, match=f"WGPU_SHADING_MESH_CACHE_MB='{bad}' is not a number of MiB"):
            _assert_same(load_mesh(path), expected)
    assert len(_entries(tmp_path / "zero")) == 1


def test_a_file_changed_while_it_is_read_is_not_kept(tmp_path, cache, monkeypatch):
    path = _torus_obj(tmp_path / "torus.obj")
    shipped = meshes.mesh_reader

    def touching(reader):
        read = shipped(reader)

        def wrapped(file, size, *rest):
            found = read(file, size, *rest)
            os.utime(file, ns=(1, 1))  # another writer, meanwhile
            return found
        return wrapped

    monkeypatch.setattr(meshes, "mesh_reader", touching)
    load_mesh(path)
    assert _entries(cache) == []


def test_a_file_longer_than_its_load_allowed_is_not_hashed_past_it(tmp_path, cache, monkeypatch):
    """A file someone keeps writing: the hash stops at the size the load was allowed (here a
    size the file had outgrown), the file is parsed and nothing kept."""
    from wgpu_shading.assets import mesh_cache

    path = _torus_obj(tmp_path / "torus.obj")
    shipped = mesh_cache.file_identity
    monkeypatch.setattr(mesh_cache, "file_identity", lambda file: (shipped(file)[0] - 100, *shipped(file)[1:]))
    _assert_same(load_mesh(path), _parsed(path, monkeypatch))
    assert _entries(cache) == []


def test_threads_loading_one_file_agree(tmp_path, cache, monkeypatch):
    path = _torus_obj(tmp_path / "torus.obj", 72)
    expected = _parsed(path, monkeypatch)
    found, errors = [], []

    def load() -> None:
        try:
            found.append(load_mesh(path))
        except Exception as error:  # pragma: no cover - reported below
            errors.append(error)

    for _ in range(2):  # the first round writes (every thread may), the second reads
        threads = [threading.Thread(target=load) for _ in range(4)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    assert not errors and len(found) == 8
    for mesh in found:
        _assert_same(mesh, expected)
    assert len(_entries(cache)) == 1 and not [p for p in cache.iterdir() if p.name.startswith(".")]


def test_temporaries_left_by_a_killed_process_are_removed(tmp_path):
    folder = tmp_path / "cache"
    folder.mkdir()
    old = folder / f".x{SUFFIX}.wgpu-shading-tmp-{TEMPORARY_TAG}123-abc-0{SUFFIX}"
    new = folder / f".y{SUFFIX}.wgpu-shading-tmp-{TEMPORARY_TAG}123-abc-1{SUFFIX}"
    for path in (old, new):
        path.write_bytes(b"partial")
    os.utime(old, (time.time() - 7200, time.time() - 7200))
    trim(folder, 1 << 20)
    assert not old.exists() and new.exists()  # (a newer one may still be being written)


def test_a_kept_vertex_order_is_the_one_meshoptimizer_makes(cache, monkeypatch):
    mesh = builtin("builtin:torus?segments=96")
    with monkeypatch.context() as local:
        local.setenv(CACHE_VARIABLE, "off")
        scratch, expected = cache_order(mesh.indices, mesh.vertex_count, mesh.parts)
        ordered = scratch.array.copy()
    first_scratch, first = cache_order(mesh.indices, mesh.vertex_count, mesh.parts)
    assert np.array_equal(first_scratch.array, ordered) and np.array_equal(first.gather, expected.gather)
    assert len(_entries(cache)) == 1

    def no_meshoptimizer(*args):
        raise AssertionError("ordered again")

    monkeypatch.setattr(vertex_order, "optimize_for_cache", no_meshoptimizer)
    hit_scratch, hit = cache_order(mesh.indices, mesh.vertex_count, mesh.parts)
    assert np.array_equal(hit_scratch.array, ordered) and np.array_equal(hit.gather, expected.gather)
    assert hit.in_order == expected.in_order and hit.clusters is None
    # other parts or another blended part: another order, never this one
    with pytest.raises(AssertionError, match="ordered again"):
        cache_order(mesh.indices, mesh.vertex_count, mesh.parts, frozenset({1}))
    # a damaged entry is dropped, and the order made and kept again
    (entry,) = _entries(cache)
    kept = entry.read_bytes()
    entry.write_bytes(kept[:-3] + bytes([kept[-3] ^ 0xFF]) + kept[-2:])
    monkeypatch.undo()  # (meshoptimizer back, and the fixture's folder with it)
    monkeypatch.setenv(CACHE_VARIABLE, str(cache))
    again_scratch, again = cache_order(mesh.indices, mesh.vertex_count, mesh.parts)
    assert np.array_equal(again_scratch.array, ordered) and np.array_equal(again.gather, expected.gather)
    assert entry.read_bytes() == kept


def test_the_cli_reads_a_mesh_once_and_draws_the_same_image(tmp_path):
    path = _torus_obj(tmp_path / "torus.obj", 96)  # (18K triangles: big enough for its order to be kept)
    folder = tmp_path / "cache"
    env = {**os.environ, CACHE_VARIABLE: str(folder)}
    images = []
    for run in range(2):
        out = tmp_path / f"{run}.png"
        subprocess.run([str(Path(sys.executable).parent / "wgpu-shading"), "render", str(path), "-o", str(out), "--size", "64"],
                       env=env, check=True, capture_output=True, timeout=120)
        images.append(out.read_bytes())
        assert len(_entries(folder)) == 2  # the mesh and its vertex-cache order
    assert images[0] == images[1]
