"""glTF primitives → pieces, one per primitive instance (our own reader, document.py).

Every mode of §3.7.2.1 is read: triangles, triangle strips (alternating their winding) and
triangle fans (turning around their first vertex) as triangles; LINES, LINE_STRIP and
LINE_LOOP as line segments; POINTS as points (docs/primitives.md). Every TEXCOORD_n is
read (a texture's `texCoord` picks one: reader.py). A primitive instance is its morph
targets moved by its node's weights (morph_targets.py), then its node's world matrix
applied, or, for a skinned mesh, the joints' pose (nodes.pose). Draco-compressed primitives are
decoded with DracoPy (the `draco` extra).
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES, MAX_VERTICES
from ...scene.geometry.vertex_arrays import row_blocks
from .document import MAX_GLTF_ITEMS, GltfData, gltf_error
from .morph_targets import apply_morph_targets, morph_weights
from .nodes import pose, scene_nodes, scene_roots, skin_matrices, world_matrices

_POINTS, _LINES, _LINE_LOOP, _LINE_STRIP, _TRIANGLES, _STRIP, _FAN = range(7)
PRIMITIVE_OF_MODE = {_POINTS: "points", _LINES: "lines", _LINE_LOOP: "lines", _LINE_STRIP: "lines"}  # else triangles
# TEXCOORD_0..7 are read (what glTF exporters write, and more); a draw reads at most
# MAX_UV_SET + 1 of them, each with its transform (reader.py).
_UV_SET_NAMES = tuple(f"TEXCOORD_{k}" for k in range(8))
_DRACO = "KHR_draco_mesh_compression"
_SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"


@dataclass
class GltfPiece:
    positions: np.ndarray
    faces: np.ndarray | None  # (f, 3) triangles, (f, 2) line segments, None for points (every vertex one)
    normals: np.ndarray | None
    uv_sets: dict[int, np.ndarray]  # TEXCOORD_n by n, v flipped: 0 at the image's bottom (glTF's origin is its top)
    colors: np.ndarray | None  # (n, 4) in [0, 1]
    primitive: dict  # the glTF primitive (its material, attributes)
    name: str
    key: tuple[int, int]  # (mesh, primitive): instances of one primitive share its material
    tangents: np.ndarray | None = None  # (n, 4) TANGENT: xyz and handedness w, in world space
    kind: str = "triangles"  # triangles | lines | points

    @property
    def element_count(self) -> int:
        return len(self.positions) if self.faces is None else len(self.faces)


def triangles(mode: int, indices: np.ndarray) -> np.ndarray:
    """(f, 3) triangles of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN index list."""
    if mode == _TRIANGLES:
        return indices[: len(indices) // 3 * 3].reshape(-1, 3)
    count = len(indices) - 2
    if count <= 0:
        return np.zeros((0, 3), np.int64)
    i = np.arange(count)
    if mode == _STRIP:  # §3.7.2.1: {v_i, v_(i+1+i%2), v_(i+2-i%2)}
        faces = np.stack([indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]], axis=1)
    else:  # fan: {v_(i+1), v_(i+2), v_0}
        faces = np.stack([indices[i + 1], indices[i + 2], np.full(count, indices[0])], axis=1)
    # strips join separate runs with repeated indices: those triangles have no area
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    return faces[keep]


def segments(mode: int, indices: np.ndarray) -> np.ndarray:
    """(f, 2) segments of a LINES, LINE_STRIP or LINE_LOOP index list (§3.7.2.1)."""
    if mode == _LINES:
        return indices[: len(indices) // 2 * 2].reshape(-1, 2)
    if len(indices) < 2:
        return np.zeros((0, 2), np.int64)
    pairs = np.stack([indices[:-1], indices[1:]], axis=1)
    if mode == _LINE_LOOP:  # the loop closes from the last vertex back to the first
        pairs = np.concatenate([pairs, [[indices[-1], indices[0]]]])
    return pairs


def _attribute(data: GltfData, attributes: dict, name: str, where: str, count: int, widths: tuple[int, ...],
               as_stored: bool = False) -> np.ndarray | None:
    if name not in attributes:
        return None
    values = data.accessor(attributes[name], f"{where}.attributes.{name}", as_stored)
    if values.shape[1] not in widths or len(values) != count:
        raise gltf_error(data.path, f"{where}.attributes.{name}", f"expected {count} elements of width {'/'.join(map(str, widths))}, got {values.shape[0]} of width {values.shape[1]}")
    if values.dtype.kind == "f" and not np.isfinite(values).all():
        raise gltf_error(data.path, f"{where}.attributes.{name}", "values must be finite")
    return values


def _optional_tangents(data: GltfData, attributes: dict, where: str, count: int) -> np.ndarray | None:
    """TANGENT when it is usable (float VEC4, finite, one per vertex); otherwise None: a
    broken TANGENT never rejects a file, the normal map falls back to the derivative frame."""
    try:
        values = _attribute(data, attributes, "TANGENT", where, count, (4,))
    except MeshError:
        return None
    return values if values is not None and values.dtype.kind == "f" else None


def _draco(data: GltfData, primitive: dict, where: str) -> dict:
    """The decoded attributes of a Draco primitive: {'indices', 'POSITION', ...}."""
    try:
        import DracoPy
    except ImportError:
        from ...errors import install_hint

        raise MeshError(f"mesh file {str(data.path)!r} uses Draco mesh compression ({_DRACO}); to decode it, {install_hint('draco')}") from None
    extension = primitive["extensions"][_DRACO]
    if not isinstance(extension, dict) or not isinstance(extension.get("attributes"), dict):
        raise gltf_error(data.path, f"{where}.extensions.{_DRACO}", "expected an object with bufferView and attributes")
    try:
        decoded = DracoPy.decode(data.view_bytes(extension.get("bufferView"), f"{where}.extensions.{_DRACO}.bufferView"))
    except MeshError:
        raise
    except Exception as error:  # DracoPy raises its own kinds for damaged data
        raise gltf_error(data.path, f"{where}.extensions.{_DRACO}", f"cannot be decoded ({type(error).__name__})") from None
    out = {"indices": np.asarray(decoded.faces, dtype=np.int64).reshape(-1)}
    for name, unique_id in extension["attributes"].items():
        attribute = decoded.get_attribute_by_unique_id(unique_id) if isinstance(unique_id, int) else None
        if attribute is not None:
            values = np.asarray(attribute["data"], dtype=np.float64)
            out[name] = values.reshape(len(values), -1)
    return out


def _primitive_arrays(data: GltfData, primitive: dict, where: str) -> dict | None:
    """POSITION, NORMAL, TEXCOORD_n, COLOR_0, JOINTS_0/WEIGHTS_0 and the triangles, segments
    or points of one primitive, in the primitive's own space; None for a primitive without POSITION."""
    mode = data.integer(primitive.get("mode", _TRIANGLES), f"{where}.mode", 0, 6)
    attributes = primitive.get("attributes")
    if not isinstance(attributes, dict):
        raise gltf_error(data.path, f"{where}.attributes", f"expected an object, got {type(attributes).__name__}")
    if "POSITION" not in attributes:  # §3.7.2.1: the client skips it (with extensions that supply positions)
        data.notes.append(f"{data.path.name}: {where} has no POSITION attribute; skipped")
        return None
    extensions = primitive.get("extensions", {})
    if isinstance(extensions, dict) and _DRACO in extensions:
        decoded = _draco(data, primitive, where)
        positions = decoded.get("POSITION")
        if positions is None or positions.shape[1] != 3:
            raise gltf_error(data.path, f"{where}.extensions.{_DRACO}", "has no POSITION attribute")
        arrays = {name: decoded.get(name) for name in ("NORMAL", "TANGENT", "COLOR_0", "JOINTS_0", "WEIGHTS_0") + _UV_SET_NAMES}
        indices = decoded["indices"]
    else:
        positions = _attribute(data, attributes, "POSITION", where, data.accessor(attributes["POSITION"], f"{where}.attributes.POSITION", True).shape[0], (3,), True)
        count = len(positions)
        arrays = {
            "NORMAL": _attribute(data, attributes, "NORMAL", where, count, (3,), True),
            "TANGENT": _optional_tangents(data, attributes, where, count),
            **{name: _attribute(data, attributes, name, where, count, (2,)) for name in _UV_SET_NAMES},
            "COLOR_0": _attribute(data, attributes, "COLOR_0", where, count, (3, 4)),
            "JOINTS_0": _attribute(data, attributes, "JOINTS_0", where, count, (4,)),
            "WEIGHTS_0": _attribute(data, attributes, "WEIGHTS_0", where, count, (4,)),
        }
        extra = [_attribute(data, attributes, name, where, count, (4,)) for name in ("JOINTS_1", "WEIGHTS_1")]
        if all(a is not None for a in extra + [arrays["JOINTS_0"], arrays["WEIGHTS_0"]]):  # 8 influences
            arrays["JOINTS_0"] = np.concatenate([arrays["JOINTS_0"], extra[0]], axis=1)
            arrays["WEIGHTS_0"] = np.concatenate([arrays["WEIGHTS_0"], extra[1]], axis=1)
        if "indices" in primitive:
            indices = data.accessor(primitive["indices"], f"{where}.indices", as_stored=True)
            if indices.shape[1] != 1 or indices.dtype.kind not in "iu":
                raise gltf_error(data.path, f"{where}.indices", "expected an accessor of unsigned integer scalars")
            indices = indices.reshape(-1)
        else:
            indices = np.arange(count, dtype=np.int64)
    if len(indices) and (indices.min() < 0 or indices.max() >= len(positions)):
        raise gltf_error(data.path, f"{where}.indices", f"index {int(indices.max())} is beyond the {len(positions)} vertices")
    # KHR_mesh_quantization allows integer positions, normals and uvs: placed as floats
    if arrays["TANGENT"] is not None and (arrays["TANGENT"].ndim != 2 or arrays["TANGENT"].shape[1] != 4):
        arrays["TANGENT"] = None  # a Draco TANGENT of another shape: the derivative frame instead
    for name in ("TANGENT",) + _UV_SET_NAMES:  # (accessors are float64 already: no copy of them)
        if arrays.get(name) is not None:
            arrays[name] = arrays[name].astype(np.float64, copy=False)
    # POSITION and NORMAL as stored (float32, or integers): _instance places them in float64.
    arrays["POSITION"] = positions
    arrays["kind"] = PRIMITIVE_OF_MODE.get(mode, "triangles")
    if arrays["kind"] == "points":  # every listed vertex a point (in index order, after morphing: _listed_points)
        arrays["faces"] = None
        arrays["point_order"] = None if "indices" not in primitive else indices
    else:
        arrays["faces"] = segments(mode, indices) if arrays["kind"] == "lines" else triangles(mode, indices)
    return arrays


