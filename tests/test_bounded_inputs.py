"""Inputs bounded by their headers and sizes, not by luck: binary STL counts checked against
the file size before allocating, text meshes of NULs refused at once, scene files with too
many objects refused before anything loads, special files (FIFOs, devices, folders) refused
without being opened, and Pillow's decompression-bomb limit matching our documented 16384."""

from __future__ import annotations

import os
import struct
import warnings
import zlib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpu_shading import Mesh, load_mesh, load_scene
from wgpu_shading.assets.mesh_formats.checks import describe_load_error
from wgpu_shading.assets.textures import decoding_limits, load_texture
from wgpu_shading.cli.main import main
from wgpu_shading.errors import MeshError, SceneError
from wgpu_shading.scene.values import MAX_OBJECTS

RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def binary_stl(path: Path, corners: np.ndarray, header: bytes = b"binary", count: int | None = None) -> Path:
    records = np.zeros(len(corners), RECORD)
    records["corners"] = corners
    path.write_bytes(header.ljust(80, b" ") + struct.pack("<I", len(corners) if count is None else count) + records.tobytes())
    return path


def tetrahedron() -> np.ndarray:
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    return p[np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])]


# --------------------------------------------------------------------------- STL


def test_a_binary_stl_header_claiming_40m_triangles_is_refused_before_allocating(tmp_path):
    path = binary_stl(tmp_path / "liar.stl", tetrahedron(), count=40_000_000)
    with pytest.raises(MeshError, match=r"liar.stl': not a valid STL file: its header declares 40000000 triangles"):
        load_mesh(path)


def test_a_truncated_binary_stl_is_refused(tmp_path):
    path = binary_stl(tmp_path / "cut.stl", tetrahedron(), count=5)
    with pytest.raises(MeshError, match=r"declares 5 triangles, which need 334 bytes, but the file has 284 \(truncated\?\)"):
        load_mesh(path)


def test_a_binary_stl_whose_header_declares_0_triangles_is_read_to_its_size_with_a_warning(tmp_path):
    """A writer that streams its triangles may leave the count 0: the file's size says how
    many (VTK's reader, f3d's, reads such files); it said "contains no triangles"."""
    declared = load_mesh(binary_stl(tmp_path / "counted.stl", tetrahedron()))
    with pytest.warns(UserWarning, match=r"zero.stl': its header declares 0 triangles; read the 4 its 284 bytes hold"):
        streamed = load_mesh(binary_stl(tmp_path / "zero.stl", tetrahedron(), count=0))
    for name in ("positions", "indices", "normals", "origin"):
        np.testing.assert_array_equal(getattr(streamed, name), getattr(declared, name), err_msg=name)
    binary_stl(tmp_path / "ragged.stl", tetrahedron(), count=0)
    with open(tmp_path / "ragged.stl", "ab") as file:
        file.write(b"\0" * 7)  # not whole records: no count to trust
    with pytest.raises(MeshError, match="ragged.stl': not a valid STL file: its header declares 0 triangles, and the 207 bytes"):
        load_mesh(tmp_path / "ragged.stl")


def test_a_binary_stl_is_read_with_shared_vertices_like_trimesh_reads_it(tmp_path):
    import trimesh

    path = binary_stl(tmp_path / "tet.stl", tetrahedron(), header=b"solid exported by a CAD tool")  # binary despite "solid"
    mesh = load_mesh(path)
    reference = trimesh.load(str(path), process=False)  # every corner its own vertex
    ours = np.sort((mesh.positions.astype(np.float64) + mesh.origin)[mesh.indices].reshape(-1, 3), axis=0)
    theirs = np.sort(np.asarray(reference.vertices)[np.asarray(reference.faces)].reshape(-1, 3), axis=0)
    np.testing.assert_allclose(ours, theirs, atol=1e-7)
    assert mesh.triangle_count == 4 and mesh.vertex_count == 12  # every edge a crease: each face flat
    # Each triangle keeps its winding: the normals point out of the tetrahedron.
    centre = np.float64([0.25, 0.25, 0.25])
    corners = mesh.positions.astype(np.float64)[mesh.indices] + mesh.origin
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert (np.einsum("ij,ij->i", normals, corners.mean(axis=1) - centre) > 0).all()


