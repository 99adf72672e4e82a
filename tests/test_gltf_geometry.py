"""glTF geometry read by our own accessor reader (assets/gltf/document.py, nodes.py,
primitives.py): sparse accessors, strips and fans, skins, hidden nodes, deep node chains,
percent-encoded URIs, special files and limits. Every file is built here; expected values
are computed by hand from the glTF 2.0 specification's definitions."""

from __future__ import annotations

import json
import os
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh
from wgpu_shading.cli.main import main

from gltf_builder import FLOAT as _FLOAT, UINT as _UINT, USHORT as _USHORT, Doc

SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)


def _same_points(mesh, expected, absolute: bool = True) -> bool:
    """The mesh's distinct vertex positions (in the file's space) are exactly `expected`'s."""
    found = np.unique(np.round(mesh.world_positions(), 5), axis=0)
    return found.shape == np.unique(np.asarray(expected, float), axis=0).shape and np.allclose(found, np.unique(np.asarray(expected, float), axis=0))


def _normals_of(mesh) -> np.ndarray:
    p = mesh.positions[mesh.indices.reshape(-1, 3)]
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return cross / np.linalg.norm(cross, axis=1, keepdims=True)


def test_sparse_accessor_replaces_the_listed_elements(tmp_path):
    # Khronos' SimpleSparseAccessor: a flat strip whose sparse values raise some vertices
    # (it rendered flat before: trimesh ignored `sparse`).
    doc = Doc()
    base = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], np.float32)
    position = doc.accessor(base)
    doc.accessors[position]["sparse"] = {
        "count": 2,
        "indices": {"bufferView": doc.view(np.array([1, 4], np.uint16)), "componentType": _USHORT},
        "values": {"bufferView": doc.view(np.array([[1, 0, 3], [1, 1, 3]], np.float32))},
    }
    indices = doc.accessor(np.array([0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4], np.uint16), _USHORT)
    mesh = load_mesh(doc.write(tmp_path / "sparse.gltf", [[{"attributes": {"POSITION": position}, "indices": indices}]], [{"mesh": 0}]))
    expected = base.copy()
    expected[[1, 4]] = [[1, 0, 3], [1, 1, 3]]
    assert _same_points(mesh, expected)


def test_sparse_accessor_without_buffer_view_starts_from_zeros(tmp_path):
    doc = Doc()
    doc.accessors.append({"componentType": _FLOAT, "count": 3, "type": "VEC3", "sparse": {
        "count": 2,
        "indices": {"bufferView": doc.view(np.array([1, 2], np.uint32)), "componentType": _UINT},
        "values": {"bufferView": doc.view(np.array([[1, 0, 0], [0, 1, 0]], np.float32))},
    }})
    mesh = load_mesh(doc.write(tmp_path / "zeros.gltf", [[{"attributes": {"POSITION": 0}}]], [{"mesh": 0}]))
    assert _same_points(mesh, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])


@pytest.mark.parametrize("mode, indices", [(6, [0, 1, 2, 3]), (5, [0, 1, 3, 2])])
def test_triangle_fans_and_strips_are_drawn_with_their_winding(tmp_path, mode, indices):
    # glTF §3.7.2.1: fan {v(i+1), v(i+2), v0}; strip {v(i), v(i+1+i%2), v(i+2-i%2)}: both
    # cover the square counter-clockwise (normal +Z). Fans were dropped ("no triangles").
    doc = Doc()
    primitive = {"attributes": {"POSITION": doc.accessor(SQUARE)}, "indices": doc.accessor(np.array(indices, np.uint16), _USHORT), "mode": mode}
    mesh = load_mesh(doc.write(tmp_path / "fan.gltf", [[primitive]], [{"mesh": 0}]))
    assert mesh.triangle_count == 2
    assert np.allclose(_normals_of(mesh), [0, 0, 1])


def test_points_and_lines_are_skipped(tmp_path):
    doc = Doc()
    square = doc.accessor(SQUARE)
    mesh = load_mesh(doc.write(tmp_path / "lines.gltf", [[{"attributes": {"POSITION": square}, "mode": 1},
                                                         {"attributes": {"POSITION": square}, "mode": 6}]], [{"mesh": 0}]))
    assert mesh.triangle_count == 2