def gltf_pieces(data: GltfData, nodes: list | None = None) -> list[GltfPiece]:
    """Every primitive instance of the file's scene, in node order, in world space; `nodes`:
    the file's nodes as an animation poses them (animations.py), else the file's own."""
    world, roots = world_matrices(data, nodes)
    nodes = data.items("nodes") if nodes is None else nodes
    data.items("meshes")  # checked to be a list within the limit
    cache: dict[tuple[int, int], dict | None] = {}
    pieces: list[GltfPiece] = []
    vertices = faces = 0
    for node_index in scene_nodes(data, scene_roots(data, roots)):
        node = nodes[node_index]
        if "mesh" not in node:
            continue
        mesh_index = node["mesh"]
        mesh = data.item("meshes", mesh_index, f"nodes[{node_index}].mesh")
        skinned = "skin" in node
        if world[node_index] is None and not skinned:
            continue  # hidden (scaled to zero)
        primitives = mesh.get("primitives", [])
        if not isinstance(primitives, list) or len(primitives) > MAX_GLTF_ITEMS:
            raise gltf_error(data.path, f"meshes[{mesh_index}].primitives", f"expected a list of at most {MAX_GLTF_ITEMS} primitives")
        skin = skin_matrices(data, node["skin"], world, f"nodes[{node_index}].skin") if skinned else None
        weights = morph_weights(data, node, mesh, f"nodes[{node_index}]")
        for primitive_index, primitive in enumerate(primitives):
            where = f"meshes[{mesh_index}].primitives[{primitive_index}]"
            if not isinstance(primitive, dict):
                raise gltf_error(data.path, where, f"expected an object, got {type(primitive).__name__}")
            key = (mesh_index, primitive_index)
            if key not in cache:
                cache[key] = _primitive_arrays(data, primitive, where)
            arrays = cache[key]
            if arrays is None or not len(arrays["POSITION"] if arrays["faces"] is None else arrays["faces"]):
                continue
            vertices += len(arrays["POSITION"])
            faces += 0 if arrays["faces"] is None else len(arrays["faces"])
            if vertices > MAX_VERTICES or faces > MAX_TRIANGLES:
                raise gltf_error(data.path, "scene", f"its instances hold more than {MAX_VERTICES} vertices or triangles (the limit)")
            arrays = _listed_points(apply_morph_targets(data, primitive, arrays, weights, where))
            pieces.append(_instance(data, arrays, primitive, where, world[node_index], skin, key, mesh.get("name") or where))
    return pieces