def test_an_ascii_stl_is_still_read(tmp_path):
    facets = "".join(
        "facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {x} {y} {z}\n" for x, y, z in triangle) + "endloop\nendfacet\n"
        for triangle in tetrahedron().tolist()
    )
    path = tmp_path / "tet.stl"
    path.write_text(f"solid tet\n{facets}endsolid tet\n")
    assert load_mesh(path).triangle_count == 4


def test_an_ascii_stl_beyond_its_limit_is_refused_before_trimesh_reads_it(tmp_path, monkeypatch):
    """A plain ASCII STL is read a block of lines at a time whatever its size
    (stl_ascii.py); any other layout goes to trimesh, which holds the whole text several
    times over, and only up to MAX_ASCII_BYTES."""
    from wgpu_shading.assets.mesh_formats import stl

    monkeypatch.setattr(stl, "MAX_ASCII_BYTES", 100)
    facets = "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n" * 3
    (tmp_path / "plain.stl").write_text(f"solid plain\n{facets}endsolid plain\n")
    assert load_mesh(tmp_path / "plain.stl").triangle_count == 3
    (tmp_path / "big.stl").write_text(f"solid big\n{facets}endsolid big\nsolid second\n{facets}endsolid second\n")
    with pytest.raises(MeshError, match="big.stl': an ASCII STL of 0 MiB, not in the plain layout .* read in blocks; "
                                        "others are read whole, up to 0 MiB .*save it as binary STL"):
        load_mesh(tmp_path / "big.stl")


def test_an_stl_may_be_bigger_than_other_mesh_files(tmp_path):
    """ASCII STL spends ~270 bytes a triangle: a 10M-triangle file is ~2.6 GB, over the 2 GiB
    of every other format, and is read a block of lines at a time. So .stl files are allowed
    up to MAX_STL_FILE_BYTES (2^25 facets of 288 bytes); the size check lets a 3 GiB one
    through to the reader (which finds the NULs after its facets), and
    refuses a 10 GiB one, and a 3 GiB PLY, before reading a byte (sparse files: nothing is
    written to disk)."""
    from wgpu_shading.assets.mesh_formats.checks import MAX_MESH_FILE_BYTES, MAX_STL_FILE_BYTES

    assert MAX_STL_FILE_BYTES == 9 << 30 and MAX_MESH_FILE_BYTES == 2 << 30

    def sparse(name: str, size: int, start: bytes = b"") -> object:
        path = tmp_path / name
        with open(path, "wb") as file:
            file.write(start)
            file.truncate(size)
        return path

    facets = b"solid big\n" + b"facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n" * 30
    with pytest.raises(MeshError, match=rf"big.stl': not a text file \(a NUL byte at offset {len(facets)}\)"):
        load_mesh(sparse("big.stl", 3 << 30, facets))
    with pytest.raises(MeshError, match=r"huge.stl': 10.0 GiB; STL files up to 9 GiB are supported"):
        load_mesh(sparse("huge.stl", 10 << 30, facets))
    with pytest.raises(MeshError, match=r"big.ply': 3.0 GiB; mesh files up to 2 GiB are supported"):
        load_mesh(sparse("big.ply", 3 << 30, b"ply\n"))


# --------------------------------------------------------------------------- text meshes


@pytest.mark.parametrize("suffix", [".obj", ".off"])
def test_a_huge_text_mesh_of_nuls_is_refused_at_once(tmp_path, suffix):
    path = tmp_path / f"zeros{suffix}"
    with open(path, "wb") as file:
        file.truncate((2 << 30) - 1)  # 2 GiB of NULs (sparse: nothing is written to disk)
    with pytest.raises(MeshError, match=rf"zeros{suffix}': not a text file \(a NUL byte at offset 0\)"):
        load_mesh(path)