def test_skinned_mesh_is_posed_by_its_joints(tmp_path):
    # Joint 1 is translated (0, 2, 0) and has an identity inverse bind matrix: a vertex fully
    # on joint 1 moves up 2, one half on each joint moves up 1, one on joint 0 (at the
    # origin) stays. The mesh node's own translation is ignored for skinned meshes (§3.7.3).
    doc = Doc()
    positions = doc.accessor(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32))
    joints = doc.accessor(np.array([[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]], np.uint16), _USHORT)
    weights = doc.accessor(np.array([[1, 0, 0, 0], [1, 0, 0, 0], [0.5, 0.5, 0, 0]], np.float32))
    inverse = doc.accessor(np.tile(np.eye(4, dtype=np.float32).reshape(1, 16), (2, 1)))
    primitive = {"attributes": {"POSITION": positions, "JOINTS_0": joints, "WEIGHTS_0": weights}}
    nodes = [{"mesh": 0, "skin": 0, "translation": [100, 0, 0]}, {"children": [2]}, {"translation": [0, 2, 0], "_child": True}]
    mesh = load_mesh(doc.write(tmp_path / "skin.gltf", [[primitive]], nodes, skins=[{"joints": [1, 2], "inverseBindMatrices": inverse}]))
    assert _same_points(mesh, [[0, 0, 0], [1, 2, 0], [0, 2, 0]], absolute=True)


def test_nodes_scaled_to_zero_are_hidden_with_their_children(tmp_path):
    # How exporters hide objects; it was `LinAlgError: Singular matrix`, exit 3.
    doc = Doc()
    square = doc.accessor(SQUARE)
    nodes = [{"mesh": 0}, {"mesh": 0, "scale": [0, 0, 0], "children": [2]}, {"mesh": 0, "translation": [5, 0, 0], "_child": True}]
    mesh = load_mesh(doc.write(tmp_path / "hidden.gltf", [[{"attributes": {"POSITION": square}, "indices": doc.accessor(np.array([0, 1, 2, 0, 2, 3]), _USHORT)}]], nodes))
    assert mesh.triangle_count == 2 and mesh.world_positions()[:, 0].max() == 1.0


def test_a_100000_deep_node_chain_loads_in_linear_time(tmp_path):
    doc = Doc()
    square = doc.accessor(SQUARE)
    count = 100_000
    nodes = [{"children": [k + 1], "translation": [1e-5, 0, 0]} | ({"_child": True} if k else {}) for k in range(count - 1)]
    nodes.append({"mesh": 0, "_child": True})
    path = doc.write(tmp_path / "chain.gltf", [[{"attributes": {"POSITION": square}, "indices": doc.accessor(np.array([0, 1, 2, 0, 2, 3]), _USHORT)}]], nodes)
    start = time.perf_counter()
    mesh = load_mesh(path)
    assert time.perf_counter() - start < 15.0  # quadratic before: over a minute
    assert np.isclose(mesh.world_positions()[:, 0].min(), (count - 1) * 1e-5)


def _cli(capsys, path) -> str:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(["render", str(path), "-o", str(Path(path).with_suffix(".png")), "--size", "16"])
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and Path(path).name in lines[0], err
    return lines[0]


def test_a_huge_count_without_data_is_refused_before_allocating(tmp_path, capsys):
    # 831 bytes claiming 2^26 vertices took 30 s and 6.2 GB.
    path = tmp_path / "huge.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
                                "nodes": [{"mesh": 0}], "accessors": [{"componentType": _FLOAT, "count": 1 << 26, "type": "VEC3"}]}))
    start = time.perf_counter()
    assert "count" in _cli(capsys, path)
    assert time.perf_counter() - start < 5.0


def _square_doc(tmp_path, uri=None, **mutations) -> Path:
    doc = Doc()
    square = doc.accessor(SQUARE)
    indices = doc.accessor(np.array([0, 1, 2, 0, 2, 3]), _USHORT)
    return doc.write(tmp_path / "h.gltf", [[{"attributes": {"POSITION": square}, "indices": indices}]], [{"mesh": 0}], uri=uri)