_PER_VERTEX = ("POSITION", "NORMAL", "TANGENT", "COLOR_0", "JOINTS_0", "WEIGHTS_0") + _UV_SET_NAMES


def _listed_points(arrays: dict) -> dict:
    """An indexed POINTS primitive's vertices in the order its indices list them (each index a point)."""
    order = arrays.get("point_order")
    if order is None:
        return arrays
    return {**arrays, "point_order": None, **{name: arrays[name][order] for name in _PER_VERTEX if arrays.get(name) is not None}}


def _instance(data, arrays, primitive, where, matrix, skin, key, name) -> GltfPiece:
    positions, normals, tangents = arrays["POSITION"], arrays["NORMAL"], arrays["TANGENT"]
    faces = arrays["faces"]
    if skin is not None and arrays["JOINTS_0"] is not None and arrays["WEIGHTS_0"] is not None:
        tangents = None  # not posed: skinned primitives keep the derivative frame
        positions, normals = pose(skin, arrays["JOINTS_0"].astype(np.int64), arrays["WEIGHTS_0"].astype(np.float64),
                                  _float64(positions), _float64(normals), f"{where}.attributes.JOINTS_0", data)
    elif matrix is not None:
        linear = matrix[:3, :3]
        positions = _transformed(positions, linear.T, matrix[:3, 3])
        if normals is not None:
            normals = _transformed(normals, np.linalg.inv(linear))  # the inverse transpose, applied to rows
        if tangents is not None:  # tangents follow the surface (the matrix); a mirror flips w
            tangents = np.concatenate([tangents[:, :3] @ linear.T, tangents[:, 3:] * np.sign(np.linalg.det(linear))], axis=1)
        if np.linalg.det(linear) < 0 and arrays["kind"] == "triangles":
            faces = faces[:, ::-1]  # a mirroring node keeps the outside outside
    uv_sets = {k: np.stack([uvs[:, 0], 1.0 - uvs[:, 1]], axis=1) for k, name in enumerate(_UV_SET_NAMES)
               if (uvs := arrays.get(name)) is not None}
    colors = arrays["COLOR_0"]
    if colors is not None:
        colors = colors.astype(np.float64)
        if colors.shape[1] == 3:
            colors = np.concatenate([colors, np.ones((len(colors), 1))], axis=1)
        colors = np.clip(colors, 0.0, 1.0)
    return GltfPiece(_floats(positions), faces, _floats(normals), uv_sets, colors, primitive, str(name), key, tangents, arrays["kind"])


