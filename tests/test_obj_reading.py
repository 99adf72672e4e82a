"""OBJ and MTL files as their writers meant them (assets/mesh_formats/obj.py, mtl.py): traits of real
files found outside the repository (issue 12: each named in its test, reproduced by a small
generated file), encodings, line endings and material libraries."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from test_file_parts import head_on, pixel
from wgpu_shading import MeshError, SceneObject, load_mesh


SQUARE_FACES = "f 1 2 3\nf 1 3 4\n"


def _square_obj(tmp_path, mtl_text: str):
    (tmp_path / "m.mtl").write_text(mtl_text)
    (tmp_path / "m.obj").write_text(
        "mtllib m.mtl\nusemtl m\nv -1 -0.5 0\nv 1 -0.5 0\nv 1 0.5 0\nv -1 0.5 0\n" + SQUARE_FACES
    )
    return tmp_path / "m.obj"


def test_meshlab_tr_1_without_d_is_opaque_not_invisible(tmp_path, renderer):
    """MeshLab (VCG) writes `Tr 1.000000` into every MTL it exports, meaning opaque (trimesh's
    models/fuze.obj.mtl). 1 − Tr made such files render as an empty black image with exit 0;
    f3d shows them opaque. A white Kd under a white head-on light is 255 and covered."""
    obj = _square_obj(tmp_path, "# Converted by Meshlab Group\nnewmtl m\nKa 0.2 0.2 0.2\nKd 1 1 1\nKs 1 1 1\nTr 1.000000\nillum 2\nNs 0\n")
    with pytest.warns(UserWarning, match=r"m.mtl:2: material 'm': 'Tr 1' without 'd' would make it invisible; read as opaque"):
        mesh = load_mesh(obj)
    material = mesh.parts[0].material
    assert material.diffuse[3] == 1.0 and material.alpha_mode == "opaque"
    image = renderer.render(head_on([SceneObject(mesh)], "phong"))
    assert tuple(pixel(image, 0.0, 0.0)) == (255, 255, 255, 255)


def test_explicit_d_0_is_kept_but_warned_about(tmp_path):
    obj = _square_obj(tmp_path, "newmtl m\nKd 1 1 1\nd 0\n")
    with pytest.warns(UserWarning, match=r"material 'm': 'd 0' makes it fully transparent; its faces draw nothing"):
        mesh = load_mesh(obj)
    assert mesh.parts[0].material.diffuse[3] == 0.0


def test_concave_obj_polygon_leaves_its_notch_open(tmp_path, renderer):
    """n-gons are exported as they are (Blender by default, LightWave: assimp's
    concave_polygon.obj, a ring cut open by a slit, rendered as a filled disk). An L whose
    first corner is not in its kernel: a fan from it covers the notch. Ear clipping leaves
    the notch empty and both arms covered, as f3d shows it; the convex quad keeps its fan."""
    (tmp_path / "l.obj").write_text(
        "v 0.8 0 0\nv 0 0 0\nv 0 0.8 0\nv -0.8 0.8 0\nv -0.8 -0.8 0\nv 0.8 -0.8 0\n"
        "v 1.2 -0.8 0\nv 1.8 -0.8 0\nv 1.8 0.8 0\nv 1.2 0.8 0\n"
        "f 1 2 3 4 5 6\nf 7 8 9 10\n"
    )
    mesh = load_mesh(tmp_path / "l.obj")
    assert sum(p.count for p in mesh.parts) == 4 + 2
    image = renderer.render(head_on([SceneObject(mesh)], "flat", size=(128, 64), background=(0.0, 0.0, 1.0, 1.0)))
    arm_a, arm_b = pixel(image, -0.4, 0.4), pixel(image, 0.4, -0.4)
    assert arm_a[:3].sum() > 100 and tuple(arm_a) == tuple(arm_b)  # facing the viewer, same material
    for x, y in ((0.2, 0.2), (0.1, 0.6), (0.6, 0.1), (0.6, 0.6)):  # the notch: a fan covered the first three
        assert tuple(pixel(image, x, y)) == (0, 0, 255, 255), (x, y)
    assert tuple(pixel(image, 1.5, 0.0)) == tuple(arm_a)  # the quad, lit the same way


def test_byte_order_marks_and_unknown_usemtl(tmp_path, recwarn):
    """Windows tools start files with a UTF-8 byte order mark: on an OBJ's first `v` line it
    hid the vertex (every index shifted: an error here, a wrong mesh elsewhere); on an MTL's
    first `newmtl` it hid the material, and the part was silently drawn in the default
    material. assimp's box_UTF16BE.obj (UTF-16) read as "0 vertices". A `usemtl` that no
    library defines is now a warning naming it."""
    (tmp_path / "m.mtl").write_bytes(b"\xef\xbb\xbfnewmtl red\nKd 1 0 0\n")
    body = "mtllib m.mtl\nusemtl red\nf 1 2 3\nusemtl blue\nf 1 3 2\n"
    (tmp_path / "utf8.obj").write_bytes(b"\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\n" + body.encode())
    (tmp_path / "utf16.obj").write_bytes(("v 0 0 0\nv 1 0 0\nv 0 1 0\n" + body).encode("utf-16"))
    for name in ("utf8.obj", "utf16.obj"):
        with pytest.warns(UserWarning, match=r"'usemtl blue' names no material of m.mtl; its faces drawn without it"):
            mesh = load_mesh(tmp_path / name)
        assert len(mesh.positions) >= 3 and [p.name for p in mesh.parts] == ["red", "blue"]
        assert mesh.parts[0].material.diffuse[:3] == (1.0, 0.0, 0.0) and mesh.parts[1].material is None


def test_missing_vt_or_vn_drops_the_attribute_not_the_faces(tmp_path, renderer):
    """OpenSubdiv's catmark_torus_creases0.obj refers to vn that it never declares, trimesh's
    cubevt.obj to vt: f3d draws both meshes, here they stopped with an error. Now the
    attribute goes with a warning naming the line; the faces render (computed normals)."""
    (tmp_path / "q.obj").write_text("v -1 -0.5 0\nv 1 -0.5 0\nv 1 0.5 0\nv -1 0.5 0\nvt 0 0\nf 1/1/1 2/1/2 3/1/3 4/1/4\n")
    with pytest.warns(UserWarning, match=r"q.obj:6: face 'f 1/1/1 2/1/2 3/1/3 4/1/4' refers to a normal \(vn\) that does not exist "
                                         r"\(1 vt, 0 vn declared before it\); its normals are ignored"):
        mesh = load_mesh(tmp_path / "q.obj")
    assert mesh.uvs is not None and sum(p.count for p in mesh.parts) == 2
    np.testing.assert_allclose(mesh.normals, np.tile([0.0, 0.0, 1.0], (len(mesh.normals), 1)))
    image = renderer.render(head_on([SceneObject(mesh)], "flat"))
    assert image[16, 32, 3] == 255 and image[16, 32, :3].sum() > 100
    (tmp_path / "t.obj").write_text("v -1 -0.5 0\nv 1 -0.5 0\nv 1 0.5 0\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n")
    with pytest.warns(UserWarning, match=r"t.obj:5: .* refers to a texture coordinate \(vt\) that does not exist.*its texture coordinates are ignored"):
        assert load_mesh(tmp_path / "t.obj").uvs is None
    (tmp_path / "v.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 3\n")
    with pytest.raises(MeshError, match=r"v.obj:3: face 'f 1 2 3' refers to a vertex that does not exist"):
        load_mesh(tmp_path / "v.obj")  # a missing position is still an error


def test_mtllib_with_several_files_and_map_colorspace(tmp_path):
    """tinyobjloader issues 112 and 184: `mtllib a.mtl b.mtl` names two libraries (was looked
    up as one file 'a.mtl b.mtl': every material lost); `map_Kd -colorspace sRGB tex.png`
    looked for a file named '-colorspace sRGB tex.png'."""
    from PIL import Image

    Image.fromarray(np.full((2, 2, 3), 200, np.uint8)).save(tmp_path / "tex.png")
    (tmp_path / "a.mtl").write_text("newmtl red\nKd 1 0 0\n")
    (tmp_path / "b.mtl").write_text("newmtl textured\nKd 1 1 1\nmap_Kd -colorspace sRGB -o 0.1 tex.png\n")
    (tmp_path / "m.obj").write_text(
        "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3\nusemtl textured\nf 1/1 3/3 2/2\n")
    red, textured = (p.material for p in load_mesh(tmp_path / "m.obj").parts)
    assert red.diffuse[:3] == (1.0, 0.0, 0.0)
    assert textured.texture is not None and textured.texture.pixels[0, 0, 0] == 200


def test_an_mtllib_that_is_a_folder_is_skipped_like_a_missing_one(tmp_path, capsys):
    # It raised IsADirectoryError's "[Errno 21] Is a directory: '...'", naming neither the
    # OBJ nor the material library.
    (tmp_path / "sub").mkdir()
    path = tmp_path / "m.obj"
    path.write_bytes(b"mtllib sub\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.warns(UserWarning, match="material library 'sub'"):
        mesh = load_mesh(path)
    assert len(mesh.indices) == 1


def test_indented_obj_lines_are_read(tmp_path):
    """Blanks before a keyword are allowed; they used to hide every line ('0 vertices')."""
    path = tmp_path / "indented.obj"
    path.write_text("  v 0 0 0\n\tv 1 0 0\n v 0 1 0\n   f 1 2 3\n")
    mesh = load_mesh(path)
    assert (mesh.vertex_count, mesh.triangle_count) == (3, 1)
    assert sorted(map(tuple, mesh.world_positions().round(6).tolist())) == [(0, 0, 0), (0, 1, 0), (1, 0, 0)]


def test_a_latin1_comment_in_an_obj_loads(tmp_path):
    path = tmp_path / "latin.obj"
    path.write_bytes("# café, naïve\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".encode("latin-1"))
    mesh = load_mesh(path)
    assert mesh.triangle_count == 1 and mesh.vertex_count == 3


def test_an_obj_with_classic_mac_line_endings_loads(tmp_path):
    path = tmp_path / "cr.obj"
    path.write_bytes(b"v 0 0 0\rv 1 0 0\rv 0 1 0\rv 1 1 0\rf 1 2 3\rf 2 4 3\r")
    mesh = load_mesh(path)
    assert len(mesh.indices) == 2 and len(mesh.positions) >= 4


def _reference_triangles(text: str) -> list[tuple]:
    """Each face line fan-triangulated in file order, every corner as its (position, uv,
    normal) values (None where the corner gives none): an independent reading, line by
    line, of the subset of OBJ the generator below writes."""
    v, vt, vn, triangles = [], [], [], []

    def resolve(number: str, table: list):
        if not number:
            return None
        index = int(number)
        return table[index - 1] if index > 0 else table[len(table) + index]

    for line in text.splitlines():
        key, *rest = line.split()
        if key in ("v", "vt", "vn"):
            {"v": v, "vt": vt, "vn": vn}[key].append(tuple(float(x) for x in rest))
        elif key == "f":
            corners = []
            for token in rest:
                parts = (token.split("/") + ["", ""])[:3]
                corners.append((resolve(parts[0], v), resolve(parts[1], vt), resolve(parts[2], vn)))
            triangles += [(corners[0], corners[k], corners[k + 1]) for k in range(1, len(corners) - 1)]
    return triangles


def _generated_obj(rng: np.random.Generator) -> str:
    """Runs of faces of 3 to 6 corners (convex: corners in angular order on a circle, so no
    polygon is ear-clipped), in one corner format a run or `v//vn` and `v/vt/vn` mixed,
    indices positive or relative, more vertices declared between runs."""
    lines, count = [], 0
    for _ in range(rng.integers(1, 4)):
        added = int(rng.integers(6, 12))
        angles = np.sort(rng.uniform(0, 2 * np.pi, added))
        lines += [f"v {np.cos(a):.6f} {np.sin(a):.6f} 0" for a in angles]  # planar: no fan is re-cut
        lines += [f"vt {rng.uniform():.4f} {rng.uniform():.4f}" for _ in range(2)]
        lines += [f"vn 0 0 {1 if rng.uniform() < 0.5 else -1}" for _ in range(2)]
        first, count = count, count + added
        formats = [["v"], ["v/vt"], ["v/vt/vn"], ["v//vn"], ["v//vn", "v/vt/vn"]][rng.integers(5)]
        for _ in range(rng.integers(1, 9)):
            chosen = np.sort(rng.choice(added, size=int(rng.integers(3, 7)), replace=False)) + first
            tokens = []
            for index in chosen.tolist():
                number = str(index + 1) if rng.uniform() < 0.7 else str(index - count)  # relative: from the end so far
                uv, normal = str(int(rng.integers(1, 3))), str(int(rng.integers(-2, 0)))
                tokens.append({"v": number, "v/vt": f"{number}/{uv}", "v/vt/vn": f"{number}/{uv}/{normal}",
                               "v//vn": f"{number}//{normal}"}[rng.choice(formats)])
            lines.append("f " + rng.choice([" ", "  ", "\t"]).join(tokens))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("seed", range(40))
def test_faces_are_read_as_a_line_by_line_reading_gives_them(tmp_path, seed):
    """Polygons of several sizes in one run (Blender's quads among triangles), `v//vn`, tabs,
    relative indices: the faces read at once in numpy are the fan triangles of each line in
    order, with each corner's position, uv and normal. (Once, runs whose lines had different
    corner counts but as many numbers in all as equal polygons would have were cut wrongly.)"""
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    text = _generated_obj(np.random.default_rng(seed))
    path = tmp_path / "faces.obj"
    path.write_text(text)
    (piece,) = read_obj(path).pieces
    expected = _reference_triangles(text)
    assert len(piece.faces) == len(expected)
    np.testing.assert_array_equal(piece.positions[piece.faces], [[c[0] for c in t] for t in expected])
    if all(c[1] is not None for t in expected for c in t):
        np.testing.assert_array_equal(piece.uvs[piece.faces], np.float32([[c[1] for c in t] for t in expected]))  # (kept as the Mesh keeps them)
    else:
        assert piece.uvs is None
    if all(c[2] is not None for t in expected for c in t):
        np.testing.assert_array_equal(piece.normals[piece.faces], [[c[2] for c in t] for t in expected])
    else:
        assert piece.normals is None


def test_polygons_of_different_sizes_whose_numbers_add_up_like_equal_ones(tmp_path):
    """A quad, a pentagon, a triangle and a quad: 16 corners, as many as four quads. Read as
    four quads, the pentagon's last corner began the triangle."""
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    circle = "".join(f"v {np.cos(a):.6f} {np.sin(a):.6f} 0\n" for a in np.linspace(0, 6, 8))
    path = tmp_path / "sizes.obj"
    path.write_text(circle + "f 1 2 3 4\nf 1 3 5 6 7\nf 2 4 6\nf 1 2 7 8\n")
    (piece,) = read_obj(path).pieces
    triangles = piece.positions[piece.faces]
    reference = _reference_triangles(path.read_text())
    np.testing.assert_array_equal(triangles, [[c[0] for c in t] for t in reference])


