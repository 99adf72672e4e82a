"""Binary PLY triangle meshes read with numpy, a block of rows at a time: what scanners,
MeshLab, VTK and Open3D write for a mesh (Lucy, the big-endian horse, MeshLab's coloured
exports in ../shared/corpora/realworld2/ply).

trimesh's reader, which reads every other PLY (trimesh_reader.py), holds the whole file in
memory and makes float64 and int64 copies of it: a 2M-triangle binary PLY peaked at 4.0×
its mesh's arrays (`python benchmarks/scripts/load_peak.py`), over issue #29's 3× for big
meshes. Here the rows go straight into the arrays a Mesh keeps (float32 positions where the
file has floats, 32-bit indices), and the peak is that of a binary STL (stl.py).

Only this layout is read here, and it is read as trimesh reads it (tests/test_ply_triangles.py
compares the two on real files and on every case below); any other PLY goes to trimesh:
- binary (either byte order), its non-empty elements `vertex` then `face`;
- vertex: scalar properties with x, y, z; nx, ny, nz are its normals and red, green, blue
  (alpha) its colours when they are uchar; others (MeshLab's flags and quality, a scanner's
  confidence) are skipped, as trimesh skips them. Texture coordinates (trimesh's names for
  them: TEXTURE_PAIRS) are read by ply_polygons.py, a pair per vertex;
- face: one list property, vertex_indices or vertex_index, then only scalar properties,
  read past as trimesh keeps them aside (MeshLab's flags and quality), except uchar red,
  green, blue (alpha): a face's colour, every corner then its own vertex, as trimesh
  gives them for triangles (unless the vertices have colours: then those, as trimesh; a
  polygon's colour goes to each of its triangles, which trimesh does not do: it keeps one
  colour a polygon beside twice as many triangles); a `texcoord` list
  after the indices goes to ply_face_uvs.py; every face a
  polygon of the same size (triangles,
  quads as quad-remeshers write them, ...): the file is exactly as long as that makes it,
  and every count read is that size (a file of mixed polygons: ply_polygons.py). Polygons
  are cut into triangles as trimesh cuts them (trimesh.geometry.triangulate_quads): a quad
  (a, b, c, d) into (a, b, c), then after every quad's first, (c, d, a); a larger one into
  its fan from its first corner, one polygon after the other. A 2M-triangle file of quads
  through trimesh peaked at 4.7x its mesh's arrays.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..mesh_pieces import MeshPiece, polygon_fans, with_face_colors
from .checks import MAX_FACE_CORNERS
from .ply_header import PLY_TYPES, PlyHeader

# The names trimesh reads texture coordinates under (trimesh/exchange/ply.py, _elements_to_kwargs)
TEXTURE_PAIRS = (("texture_u", "texture_v"), ("u", "v"), ("s", "t"))
TEXTURE_NAMES = frozenset(name for pair in TEXTURE_PAIRS for name in pair)
INDEX_NAMES = ("vertex_indices", "vertex_index")
COLOR_NAMES = ("red", "green", "blue", "alpha")
BLOCK_ROWS = 1 << 18  # vertices or faces read at a time: a few MB of records


@dataclass(frozen=True)
class TriangleLayout:
    """Where a binary PLY's vertices and faces are, and their record types."""

    vertex: np.dtype  # one vertex row (structured: the file's properties)
    face: np.dtype  # one face row: ("count", its type), ("corners", index type, (corners,))
    vertices: int
    faces: int
    offset: int  # the first vertex row's byte

    @property
    def corners(self) -> int:
        """Every face's size."""
        return self.face.fields["corners"][0].shape[0]