def test_an_obj_with_more_vertices_than_supported_is_refused_before_parsing(tmp_path, monkeypatch):
    from wgpu_shading.assets.mesh_formats import obj

    monkeypatch.setattr(obj, "MAX_VERTICES", 3)
    path = tmp_path / "many.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n")
    with pytest.raises(MeshError, match="4 vertices and 1 faces; at most 3 of each are supported"):
        load_mesh(path)



def test_an_obj_face_of_more_corners_than_supported_is_refused_from_its_bytes(tmp_path, monkeypatch, capsys):
    """One face line of millions of corners (a 48 MB line took 5.2 GB and 17 s to become
    triangles before its mesh was refused): counted on the line's bytes, before it is split
    into words, and refused naming the line. Long lines of few corners still read."""
    from wgpu_shading.assets.mesh_formats import obj_faces

    monkeypatch.setattr(obj_faces, "MAX_FACE_CORNERS", 8)  # lines over 16 bytes are counted
    vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    allowed = tmp_path / "padded.obj"
    allowed.write_text(vertices + "f 0001 0002 0003 0004 0001 0002 0003 0004\n")  # 8 corners, 41 bytes
    assert load_mesh(allowed).triangle_count == 6
    path = tmp_path / "long_face.obj"
    path.write_text(vertices + "f 1 2 3\nf 1 2 3 4 1 2 3 4 1\n")
    with pytest.raises(MeshError, match=r"long_face\.obj:6: a face of 9 corners; at most 8 are supported"):
        load_mesh(path)
    assert main(["render", str(path), "-o", str(tmp_path / "out.png"), "--size", "16"]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "a face of 9 corners" in error and "Traceback" not in error
    assert not (tmp_path / "out.png").exists()


def test_an_obj_whose_polygons_make_too_many_triangles_is_refused_as_they_are_read(tmp_path, monkeypatch):
    """Faces are counted against the limit as lines, and their fans as triangles as each
    run is read: 40 faces of a million corners (80 MB) make 40M triangles, refused at
    line 38 in 6 s and 1.1 GB, where the Mesh's own check came after every triangle was
    made (the limit patched small here: 60 pentagons, 180 triangles)."""
    from wgpu_shading.assets.mesh_formats import obj

    monkeypatch.setattr(obj, "MAX_TRIANGLES", 100)
    path = tmp_path / "pentagons.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\n" + "f 1 2 3 4 5\n" * 60)
    # triangle 100 (0-based) is the 34th face's: line 5 + 34
    with pytest.raises(MeshError, match=r"pentagons\.obj': its faces cut into triangles make more than 100 \(the limit is passed at line 39\)"):
        load_mesh(path)
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\n" + "f 1 2 3 4 5\n" * 33)  # 99 triangles
    assert load_mesh(path).triangle_count == 99

def test_a_mesh_file_over_the_triangle_limit_is_refused_before_its_normals(tmp_path, monkeypatch):
    """Whatever the format (an OFF here: 40 faces of a thousand corners, 39,920 triangles),
    the Mesh's limits are checked on the file's pieces before they are welded and creased,
    which for a file of few huge polygons was most of the time and memory."""
    from wgpu_shading.assets import mesh_pieces

    path = tmp_path / "polygons.off"
    ring = np.linspace(0, 2 * np.pi, 1000, endpoint=False)
    path.write_text("OFF\n1000 40 0\n" + "".join(f"{np.cos(a):.6f} {np.sin(a):.6f} 0\n" for a in ring.tolist())
                    + ("1000 " + " ".join(map(str, range(1000))) + "\n") * 40)
    monkeypatch.setattr(mesh_pieces, "MAX_TRIANGLES", 39_919)
    monkeypatch.setattr(mesh_pieces, "crease_normals", lambda *args: pytest.fail("creased past the limit"))
    with pytest.raises(MeshError, match=r"polygons\.off: 1000 vertices, 39920 triangles and 0 line segments; at most"):
        load_mesh(path)