@pytest.mark.parametrize("lines, culprit", [
    ("v 0 0 0 1\nv 1 0\nv 0 1 0\n", "sizes.obj:2: 'v' line has 2 numbers, expected 3"),  # x y z w, then a short one
    ("v 0 0 0\nv 1 0 0 1 1 1 1\nv 0 1\n", "sizes.obj:3: 'v' line has 2 numbers, expected 3"),  # a long colour line
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvt 1\nvt 0 1\n", "sizes.obj:5: 'vt' line has 1 numbers, expected 2"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1 0\nvn 0 0\nvn 0 0 1\n", "sizes.obj:5: 'vn' line has 2 numbers, expected 3"),
])
@pytest.mark.parametrize("at_once", [None, 2])
def test_coordinate_lines_whose_numbers_add_up_like_equal_ones(tmp_path, monkeypatch, lines, culprit, at_once):
    """A `v` line with a w and a short one after it hold 4 + 2 numbers, as many as two of 3:
    read as rows of 3, the short line took the w as its x. Each line holds its own numbers
    (the OBJ is a line per statement), so the short line is refused, naming it, as the
    line-by-line reading refuses it; in blocks of a few lines too."""
    from wgpu_shading.assets.mesh_formats import obj_blocks

    if at_once:
        monkeypatch.setattr(obj_blocks, "NUMBER_LINES_AT_ONCE", at_once)
    path = tmp_path / "sizes.obj"
    faces = "f 1/1/1 2/2/2 3/3/3\n" if "vt" in lines and "vn" in lines else "f 1/1 2/2 3/3\n" if "vt" in lines else "f 1//1 2//2 3//3\n" if "vn" in lines else "f 1 2 3\n"
    path.write_text(lines + faces)
    with pytest.raises(MeshError) as raised:
        load_mesh(path)
    assert culprit in str(raised.value)