def _float64(values: np.ndarray | None) -> np.ndarray | None:
    return None if values is None else values.astype(np.float64, copy=False)


def _floats(values: np.ndarray | None) -> np.ndarray | None:
    """Float values as they are (float32 ones are exact as stored, and a Mesh reads them in
    float64); stored integers (KHR_mesh_quantization) as float64."""
    return values if values is None or values.dtype.kind == "f" else values.astype(np.float64)


def _transformed(values: np.ndarray, right: np.ndarray, translation: np.ndarray | None = None) -> np.ndarray:
    """float64(values) @ right + translation, a block of rows at a time into one array:
    no float64 copy of the stored values, nor a temporary of the whole array. Each row's
    product is the one the whole array's product gives (the same operands, one BLAS call a
    block: the same bits, tests/test_large_mesh_arrays.py). The array is float32 while
    every value is exactly a float32 (float32 data placed by a node without a transform:
    most files), else float64: the same values, which a Mesh reads in float64 again
    (scene/geometry/mesh.py), in half the memory."""
    out = np.empty((len(values), right.shape[1]), np.float32)
    for rows in row_blocks(len(values)):
        block = values[rows].astype(np.float64) @ right
        if translation is not None:
            block += translation
        if out.dtype == np.float32:
            narrow = block.astype(np.float32)
            if np.array_equal(narrow, block):
                out[rows] = narrow
                continue
            out = out.astype(np.float64)  # the rows so far, exactly; float64 from here on
        out[rows] = block
    return out