@pytest.mark.parametrize("limit, at_least", [(344, 354), (170, 174)])
def test_a_polygon_of_repeated_corners_is_refused_before_its_creases_are_split(tmp_path, monkeypatch, limit, at_least):
    """The hostile OBJ's other shape: faces of repeated corners, whose fans hold triangles
    without area, every corner a vertex of its own once split at creases (354 here). Refused
    as soon as the crease normals can count more than the limit, not after the split: from
    the fans (all 354), or before the edge analysis from the 58 triangles without area
    (3 × 58 = 174). A 48 MB file of 24 such faces took 5.3 GB and 34 s; ~1 GB and 18 s now
    (docs/reliability.md)."""
    from wgpu_shading.assets import mesh_pieces
    from wgpu_shading.scene.geometry import crease_normals as creases

    path = tmp_path / "repeated.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n" + "f" + " 1 2 3 4" * 30 + "\n")
    whole = load_mesh(path)  # 118 triangles, half without area: every corner its own vertex
    assert whole.vertex_count == 3 * whole.triangle_count == 354
    monkeypatch.setattr(mesh_pieces, "MAX_VERTICES", limit)
    monkeypatch.setattr(creases, "split_vertices", lambda *args: pytest.fail("split after the limit was seen"))
    with pytest.raises(MeshError, match=rf"repeated\.obj: at least {at_least} vertices once split at creases .*; at most {limit} are supported"):
        load_mesh(path)


def test_flat_faces_and_crease_splits_count_against_the_vertex_limit(tmp_path, monkeypatch):
    """Vertices made by the normals count too: an OBJ whose faces are all flat (`s off`:
    every corner a vertex) is refused before the split, a glTF primitive without normals
    (drawn flat) before its corners are copied, and Mesh.from_arrays with a crease angle
    refuses a split past the limit (the cube: 8 given vertices, 24 once each face keeps
    its own normal)."""
    from wgpu_shading.assets import mesh_pieces
    from wgpu_shading.scene import Mesh
    from wgpu_shading.scene.geometry import mesh as mesh_module

    path = tmp_path / "flat.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ns off\nf 1 2 3\nf 1 3 4\nf 1 2 4\nf 2 3 4\n")
    assert load_mesh(path).vertex_count == 12
    monkeypatch.setattr(mesh_pieces, "MAX_VERTICES", 11)
    with pytest.raises(MeshError, match=r"flat\.obj: at least 12 vertices once split at creases .*; at most 11 are supported"):
        load_mesh(path)
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 3], [0, 1, 3], [1, 2, 3]], np.uint32)
    piece = mesh_pieces.MeshPiece(positions, faces, all_flat=True, parts=[(0, 4, None, "flat")])
    with pytest.raises(MeshError, match=r"flat\.glb: 12 vertices once every flat face's corners are split; at most 11 are supported"):
        mesh_pieces.assemble([piece], "flat.glb", 60.0)
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    assert Mesh.from_arrays(corners, faces, crease_angle=30.0).vertex_count == 24
    monkeypatch.setattr(mesh_module, "MAX_VERTICES", 23)
    with pytest.raises(MeshError, match=r"cube: (at least )?24 vertices once split at creases.*; at most 23 are supported"):
        Mesh.from_arrays(corners, faces, crease_angle=30.0, name="cube")

# --------------------------------------------------------------------------- scene files