_HOSTILE = [
    (lambda d: d["nodes"][0].update(translation=["x", 0, 0]), "nodes[0].translation"),
    (lambda d: d["nodes"][0].update(rotation=[0, 0, 0, 0]), "nodes[0].rotation"),
    (lambda d: d["nodes"][0].update(matrix=[1e300] * 16), "nodes[0].matrix"),
    (lambda d: d["nodes"][0].update(children=[0]), "nodes[0].children"),
    (lambda d: d["nodes"].append({"children": [0]}) or d["nodes"].append({"children": [0]}), "children"),
    (lambda d: d["nodes"].extend([{"children": [2]}, {"children": [1]}]), "cycle"),
    (lambda d: d["nodes"][0].update(mesh=7), "nodes[0].mesh"),
    (lambda d: d["accessors"][0].update(componentType=1), "accessors[0].componentType"),
    (lambda d: d["accessors"][0].update(count=1000), "accessors[0]"),
    (lambda d: d["accessors"][0].update(type=[]), "accessors[0].type"),
    (lambda d: d["bufferViews"][0].update(byteOffset=-1), "bufferViews[0].byteOffset"),
    (lambda d: d["bufferViews"][0].update(byteLength=1 << 40), "bufferViews[0].byteLength"),
    (lambda d: d["buffers"][0].update(byteLength=10**6), "buffers[0].byteLength"),
    (lambda d: d["accessors"][0].update(sparse={"count": 0}), "sparse"),
    (lambda d: d["accessors"][0].update(sparse={"count": 1, "indices": {"bufferView": 1, "componentType": 5125}, "values": {"bufferView": 0}}), "sparse.indices"),
    (lambda d: d["meshes"][0]["primitives"][0].update(mode="x"), "mode"),
    (lambda d: d["meshes"][0]["primitives"][0].update(indices=0), "indices"),
    (lambda d: d.update(extensionsRequired="KHR_materials_unlit"), "extensionsRequired"),
    (lambda d: d.update(extensionsRequired=["EXT_mystery"]), "EXT_mystery"),
    (lambda d: d["nodes"][0].update(skin=0) or d.update(skins=[{"joints": "a"}]), "skins[0].joints"),
    (lambda d: d.update(scene=3), "scene"),
    (lambda d: d["buffers"][0].update(uri="http://example.com/x.bin"), "buffers[0].uri"),
]


@pytest.mark.parametrize("mutate, words", _HOSTILE, ids=[words for _, words in _HOSTILE])
def test_hostile_gltf_fields_are_one_line_errors(tmp_path, capsys, mutate, words):
    path = _square_doc(tmp_path)
    document = json.loads(path.read_text())
    mutate(document)
    path.write_text(json.dumps(document))
    assert words in _cli(capsys, path)


def test_percent_encoded_buffer_uris_are_decoded(tmp_path):
    doc = Doc()
    square = doc.accessor(SQUARE)
    indices = doc.accessor(np.array([0, 1, 2, 0, 2, 3]), _USHORT)
    (tmp_path / "my file.bin").write_bytes(bytes(doc.blob))
    mesh = load_mesh(doc.write(tmp_path / "p.gltf", [[{"attributes": {"POSITION": square}, "indices": indices}]], [{"mesh": 0}], uri="my%20file.bin"))
    assert mesh.triangle_count == 2


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_fifo_named_as_a_buffer_is_refused_without_reading(tmp_path, capsys):
    os.mkfifo(tmp_path / "pipe.bin")
    path = _square_doc(tmp_path, uri="pipe.bin")
    assert "not a regular file" in _cli(capsys, path)


def test_extensions_we_implement_may_be_required(tmp_path):
    path = _square_doc(tmp_path)
    document = json.loads(path.read_text())
    document["extensionsRequired"] = ["KHR_materials_pbrSpecularGlossiness", "KHR_materials_emissive_strength", "KHR_lights_punctual"]
    path.write_text(json.dumps(document))
    assert load_mesh(path).triangle_count == 2
    document["extensionsRequired"].append("KHR_materials_volume")
    path.write_text(json.dumps(document))
    with pytest.raises(MeshError, match="KHR_materials_volume"):
        load_mesh(path)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_fifo_named_as_a_gltf_image_is_a_warning_without_reading(tmp_path):
    from gltf_builder import quad, write_gltf

    os.mkfifo(tmp_path / "pipe.png")
    positions, indices = quad(0, 0)
    path = write_gltf(tmp_path / "f.gltf", [[{"positions": positions, "indices": indices, "uvs": positions[:, :2], "material": 0}]],
                      materials=[{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], images=[np.zeros((1, 1, 3))])
    document = json.loads(path.read_text())
    document["images"] = [{"uri": "pipe.png"}]
    path.write_text(json.dumps(document))
    with pytest.warns(UserWarning, match="could not be read"):
        mesh = load_mesh(path)
    assert mesh.parts[0].material.texture is None


def test_quantized_integer_positions_are_scaled_by_their_node(tmp_path):
    # KHR_mesh_quantization: unsigned short positions, not normalized, dequantized by the node's scale.
    doc = Doc()
    positions = doc.accessor(np.array([[0, 0, 0, 0], [4, 0, 0, 0], [4, 4, 0, 0], [0, 4, 0, 0]], np.uint16)[:, :3], _USHORT)
    indices = doc.accessor(np.array([0, 1, 2, 0, 2, 3]), _USHORT)
    path = doc.write(tmp_path / "q.gltf", [[{"attributes": {"POSITION": positions}, "indices": indices}]], [{"mesh": 0, "scale": [0.25, 0.25, 0.25]}],
                     extensionsUsed=["KHR_mesh_quantization"], extensionsRequired=["KHR_mesh_quantization"])
    assert _same_points(load_mesh(path), SQUARE)


def _skinned_doc(tmp_path, *, joints_values=None, inverse=None, weights=None, target=None) -> Path:
    """test_skinned_mesh_is_posed_by_its_joints' file, with a morph target, parts replaced."""
    doc = Doc()
    positions = doc.accessor(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32))
    joints = doc.accessor(np.array(joints_values if joints_values is not None else [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]], np.uint16), _USHORT)
    weights = doc.accessor(np.array(weights if weights is not None else [[1, 0, 0, 0], [1, 0, 0, 0], [0.5, 0.5, 0, 0]], np.float32))
    inverse = doc.accessor(inverse if inverse is not None else np.tile(np.eye(4, dtype=np.float32).reshape(1, 16), (2, 1)))
    moved = doc.accessor(target if target is not None else np.full((3, 3), 0.5, np.float32))
    primitive = {"attributes": {"POSITION": positions, "JOINTS_0": joints, "WEIGHTS_0": weights}, "targets": [{"POSITION": moved}]}
    nodes = [{"mesh": 0, "skin": 0, "weights": [1.0]}, {"children": [2]}, {"translation": [0, 2, 0], "_child": True}]
    return doc.write(tmp_path / "skin.gltf", [[primitive]], nodes, skins=[{"joints": [1, 2], "inverseBindMatrices": inverse}])