def material_images(data: GltfData, material: dict, warn_name: str):
    """The decoded PIL images of a material's textures, under the attribute names the
    material mapping reads (trimesh's PBRMaterial names): baseColorTexture (the diffuse
    texture for specular-glossiness), metallicRoughnessTexture, emissiveTexture,
    normalTexture, occlusionTexture. An image that cannot be read is None."""
    pbr = material.get("pbrMetallicRoughness", {}) if isinstance(material.get("pbrMetallicRoughness", {}), dict) else {}
    extensions = material.get("extensions", {}) if isinstance(material.get("extensions", {}), dict) else {}
    gloss = extensions.get(_SPECULAR_GLOSSINESS)
    base_info = gloss.get("diffuseTexture") if isinstance(gloss, dict) else pbr.get("baseColorTexture")
    infos = {
        "baseColorTexture": base_info,
        "metallicRoughnessTexture": pbr.get("metallicRoughnessTexture"),
        "emissiveTexture": material.get("emissiveTexture"),
        "normalTexture": material.get("normalTexture"),
        "occlusionTexture": material.get("occlusionTexture"),
    }
    specular = extensions.get("KHR_materials_specular")  # its textures (materials.py)
    if isinstance(specular, dict):
        infos |= {"specularTexture": specular.get("specularTexture"), "specularColorTexture": specular.get("specularColorTexture")}
    return SimpleNamespace(**{name: _image(data, info) for name, info in infos.items()})


def _image(data: GltfData, info: object):
    from PIL import Image

    from ...scene.material import MAX_TEXTURE_SIDE
    from ..textures import MAX_TEXTURE_FILE_BYTES

    if not isinstance(info, dict):
        return None
    try:
        texture = data.item("textures", info.get("index"), "texture index")
        source = texture.get("source")
        extensions = texture.get("extensions") or {}
        webp = extensions.get("EXT_texture_webp") if isinstance(extensions, dict) else None
        if isinstance(webp, dict) and "source" in webp:  # the WebP image wins over its fallback (EXT_texture_webp's README)
            source = webp["source"]
        elif source is None:  # KHR_texture_basisu keeps its own in extensions (read if Pillow can)
            for extension in extensions.values():
                if isinstance(extension, dict) and "source" in extension:
                    source = extension["source"]
        raw = data.image_bytes(source, "texture source", MAX_TEXTURE_FILE_BYTES)
        import io

        image = Image.open(io.BytesIO(raw))  # reads the header only
        if max(image.size) > MAX_TEXTURE_SIDE:  # checked before the pixels are decoded
            return None
        image.load()
        return image
    except MeshError:
        return None  # the material mapping warns that its texture could not be read
    except Exception:  # Pillow raises many kinds for images it cannot decode
        return None