def test_coordinate_lines_of_random_widths_read_as_line_by_line(tmp_path, monkeypatch):
    """100 small OBJs whose `v` and `vt` lines hold random counts of numbers (x y z, a w, a
    colour, too few, too many), in random order: the block reading gives what the
    line-by-line reading gives, the same arrays or the same error (33 of 400 such files
    differed while only the block's total was checked)."""
    from wgpu_shading.assets.mesh_formats import obj_blocks
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    def read(path):
        try:
            with warnings.catch_warnings():  # (degenerate fans of random faces: said, and beside the point here)
                warnings.simplefilter("ignore")
                (piece,) = read_obj(path).pieces
        except MeshError as error:
            return str(error)
        return [None if a is None else a.tobytes() for a in (piece.positions, piece.uvs, piece.colors, piece.faces)]

    rng = np.random.default_rng(7)
    block_reading = obj_blocks.parse_floats
    for number in range(100):
        count = int(rng.integers(3, 12))
        widths = rng.choice([3, 3, 3, 3, 4, 6, 6, 2, 7], size=count) if number % 2 else np.full(count, rng.choice([3, 6]))
        lines = ["v " + " ".join(f"{x:.3f}" for x in rng.normal(size=width)) for width in widths]
        if number % 4 < 2:
            lines += ["vt " + " ".join(f"{x:.3f}" for x in rng.random(rng.choice([2, 2, 2, 3, 1]))) for _ in range(count)]
            lines += [f"f {a}/{a} {b}/{b} {c}/{c}" for a, b, c in rng.integers(1, count + 1, (5, 3))]
        else:
            lines += [f"f {a} {b} {c}" for a, b, c in rng.integers(1, count + 1, (5, 3))]
        if number % 3 == 0:
            rng.shuffle(lines)
        path = tmp_path / f"widths{number}.obj"
        path.write_text("\n".join(lines) + "\n")
        monkeypatch.setattr(obj_blocks, "parse_floats", block_reading)
        in_blocks = read(path)
        monkeypatch.setattr(obj_blocks, "parse_floats", lambda text, line_width=None: None)  # every line one by one
        assert in_blocks == read(path), path.read_text()