def test_a_scene_file_with_too_many_objects_is_refused_before_loading(tmp_path, capsys):
    path = tmp_path / "crowd.toml"
    path.write_text('[[objects]]\nmesh = "no-such-file.obj"\n' * (MAX_OBJECTS + 1))  # none is loaded
    with pytest.raises(SceneError, match=rf"\[\[objects\]\]: {MAX_OBJECTS + 1} objects; at most {MAX_OBJECTS} are supported"):
        load_scene(path)


def test_a_scene_file_with_too_many_lights_is_refused(tmp_path):
    path = tmp_path / "lights.toml"
    path.write_text('[[objects]]\nmesh = "builtin:cube"\n' + '[[lights]]\ntype = "directional"\n' * 257)
    with pytest.raises(SceneError, match=r"\[\[lights\]\]: 257 lights; at most 256"):
        load_scene(path)


# --------------------------------------------------------------------------- special files


@pytest.fixture
def fifo(tmp_path):
    def make(name: str) -> Path:
        path = tmp_path / name
        os.mkfifo(path)
        return path

    return make


def test_fifos_are_refused_without_being_opened(tmp_path, fifo):
    """Each would block open() forever; the test would hang, not fail, if one were opened."""
    with pytest.raises(MeshError, match=r"pipe.obj' is a FIFO \(named pipe\), not a regular file"):
        load_mesh(fifo("pipe.obj"))
    with pytest.raises(SceneError, match=r"pipe.png' is a FIFO"):
        load_texture(fifo("pipe.png"))
    with pytest.raises(SceneError, match=r"scene file .*pipe.toml' is a FIFO"):
        load_scene(fifo("pipe.toml"))
    fifo("fifo.png")
    scene = tmp_path / "textured.toml"
    scene.write_text('[[objects]]\nmesh = "builtin:cube"\nmaterial = { texture = "fifo.png" }\n')
    with pytest.raises(SceneError, match=r"fifo.png' is a FIFO"):
        load_scene(scene)


def test_an_mtl_texture_that_is_a_fifo_is_refused(tmp_path, fifo):
    fifo("wood.png")
    (tmp_path / "m.mtl").write_text("newmtl wood\nKd 1 1 1\nmap_Kd wood.png\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl wood\nf 1/1 2/2 3/3\n")
    with pytest.raises((SceneError, MeshError), match=r"wood.png' is a FIFO"):
        load_mesh(tmp_path / "m.obj")