@pytest.mark.parametrize("parts, mutate, words", [
    ({}, lambda d: d["skins"][0].update(joints=[1, 99]), ["skins[0].joints", "99 is not an index into nodes"]),
    ({}, lambda d: d["skins"][0].update(joints=[]), ["skins[0].joints"]),
    ({}, lambda d: d["nodes"][0].update(skin=4), ["nodes[0].skin", "4 is not an index into skins"]),
    ({"joints_values": [[0, 0, 0, 0], [7, 0, 0, 0], [0, 1, 0, 0]]}, None, ["JOINTS_0", "a JOINTS value 7 is beyond the skin's 2 joints"]),
    ({"inverse": np.eye(4, dtype=np.float32).reshape(1, 16)}, None, ["skins[0].inverseBindMatrices", "expected 2 MAT4, got 1"]),
    ({"inverse": np.full((2, 16), np.nan, np.float32)}, None, ["skins[0].inverseBindMatrices", "not finite"]),
    ({"weights": np.full((3, 4), np.nan, np.float32)}, None, ["WEIGHTS_0", "finite"]),
    ({"target": np.full((2, 3), 0.5, np.float32)}, None, ["targets[0].POSITION", "expected 3 finite VEC3 displacements, got 2"]),
    ({"target": np.full((3, 3), np.inf, np.float32)}, None, ["targets[0].POSITION"]),
    ({}, lambda d: d["nodes"][0].update(weights=[float("nan")]), ["nodes[0].weights"]),
    ({}, lambda d: d["nodes"][0].update(weights=[1e30]), ["nodes[0].weights", "within ±1e6"]),
    ({}, lambda d: d["meshes"][0]["primitives"][0].update(targets=[{"POSITION": 99}]), ["targets[0].POSITION", "99 is not an index into accessors"]),
    ({}, lambda d: d["meshes"][0]["primitives"][0].update(targets={"POSITION": 0}), ["targets", "expected a list of objects"]),
])
def test_hostile_skins_and_morph_targets_are_one_line_errors(tmp_path, capsys, parts, mutate, words):
    path = _skinned_doc(tmp_path, **parts)
    if mutate is not None:
        document = json.loads(path.read_text())
        mutate(document)
        path.write_text(json.dumps(document))
    line = _cli(capsys, path)
    assert "skin.gltf" in line and all(word in line for word in words), line


def test_a_read_lets_go_of_the_files_binary_data_and_still_gives_its_lights_and_cameras():
    """read_gltf keeps the parsed document for the MeshFile's lights and cameras, and lets
    go of the binary data and the float64 accessors once the pieces are made (a 10M-triangle
    GLB was 5x its arrays while the Mesh was built); an accessor read after that is an error."""
    from wgpu_shading.assets.gltf.document import GltfData
    from wgpu_shading.assets.gltf.reader import posed_gltf, read_gltf

    path = Path(__file__).parent / "data" / "real" / "cubevc.glb"
    whole = posed_gltf(GltfData(path))
    read = read_gltf(path)
    for ours, kept in zip(read.pieces, whole.pieces):
        np.testing.assert_array_equal(ours.positions, kept.positions)
        np.testing.assert_array_equal(ours.faces, kept.faces)
    assert read.lights() == whole.lights()
    data = GltfData(path)
    posed_gltf(data)
    data.forget_binary_data()
    with pytest.raises(RuntimeError, match="let go"):
        data.accessor(0, "accessors[0]")