@pytest.mark.parametrize("seed", range(10))
def test_faces_read_in_blocks_of_a_few_lines_are_the_same(tmp_path, seed, monkeypatch):
    """Long runs are read FACE_LINES_AT_ONCE lines at a time: blocks of 2 lines give the
    same triangles, in order (each block's polygon numbers continue the last one's)."""
    from wgpu_shading.assets.mesh_formats import obj_faces
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    text = _generated_obj(np.random.default_rng(100 + seed))
    path = tmp_path / "blocks.obj"
    path.write_text(text)
    whole = read_obj(path).pieces[0]
    monkeypatch.setattr(obj_faces, "FACE_LINES_AT_ONCE", 2)
    blocks = read_obj(path).pieces[0]
    np.testing.assert_array_equal(blocks.positions[blocks.faces], whole.positions[whole.faces])
    np.testing.assert_array_equal(blocks.positions[blocks.faces], [[c[0] for c in t] for t in _reference_triangles(text)])


@pytest.mark.parametrize("seed", range(5))
def test_coordinates_read_in_blocks_of_a_few_lines_are_the_same(tmp_path, seed, monkeypatch):
    """v/vt/vn lines are read NUMBER_LINES_AT_ONCE lines at a time: blocks of 2 lines give the
    same values as one block, and as float() of each number; a block of lines with a `w`
    among plain ones (a width the whole-text reading cannot take) reads the same too."""
    from wgpu_shading.assets.mesh_formats import obj_blocks
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    rng = np.random.default_rng(300 + seed)
    text = _generated_obj(rng)
    if seed % 2:
        text = text.replace("\nv ", "\nv 1e-3 2.5E1 -7 1\nv ", 1)  # an exponent, and x y z w once
    path = tmp_path / "coordinates.obj"
    path.write_text(text)
    whole = read_obj(path).pieces[0]
    monkeypatch.setattr(obj_blocks, "NUMBER_LINES_AT_ONCE", 2)
    blocks = read_obj(path).pieces[0]
    np.testing.assert_array_equal(blocks.positions, whole.positions)
    np.testing.assert_array_equal(blocks.faces, whole.faces)
    if seed % 2:
        assert [1e-3, 25.0, -7.0] in blocks.positions.tolist()
    else:  # (the extra vertex above makes some fans degenerate, which the reader leaves out)
        np.testing.assert_array_equal(blocks.positions[blocks.faces], [[c[0] for c in t] for t in _reference_triangles(text)])