def test_a_manifest_that_is_a_fifo_is_one_line(tmp_path, fifo, capsys):
    assert main(["batch", str(fifo("jobs.csv")), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is a FIFO" in err


@pytest.mark.parametrize("path, kind", [("/dev/zero", "a character device"), (".", "a folder")])
def test_devices_and_folders_are_refused_as_meshes(path, kind, tmp_path):
    target = tmp_path / "dev.stl"
    target.symlink_to(Path(path).resolve())
    with pytest.raises(MeshError, match=f"is {kind}, not a regular file"):
        load_mesh(target)


# --------------------------------------------------------------------------- textures


def header_only_png(path: Path, width: int, height: int, bit_depth: int = 8, colour: int = 2) -> Path:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, bit_depth, colour, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IEND", b""))
    return path


@pytest.mark.parametrize("height", [6000, 10923, 16384])
def test_pillow_neither_warns_nor_refuses_within_the_documented_16384(tmp_path, height):
    path = header_only_png(tmp_path / "big.png", 16384, height)
    before = Image.MAX_IMAGE_PIXELS
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a DecompressionBombWarning would fail here
        with decoding_limits(), Image.open(path) as image:
            assert image.size == (16384, height)
        with pytest.raises(SceneError) as caught:
            load_texture(path)  # no pixel data: a read error, never "too large" or "DOS attack"
    assert "cannot read image" in str(caught.value) and "DOS" not in str(caught.value)
    assert Image.MAX_IMAGE_PIXELS == before  # restored


def test_a_texture_beyond_16384_is_refused_from_its_header(tmp_path):
    path = header_only_png(tmp_path / "wide.png", 16385, 16)
    with pytest.raises(SceneError, match="16385×16 pixels; at most 16384 per side"):
        load_texture(path)


def test_a_16_bit_rgb_reference_is_refused(tmp_path):
    import png

    from wgpu_shading.testing.golden import GoldenError, check_image

    path = tmp_path / "ref.png"
    pixels = np.full((4, 4 * 3), 40000, np.uint16)
    with open(path, "wb") as file:
        png.Writer(4, 4, greyscale=False, bitdepth=16).write(file, pixels)
    with pytest.raises(GoldenError, match="references are 8-bit PNGs; this one has uint16 pixels"):
        check_image(np.zeros((4, 4, 4), np.uint8), path)


# --------------------------------------------------------------------------- messages


def test_trimesh_internals_are_not_leaked_into_messages():

    escape = ValueError("'../secret.bin' escapes resolver root '/data/m' — pass `FilePathResolver(path, allow_anywhere=True)` to allow it")
    text = describe_load_error(escape, Path("m.gltf"))
    assert "FilePathResolver" not in text and "'../secret.bin'" in text and "outside its folder" in text
    text = describe_load_error(AssertionError(), Path("m.ply"))
    assert "AssertionError" not in text and "not a valid PLY file" in text


def test_a_missing_optional_module_is_named_not_called_an_invalid_file():
    # trimesh reaches for optional modules for some contents (it read a PLY's edges as a
    # path, which needs scipy, before ply_edges.py): the ImportError was reported as "not a
    # valid PLY file (neither its binary form nor UTF-8 text)". It names the module.
    text = describe_load_error(ImportError("No module named 'scipy'"), Path("edges.ply"))
    assert "'scipy'" in text and "not installed" in text and "not a valid" not in text


def test_pillow_warnings_about_a_texture_are_one_line_naming_it(tmp_path, capsys):
    import io

    buffer = io.BytesIO()
    Image.new("RGB", (8, 8), (200, 10, 10)).save(buffer, "JPEG")
    jpeg = buffer.getvalue()
    # An EXIF block whose one tag points past its end: Pillow warns "Tag data larger than
    # file" and "Corrupt EXIF data" (each twice) and reads the pixels.
    exif = b"Exif\x00\x00MM\x00\x2a\x00\x00\x00\x08\x00\x05\x01\x0f\x00\x02\x00\x00\x10\x00\x00\x00\x00\x00"
    (tmp_path / "bad_exif.jpg").write_bytes(jpeg[:2] + b"\xff\xe1" + struct.pack(">H", len(exif) + 2) + exif + jpeg[2:])
    scene = tmp_path / "s.toml"
    scene.write_text('[output]\nsize = [16, 16]\n[[objects]]\nmesh = "builtin:cube"\nmaterial = { texture = "bad_exif.jpg" }\n')
    assert main(["render", str(scene), "-o", str(tmp_path / "out.png"), "-q"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("wgpu-shading: warning: texture ") and "bad_exif.jpg" in err[0] and "read anyway" in err[0]


def test_texture_coordinates_beyond_float32_are_refused_not_drawn_as_infinite(tmp_path):
    """A uv of 1e39 is finite as float64 and infinite as the float32 the GPU reads: the OBJ
    reader (which keeps `vt` numbers as float32) names its line, and a caller's arrays are
    refused by the Mesh. (Before, the Mesh kept an infinite uv.)"""
    path = tmp_path / "big_uv.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1e39 0\nvt 0 1\nf 1/1 2/2 3/3\n")
    with pytest.raises(MeshError, match=r"big_uv.obj:5: 'vt' line has a number beyond float32's range: '1e39 0'"):
        load_mesh(path)
    with pytest.raises(MeshError, match="uvs beyond float32's range"):
        Mesh.from_arrays(np.eye(3), np.array([[0, 1, 2]]), uvs=np.array([[0, 0], [1e39, 0], [0, 1]]))