def triangle_layout(header: PlyHeader, file_size: int) -> TriangleLayout | None:
    """The layout of a binary PLY this module reads (the module docstring), or None for any
    other PLY. The faces' size is the one that makes the file exactly as long as it is."""
    if header.format not in ("binary_little_endian", "binary_big_endian"):
        return None
    order = "<" if header.format == "binary_little_endian" else ">"
    rows = mesh_rows(header, order, face_scalars=True)
    if rows is None:
        return None
    vertex_row, face_row = rows
    vertices, faces = header.count("vertex"), header.count("face")
    face_bytes = file_size - header.header_bytes - vertices * vertex_row.itemsize
    index_bytes = face_row.fields["corners"][0].base.itemsize
    others = face_row.itemsize - 3 * index_bytes  # the count and the scalars skipped
    if faces <= 0 or face_bytes % faces or (face_bytes // faces - others) % index_bytes:
        return None  # not faces of one size (or truncated, or more after them): trimesh says which
    corners = (face_bytes // faces - others) // index_bytes
    if corners < 3:
        return None
    if corners != 3:
        face_row = mesh_rows(header, order, corners, face_scalars=True)[1]
    return TriangleLayout(vertex_row, face_row, vertices, faces, header.header_bytes)


def fan_count(corners: int, faces: int) -> int:
    """The triangles `faces` polygons of `corners` corners are cut into."""
    return faces * (corners - 2)


def mesh_rows(header: PlyHeader, order: str, corners: int = 3, texture: bool = False,
              face_texture: bool = False, face_scalars: bool = False) -> tuple[np.dtype, np.dtype] | None:
    """A vertex row's and a face's record types (byte order `order`, faces of `corners`
    corners) when the header's elements and properties are of the layout this module reads
    (the module docstring, binary or not), else None. `texture`: vertex texture coordinates
    too, a pair of texture_pair()'s (ply_polygons.py reads them; here they go to trimesh).
    `face_texture`: the faces' second property is a `texcoord` list of floats, two a corner
    (ply_face_uvs.py reads them): ("uv_count", ...), ("uv", ..., (2 × corners,)).
    `face_scalars`: scalar properties may follow the face's lists, as MeshLab writes its
    flags and quality, Metashape its `texnumber`: fields (SKIPPED + "0", ...) that are read
    past, as trimesh keeps them aside; a face's uchar red, green, blue (alpha) are its colour,
    fields ("face red", ...) (face_color_fields; float ones: None, trimesh reads them)."""
    filled = [element for element in header.elements if element.count]
    if [element.name for element in filled] != ["vertex", "face"]:
        return None
    vertex, face = filled
    names = [name for name, _, _ in vertex.properties]
    if len(set(names)) != len(names) or not {"x", "y", "z"} <= set(names):
        return None
    if TEXTURE_NAMES & set(names) and (not texture or texture_pair(names) is None):
        return None
    if any(count is not None or kind not in PLY_TYPES for _, kind, count in vertex.properties):
        return None
    kinds = {name: PLY_TYPES[kind] for name, kind, _ in vertex.properties}
    colors = [name for name in COLOR_NAMES if name in kinds]
    if colors and (colors[:3] != ["red", "green", "blue"] or any(kinds[name] != "u1" for name in colors)):
        return None
    if len({"nx", "ny", "nz"} & set(names)) not in (0, 3):
        return None
    lists = 1 + face_texture  # the index list, then the texcoord list
    if len(face.properties) < lists or (len(face.properties) > lists and not face_scalars):
        return None
    name, index_kind, count_kind = face.properties[0]
    if name not in INDEX_NAMES or count_kind is None or index_kind not in PLY_TYPES or count_kind not in PLY_TYPES:
        return None
    if PLY_TYPES[index_kind][0] not in "iu" or PLY_TYPES[count_kind][0] not in "iu":
        return None
    vertex_row = np.dtype([(name, order + kind) for name, kind in kinds.items()])
    fields = [("count", order + PLY_TYPES[count_kind]), ("corners", order + PLY_TYPES[index_kind], (corners,))]
    if face_texture:
        uv_name, uv_kind, uv_count_kind = face.properties[1]
        if uv_name != "texcoord" or uv_count_kind not in PLY_TYPES or uv_kind not in PLY_TYPES:
            return None
        if PLY_TYPES[uv_kind][0] != "f" or PLY_TYPES[uv_count_kind][0] not in "iu":
            return None
        fields += [("uv_count", order + PLY_TYPES[uv_count_kind]), ("uv", order + PLY_TYPES[uv_kind], (2 * corners,))]
    scalars = face.properties[lists:]
    if any(count is not None or kind not in PLY_TYPES for _, kind, count in scalars):
        return None
    face_colors = [name for name, _, _ in scalars if name in COLOR_NAMES]
    if face_colors and (sorted(face_colors, key=COLOR_NAMES.index)[:3] != ["red", "green", "blue"] or len(set(face_colors)) != len(face_colors)
                        or any(PLY_TYPES[kind] != "u1" for name, kind, _ in scalars if name in COLOR_NAMES)):
        return None  # (float face colours: trimesh)
    fields += [(FACE_COLOR + name if name in COLOR_NAMES else f"{SKIPPED}{number}", order + PLY_TYPES[kind])
               for number, (name, kind, _) in enumerate(scalars)]
    return vertex_row, np.dtype(fields)


FACE_COLOR = "face "  # the face record's fields of a face's colour: "face red", ...
SKIPPED = "skipped "  # the face record's scalars read past: "skipped 0", ...


def face_color_fields(face_row: np.dtype) -> list[str]:
    """The face record's colour fields, red, green, blue (alpha) (mesh_rows): MeshLab's face colours."""
    return [FACE_COLOR + name for name in COLOR_NAMES if FACE_COLOR + name in face_row.names]


def skipped_scalars(face_row: np.dtype) -> int:
    """How many scalars (mesh_rows) follow a face's lists and are read past (MeshLab's flags)."""
    return sum(name.startswith(SKIPPED) for name in face_row.names)


def read_face_colors(block: np.ndarray, fields: list[str], out: np.ndarray) -> None:
    """A block of face records' colours into `out` (its rows)."""
    for column, field in enumerate(fields):
        out[:, column] = block[field]


def read_triangles(path: Path, layout: TriangleLayout, where: str) -> MeshPiece | None:
    """The mesh of a PLY in `layout`, or None when some face turns out to be of another
    size (then trimesh reads the file). Indices are checked later, with every other
    reader's (mesh_pieces.py)."""
    corners = layout.corners
    if corners > MAX_FACE_CORNERS:  # refused when the first face says so, as an OBJ's (trimesh took 2.4 GB to one of 12M)
        with open(path, "rb") as file:
            file.seek(layout.offset + layout.vertices * layout.vertex.itemsize)
            count = np.fromfile(file, layout.face.fields["count"][0], 1)
        if len(count) and int(count[0]) == corners:
            raise MeshError(f"{where}: a face of {corners} corners; at most {MAX_FACE_CORNERS} are supported")
        return None
    if fan_count(corners, layout.faces) > MAX_TRIANGLES:  # (before the arrays are made)
        raise MeshError(f"{where}: {layout.faces} faces of {corners} corners make {fan_count(corners, layout.faces)} triangles; "
                        f"at most {MAX_TRIANGLES} are supported")
    color_fields = face_color_fields(layout.face)
    positions, normals, colors, faces = mesh_arrays(layout.vertex, layout.face, layout.vertices, fan_count(corners, layout.faces))
    face_colors = np.empty((layout.faces, len(color_fields)), np.uint8) if color_fields and colors is None else None
    try:
        with open(path, "rb") as file:
            file.seek(layout.offset)
            read_vertices(file, layout.vertex, positions, normals, colors, where)
            for start in range(0, layout.faces, BLOCK_ROWS):
                block = file_rows(file, layout.face, min(BLOCK_ROWS, layout.faces - start), where)
                if (block["count"] != corners).any():
                    return None
                cut_polygons(block["corners"], start, layout.faces, faces)
                if face_colors is not None:
                    read_face_colors(block, color_fields, face_colors[start : start + len(block)])
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {layout.vertices} vertices and {layout.faces} faces") from None
    piece = MeshPiece(positions, faces, normals, colors=colors, parts=[(0, len(faces), None, path.name)])
    # Face colours (where the vertices have none, as trimesh reads them): every corner its own
    # vertex, every triangle its polygon's colour.
    if face_colors is None:
        return piece
    return with_face_colors(piece, polygon_colors(np.full(layout.faces, corners, np.min_scalar_type(MAX_FACE_CORNERS)), face_colors))


def polygon_colors(counts: np.ndarray, face_colors: np.ndarray) -> np.ndarray:
    """Each triangle's colour, for faces of these corner counts with a colour each (a row
    a face), in the order their triangles are cut, as trimesh cuts them (cut_polygons; of
    several sizes, ply_polygons.MixedCut): every triangle, then every quad's first half and
    every quad's second, then each larger polygon's fan; faces of fewer than 3 corners
    make none."""
    counts = np.asarray(counts)
    if (counts == 3).all():
        return face_colors
    quads, larger = face_colors[counts == 4], counts > 4
    return np.concatenate([face_colors[counts == 3], quads, quads, np.repeat(face_colors[larger], counts[larger] - 2, axis=0)])


def texture_pair(names) -> tuple[str, str] | None:
    """The vertex properties that are texture coordinates, in trimesh's order of preference
    (trimesh/exchange/ply.py, _elements_to_kwargs), or None."""
    return next(((u, v) for u, v in TEXTURE_PAIRS if u in names and v in names), None)


def read_vertices(file, vertex_row: np.dtype, positions, normals, colors, where: str, uvs=None) -> None:
    """The vertex rows at the file's position, a block at a time, into the arrays made by
    mesh_arrays (normals, colours and texture coordinates None where the file has none)."""
    channels = [name for name in COLOR_NAMES if name in vertex_row.fields]
    pair = texture_pair(vertex_row.names) if uvs is not None else None
    for start in range(0, len(positions), BLOCK_ROWS):
        block = file_rows(file, vertex_row, min(BLOCK_ROWS, len(positions) - start), where)
        rows = slice(start, start + len(block))
        for column, axis in enumerate("xyz"):
            positions[rows, column] = block[axis]
        if normals is not None:
            for column, axis in enumerate(("nx", "ny", "nz")):
                normals[rows, column] = block[axis]
        for column, channel in enumerate(channels):
            colors[rows, column] = block[channel]
        for column, name in enumerate(pair or ()):
            uvs[rows, column] = block[name]


def cut_polygons(polygons: np.ndarray, start: int, count: int, triangles: np.ndarray) -> None:
    """Polygons start .. start + len(polygons) of `count`, all of one size, cut into their
    rows of `triangles` as trimesh cuts them (trimesh.geometry.triangulate_quads; the module
    docstring)."""
    corners = polygons.shape[1]
    if corners == 3:
        triangles[start : start + len(polygons)] = polygons
    elif corners == 4:  # every quad's (a, b, c), then every quad's (c, d, a)
        triangles[start : start + len(polygons)] = polygons[:, [0, 1, 2]]
        triangles[count + start : count + start + len(polygons)] = polygons[:, [2, 3, 0]]
    else:  # each polygon's fan (a, k, k + 1), one polygon after the other
        triangles[start * (corners - 2) : (start + len(polygons)) * (corners - 2)] = polygon_fans(polygons)


def mesh_arrays(vertex_row: np.dtype, face_row: np.dtype, vertices: int, faces: int):
    """The arrays a mesh of these records is read into (`faces` triangles): positions and
    normals as float32 where the file's values are float32 (or small integers), else
    float64; RGB(A) uint8;
    the faces' indices 32-bit, unsigned when the file's are (normals, colours None when
    the file has none)."""
    fields = vertex_row.fields
    positions = np.empty((vertices, 3), float_type(fields, "xyz"))
    normals = np.empty((vertices, 3), float_type(fields, ("nx", "ny", "nz"))) if "nx" in fields else None
    channels = [name for name in COLOR_NAMES if name in fields]
    colors = np.empty((vertices, len(channels)), np.uint8) if channels else None
    index_kind = face_row.fields["corners"][0].base
    triangles = np.empty((faces, 3), np.uint32 if index_kind.kind == "u" and index_kind.itemsize == 4 else np.int32)
    return positions, normals, colors, triangles


def file_rows(file, row: np.dtype, count: int, where: str) -> np.ndarray:
    """`count` records of `row` from the file's position (a MeshError when it has fewer)."""
    block = np.fromfile(file, row, count)
    if len(block) < count:  # the file shrank since its size was taken
        raise MeshError(f"{where}: truncated while it was read")
    return block


def float_type(fields, names) -> type:
    """float32 where the file's values are float32 (or small integers): exact, half the
    memory of float64; float64 for doubles and 32-bit integers."""
    small = all(fields[name][0].kind == "f" and fields[name][0].itemsize == 4
                or fields[name][0].kind in "iu" and fields[name][0].itemsize <= 2 for name in names)
    return np.float32 if small else np.float64