def test_faces_group_by_material_in_order_of_first_use(tmp_path):
    """Faces are sorted into one range per material, materials in the order the faces first
    use them, file order kept within each (a stable sort); a quad's two triangles stay
    together. Faces before any `usemtl` form a part without a material. Written out by hand
    here, since the reader lists materials per run of face lines, not per face."""
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    (tmp_path / "m.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\n")
    (tmp_path / "m.obj").write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
        "f 1 2 3\nusemtl red\nf 1 2 4 5\nusemtl green\nf 2 3 4\nusemtl red\nf 3 4 5\n"
    )
    piece = read_obj(tmp_path / "m.obj").pieces[0]
    assert piece.faces.tolist() == [[0, 1, 2], [0, 1, 3], [0, 3, 4], [2, 3, 4], [1, 2, 3]]
    assert [(first, count, name) for first, count, _, name in piece.parts] == [(0, 1, ""), (1, 3, "red"), (4, 1, "green")]
    assert [material is None for _, _, material, _ in piece.parts] == [True, False, False]


def _richer_obj(rng: np.random.Generator) -> str:
    """_generated_obj's runs with materials, `s off`, indented and CR LF lines, comments,
    `l` and `p` records and a vertex with a colour among them."""
    lines = ["mtllib missing.mtl"]
    for number, line in enumerate(_generated_obj(rng).splitlines()):
        if line.startswith("f ") and rng.uniform() < 0.2:
            lines += [f"usemtl m{int(rng.integers(3))}", "s off" if rng.uniform() < 0.5 else "s 1"]
        if line.startswith("v ") and rng.uniform() < 0.1:
            lines.append("  # an indented comment")
        lines.append(("\t" + line) if rng.uniform() < 0.05 else line)
    lines += ["l 1 2 3", "p 1 -1", "o done"]
    return "\r\n".join(lines) if rng.uniform() < 0.3 else "\n".join(lines)


