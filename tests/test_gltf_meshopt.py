"""EXT_meshopt_compression: buffer views compressed by meshoptimizer's codecs are decoded.

References: the same arrays written uncompressed (read by the plain path), the original
float normals for the octahedral filter (written here from the extension's specification,
https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Vendor/EXT_meshopt_compression#filters),
and glTF-Transform's BoxMeshopt.glb against the Khronos Box it was made from."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import meshoptimizer
import numpy as np
import pytest
import trimesh

from wgpu_shading import load_mesh
from wgpu_shading.errors import MeshError

SHARED = next((p / "shared" for p in Path(__file__).resolve().parents if (p / "shared" / "corpora").is_dir()), None)


def _octahedral(normals: np.ndarray) -> np.ndarray:
    """Unit normals as the OCTAHEDRAL filter stores them with a 4-byte stride: x, y of the
    octahedral map in int8 (one = 127), z = one, w = 0."""
    n = normals / np.abs(normals).sum(axis=1, keepdims=True)
    x, y = n[:, 0].copy(), n[:, 1].copy()
    below = n[:, 2] < 0
    sign = np.where(n[:, :2] >= 0, 1.0, -1.0)  # the map folds 0 to +1
    x[below], y[below] = (1 - np.abs(n[below, 1])) * sign[below, 0], (1 - np.abs(n[below, 0])) * sign[below, 1]
    out = np.zeros((len(normals), 4), np.int8)
    out[:, 0], out[:, 1], out[:, 2] = np.round(x * 127), np.round(y * 127), 127
    return out


def _rotated_to_least(triangles: np.ndarray) -> np.ndarray:
    """Each triangle's corners rotated (winding kept) to start at its smallest index."""
    shift = np.argmin(triangles, axis=1)
    return np.stack([triangles[np.arange(len(triangles)), (shift + k) % 3] for k in range(3)], axis=1)


def _document(tmp_path: Path, compressed: bool, **change) -> Path:
    sphere = trimesh.creation.icosphere(subdivisions=2)
    positions = np.asarray(sphere.vertices, np.float32)
    normals = np.asarray(sphere.vertex_normals, np.float64)
    indices = np.asarray(sphere.faces, np.uint32).reshape(-1)
    blob, fallback_offset, views = bytearray(), 0, []
    streams = [
        (positions, 12, "ATTRIBUTES", "NONE", {"componentType": 5126, "type": "VEC3",
                                               "min": positions.min(0).tolist(), "max": positions.max(0).tolist()}),
        (_octahedral(normals) if compressed else normals.astype(np.float32), 4 if compressed else 12, "ATTRIBUTES", "OCTAHEDRAL",
         {"componentType": 5120, "type": "VEC3", "normalized": True} if compressed else {"componentType": 5126, "type": "VEC3"}),
        (indices, 4, "TRIANGLES", "NONE", {"componentType": 5125, "type": "SCALAR"}),
    ]
    accessors = []
    for array, stride, mode, name, accessor in streams:
        raw = np.ascontiguousarray(array)
        count = len(raw)
        if compressed:
            data = (meshoptimizer.encode_vertex_buffer(raw.view(np.dtype((np.void, stride))).reshape(-1), count, stride) if mode == "ATTRIBUTES"
                    else meshoptimizer.encode_index_buffer(raw, len(raw), 4))
            extension = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "byteStride": stride, "mode": mode, "count": count}
            if name != "NONE":
                extension["filter"] = name
            views.append({"buffer": 1, "byteOffset": fallback_offset, "byteLength": count * stride,
                          "extensions": {"EXT_meshopt_compression": extension | change.get(mode, {})}}
                         | ({"byteStride": stride} if mode == "ATTRIBUTES" else {}))
            fallback_offset += count * stride
        else:
            data = raw.tobytes()
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob.extend(bytes(data))
        blob.extend(b"\0" * (-len(blob) % 4))
        accessors.append({"bufferView": len(views) - 1, "count": count} | accessor)
    buffers = [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]
    extra = {}
    if compressed:
        buffers.append({"byteLength": fallback_offset, "extensions": {"EXT_meshopt_compression": {"fallback": True}}})
        extra = {"extensionsUsed": ["EXT_meshopt_compression", "KHR_mesh_quantization"],
                 "extensionsRequired": ["EXT_meshopt_compression", "KHR_mesh_quantization"]}
    document = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
                "buffers": buffers, "bufferViews": views, "accessors": accessors} | extra
    path = tmp_path / ("meshopt.gltf" if compressed else "plain.gltf")
    path.write_text(json.dumps(document))
    return path


def test_compressed_views_decode_to_the_arrays_written_uncompressed(tmp_path):
    compressed, plain = load_mesh(_document(tmp_path, True)), load_mesh(_document(tmp_path, False))
    assert np.array_equal(compressed.positions, plain.positions)
    # the index codec may start a triangle at another corner (same winding)
    assert np.array_equal(_rotated_to_least(compressed.indices), _rotated_to_least(plain.indices))
    # int8 octahedral normals: within about one step of 1/127 of the map per component
    angle = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", compressed.normals, plain.normals), -1, 1)))
    assert angle.max() < 1.5, angle.max()


@pytest.mark.parametrize("change, message", [
    ({"TRIANGLES": {"count": 10}}, "not whole triangles"),
    ({"TRIANGLES": {"byteStride": 3}}, "byteStride of 2 or 4"),
    ({"ATTRIBUTES": {"mode": "POINTS"}}, "'POINTS': expected one of ATTRIBUTES, TRIANGLES, INDICES"),
    ({"ATTRIBUTES": {"filter": "QUATERNION"}}, "the QUATERNION filter needs 8"),
    ({"ATTRIBUTES": {"byteLength": 5}}, "cannot be decoded"),
    ({"ATTRIBUTES": {"byteOffset": 1 << 20}}, "lie beyond buffer 0"),
    ({"ATTRIBUTES": {"count": 7}}, "the bufferView declares"),
])
def test_a_bad_compressed_view_is_one_line_naming_the_field(tmp_path, change, message):
    with pytest.raises(MeshError, match=r"bufferViews\[\d\]\.extensions\.EXT_meshopt_compression.*" + message.replace("(", r"\(")):
        load_mesh(_document(tmp_path, True, **change))


@pytest.mark.skipif(SHARED is None, reason="../shared/corpora is not beside the project")
def test_glTF_Transforms_meshopt_box_is_the_khronos_box():
    box = load_mesh(SHARED / "corpora" / "khronos" / "Box.gltf")
    compressed = load_mesh(SHARED / "corpora" / "realworld2" / "gltf" / "BoxMeshopt.glb")
    # The same 12 triangles: corners (KHR_mesh_quantization's 14-bit positions under a node
    # scale) and normals (int8) as the float file has them, within the quantization.
    def corners(mesh):
        points = mesh.world_positions()[mesh.indices.reshape(-1)]
        normals = mesh.normals[mesh.indices.reshape(-1)]
        rows = np.hstack([np.round(points, 3), np.round(normals, 2)])
        return rows[np.lexsort(rows.T[::-1])]

    assert compressed.indices.shape == box.indices.shape == (12, 3)
    assert np.allclose(corners(compressed), corners(box), atol=2e-3)