@pytest.mark.parametrize("seed", range(12))
def test_a_file_read_in_blocks_of_a_few_bytes_is_the_file_read_whole(tmp_path, seed, monkeypatch):
    """The text is read a block of whole lines at a time (16 MiB): runs of faces, the
    `usemtl`/`s` state, relative indices, `l`/`p` records and line numbers go on across
    blocks, so blocks of a line or a few give the same pieces, warnings and errors."""
    import warnings

    from wgpu_shading.assets import files
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    rng = np.random.default_rng(700 + seed)
    text = _richer_obj(rng)
    if seed % 4 == 3:  # an error on a line past the first blocks: named with its line number
        text += "\nf 1 2 0\n"
    path = tmp_path / "blocks.obj"
    path.write_bytes(text.encode())

    def read(block_bytes: int):
        monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", block_bytes)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                pieces = read_obj(path).pieces
            except MeshError as error:
                return str(error), sorted(str(w.message) for w in caught)
        arrays = [(p.primitive, p.positions, p.faces, p.normals, p.uvs, p.colors, p.flat, [part[:2] + part[3:] for part in p.parts])
                  for p in pieces]
        return arrays, sorted(str(w.message) for w in caught)

    whole, whole_warnings = read(1 << 24)
    for block_bytes in (2, 40, 333):
        blocks, block_warnings = read(block_bytes)
        assert block_warnings == whole_warnings
        if isinstance(whole, str):
            assert blocks == whole and f"{path}:" in whole
            continue
        assert len(blocks) == len(whole)
        for ours, theirs in zip(blocks, whole):
            assert ours[0] == theirs[0] and ours[-1] == theirs[-1]
            for a, b in zip(ours[1:-1], theirs[1:-1]):
                assert (a is None) == (b is None)
                if a is not None:
                    np.testing.assert_array_equal(a, b)


def read_in_small_blocks(path, monkeypatch):
    """read_obj's one piece and tracemalloc's peak while it reads, the file read in chunks
    of 256 KiB and blocks of 64 KiB (16 MiB and 4 MiB scaled to a test's few MB), an
    exported OBJ's vertices gathered 1000 rows at a time."""
    import tracemalloc

    from wgpu_shading.assets import files
    from wgpu_shading.assets.mesh_formats import obj
    from wgpu_shading.assets.mesh_formats.obj import read_obj

    monkeypatch.setattr(files, "TEXT_CHUNK", 1 << 18)
    monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", 1 << 16)
    monkeypatch.setattr(obj, "GATHER_ROWS", 1000)
    tracemalloc.start()
    try:
        (piece,) = read_obj(path).pieces
        return piece, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_a_big_obj_is_read_in_a_few_times_its_arrays(tmp_path, monkeypatch):
    """A scan-like OBJ (plain `v` and `f a b c` lines) is read a block at a time: the text's
    line strings and int64 corners of the whole file are never held at once. tracemalloc's
    peak, in the arrays the reader gives (float64 positions, uint32 faces), with the file
    read in chunks of 256 KiB and blocks of 64 KiB (16 MiB and 4 MiB scaled to this 2.6 MB
    file): 1.8x here (2.1x while every corner kept three int32s); the reader that split the
    whole text into lines and kept every corner as three int64s peaked at 18x the same
    arrays."""
    side = 200  # 40,000 vertices, 79,202 triangles, 2.6 MB of text
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    positions = np.stack([u, v, 0.1 * np.sin(6 * u)], -1).reshape(-1, 3)
    grid = np.arange(side * side).reshape(side, side) + 1
    a, b, c, d = grid[:-1, :-1].ravel(), grid[:-1, 1:].ravel(), grid[1:, :-1].ravel(), grid[1:, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    path = tmp_path / "grid.obj"
    path.write_text("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in positions) + "".join(f"f {i} {j} {k}\n" for i, j, k in faces))
    piece, peak = read_in_small_blocks(path, monkeypatch)
    np.testing.assert_array_equal(piece.faces, faces - 1)
    np.testing.assert_array_equal(piece.positions, [[float(f"{x:.6f}") for x in row] for row in positions])
    arrays = piece.positions.nbytes + piece.faces.nbytes
    assert peak < 2.2 * arrays, f"peak {peak / arrays:.2f}x the arrays"


def test_a_concave_face_through_one_point_again_and_again_keeps_its_fan(tmp_path, monkeypatch):
    """Ear clipping is for real polygons: mapbox_earcut on a ring that comes back to one point
    again and again took 63 s at 8,000 corners (a 60 KB file). Such a face, and any face
    over EAR_CLIP_CORNERS corners, keeps its fan (corners − 2 triangles) with a warning;
    a slit's two visits to a point (test_concave_obj_polygon_leaves_its_notch_open) and an
    L still cut by ear clipping."""
    from wgpu_shading.assets.mesh_formats import obj_faces

    (tmp_path / "loops.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1" + " 2 3 4 2" * 750 + "\n")
    with pytest.warns(UserWarning, match=r"loops\.obj: 1 concave face passes more than twice through one point .*drawn as its fan"):
        mesh = load_mesh(tmp_path / "loops.obj")
    assert mesh.triangle_count == 3001 - 2
    l_shape = "v 0.8 0 0\nv 0 0 0\nv 0 0.8 0\nv -0.8 0.8 0\nv -0.8 -0.8 0\nv 0.8 -0.8 0\nf 1 2 3 4 5 6\n"
    (tmp_path / "l.obj").write_text(l_shape)
    cut = load_mesh(tmp_path / "l.obj").indices.copy()
    monkeypatch.setattr(obj_faces, "EAR_CLIP_CORNERS", 5)
    with pytest.warns(UserWarning, match=r"l\.obj: 1 concave face .*over 5 corners"):
        fan = load_mesh(tmp_path / "l.obj").indices
    assert len(fan) == len(cut) == 4 and not np.array_equal(fan, cut)  # the fan covers the notch, ear clipping did not


def test_comments_after_an_elements_numbers_are_read_past(tmp_path):
    """`v 1 2 3 # top`: trimesh and VTK's reader (f3d's) read past a comment after the
    numbers; it was "cannot read 'v' line (expected numbers)". The same mesh as the file
    without them, in the files' fast reading (blocks of lines) and its line-by-line one
    (`vt` of three numbers beside ones of two), `s off # flat` flat (the quad is bent: its
    smooth normals differ); a `#` in a name is part of the name."""
    plain = ("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\nvt 0 0\nvt 1 0 0\nvt 1 1\nvt 0 1\n"
             "usemtl red#1\ns off\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
    commented = ("# a header ## with hashes\nmtllib m.mtl\nv 0 0 0 # origin\nv 1 0 0#x\nv 1 1 0\nv 0 1 0.5\t# last\n"
                 "vt 0 0 # uv\nvt 1 0 0\nvt 1 1\nvt 0 1\nusemtl red#1\ns off # flat\nf 1/1 2/2 3/3 # lower\n"
                 "f 1/1 3/3 4/4 #\n")
    meshes = []
    for name, text in (("plain", plain), ("commented", commented)):
        folder = tmp_path / name
        folder.mkdir()
        (folder / "m.mtl").write_text("newmtl red#1\nKd 1 0 0\n")
        (folder / "quad.obj").write_text(text)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # (the material found: no warning)
            meshes.append(load_mesh(folder / "quad.obj"))
    for attribute in ("positions", "indices", "normals", "uvs"):
        np.testing.assert_array_equal(getattr(meshes[0], attribute), getattr(meshes[1], attribute), err_msg=attribute)
    assert meshes[1].parts[0].material.diffuse[:3] == pytest.approx((1, 0, 0))


def test_a_line_ending_in_a_backslash_goes_on_on_the_next(tmp_path):
    """The OBJ specification's line continuation (Blender's importer reads it): the same mesh
    as the file written on single lines; errors after it keep their line numbers, and a
    comment ending in a backslash continues nothing."""
    plain = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
    continued = "# C:\\models\\\nv 0 0 0\nv 1 \\\n 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 \\\r\n 3 \\ \n 4\n"
    (tmp_path / "plain.obj").write_text(plain)
    (tmp_path / "continued.obj").write_bytes(continued.encode())
    expected, mesh = load_mesh(tmp_path / "plain.obj"), load_mesh(tmp_path / "continued.obj")
    for attribute in ("positions", "indices", "normals", "origin"):
        np.testing.assert_array_equal(getattr(mesh, attribute), getattr(expected, attribute), err_msg=attribute)
    (tmp_path / "bad.obj").write_bytes((continued + "f 1 2 x\n").encode())
    with pytest.raises(MeshError, match=r"bad.obj:10: cannot read face 'f 1 2 x'"):
        load_mesh(tmp_path / "bad.obj")
