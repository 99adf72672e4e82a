"""Morph targets (glTF 2.0 §3.7.2.2, issue 27): default weights from the mesh and the node
(the node's win), positions, normals and tangents moved, sparse targets, weights animated;
on Khronos samples against positions worked out by hand from their keyframes, and the
morphed cube drawn on the GPU against the float64 reference."""

from __future__ import annotations

import base64
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from gltf_builder import write_gltf
from wgpu_shading import load_mesh

KHRONOS = Path(__file__).parent / "data" / "real" / "khronos"
pytestmark = pytest.mark.filterwarnings("ignore:.*texture could not be read")


def _third_vertex(path, **options):
    """SimpleMorph is one triangle (0,0,0) (1,0,0) (0.5,0.5,0); target 0 moves the third
    vertex by (−1, 1, 0), target 1 by (1, 1, 0) (the glTF tutorial's listing)."""
    positions = load_mesh(path, **options).world_positions()
    return positions[np.argmax(positions[:, 1])]


def _simple_morph(tmp_path, change):
    document = json.loads((KHRONOS / "SimpleMorph.gltf").read_text())
    change(document)
    path = tmp_path / "SimpleMorph.gltf"
    path.write_text(json.dumps(document))
    return path


def test_the_mesh_default_weights_are_applied():
    # mesh.weights [0.5, 0.5]: (0.5, 0.5) + 0.5·(−1, 1) + 0.5·(1, 1) = (0.5, 1.5)
    np.testing.assert_allclose(_third_vertex(KHRONOS / "SimpleMorph.gltf"), [0.5, 1.5, 0.0], atol=1e-7)


def test_the_node_weights_override_the_mesh_weights(tmp_path):
    path = _simple_morph(tmp_path, lambda d: d["nodes"][0].update(weights=[1.0, 0.0]))
    np.testing.assert_allclose(_third_vertex(path), [-0.5, 1.5, 0.0], atol=1e-7)
    path = _simple_morph(tmp_path, lambda d: d["meshes"][0].pop("weights"))  # none at all: the base shape
    np.testing.assert_allclose(_third_vertex(path), [0.5, 0.5, 0.0], atol=1e-7)


@pytest.mark.parametrize("time, weights", [(-1.0, (0, 0)), (0.0, (0, 0)), (0.5, (0, 0.5)), (1.0, (0, 1)),
                                           (2.5, (1, 0.5)), (3.5, (0.5, 0)), (9.0, (0, 0))])
def test_animated_weights_replace_the_defaults(time, weights):
    # the file's animation: weights (0,0) (0,1) (1,1) (1,0) (0,0) at 0, 1, 2, 3, 4 s, linear
    expected = np.array([0.5, 0.5, 0.0]) + weights[0] * np.array([-1, 1, 0]) + weights[1] * np.array([1, 1, 0])
    np.testing.assert_allclose(_third_vertex(KHRONOS / "SimpleMorph.gltf", animation_time=time), expected, atol=1e-6)


def test_each_primitive_of_a_mesh_is_morphed_by_the_mesh_weights():
    # MorphPrimitivesTest: a flat grid (y = 0) of two primitives, each with one target raising
    # its middle by 0.2; mesh.weights [0.5] raise both by 0.1
    mesh = load_mesh(KHRONOS / "MorphPrimitivesTest.gltf")
    for part in mesh.parts:
        faces = mesh.indices.reshape(-1, 3)[part.first : part.first + part.count]
        heights = mesh.world_positions()[np.unique(faces)][:, 1]
        assert heights.min() == pytest.approx(0.0, abs=1e-7) and heights.max() == pytest.approx(0.1, abs=1e-6), part.name


def test_a_sparse_target_moves_only_the_vertices_it_lists(tmp_path):
    # a square, and one target written as a sparse accessor (no bufferView): vertex 2 by +1 in z
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    path = write_gltf(tmp_path / "sparse.gltf", [[{"positions": positions, "indices": [[0, 1, 2], [0, 2, 3]]}]])
    document = json.loads(path.read_text())
    payload = np.array([2], np.uint32).tobytes() + np.array([0, 0, 1], np.float32).tobytes()
    document["buffers"].append({"byteLength": len(payload),
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(payload).decode()})
    document["bufferViews"] += [{"buffer": 1, "byteOffset": 0, "byteLength": 4}, {"buffer": 1, "byteOffset": 4, "byteLength": 12}]
    views = len(document["bufferViews"])
    document["accessors"].append({"componentType": 5126, "count": 4, "type": "VEC3", "sparse": {
        "count": 1, "indices": {"bufferView": views - 2, "componentType": 5125}, "values": {"bufferView": views - 1}}})
    document["meshes"][0]["primitives"][0]["targets"] = [{"POSITION": len(document["accessors"]) - 1}]
    document["meshes"][0]["weights"] = [0.25]
    path.write_text(json.dumps(document))
    moved = load_mesh(path).world_positions()
    by_xy = {tuple(p[:2].round(6)): p[2] for p in moved}
    assert by_xy == {(0, 0): 0, (1, 0): 0, (1, 1): pytest.approx(0.25), (0, 1): 0}


def _cube(weights):
    """AnimatedMorphCube with its node's weights set: target 0 "thin" flattens the cube,
    target 1 "angle" makes a ramp; each target also moves the normals and tangents."""
    document = json.loads((KHRONOS / "AnimatedMorphCube.gltf").read_text())
    document["nodes"][0]["weights"] = list(weights)
    document["buffers"][0]["uri"] = str(KHRONOS / "AnimatedMorphCube.bin")
    return document


@pytest.mark.parametrize("weights", [(0, 0), (1, 0), (0, 1)])
def test_morphed_normals_and_tangents_follow_the_morphed_faces(tmp_path, weights):
    path = tmp_path / "cube.gltf"
    path.write_text(json.dumps(_cube(weights)))
    mesh = load_mesh(path)
    positions, faces = mesh.world_positions(), mesh.indices.reshape(-1, 3)
    face = np.cross(positions[faces[:, 1]] - positions[faces[:, 0]], positions[faces[:, 2]] - positions[faces[:, 0]])
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    # every corner's morphed (file) normal is its flat face's normal
    np.testing.assert_allclose(np.einsum("fk,fck->fc", face, mesh.normals[faces]), 1.0, atol=1e-5)
    if mesh.tangents is not None:  # tangents lie in their faces
        np.testing.assert_allclose(np.einsum("fk,fck->fc", face, mesh.tangents[faces][..., :3]), 0.0, atol=1e-4)
    # the cube is 0.02 wide, scaled by 100 in its node; "thin" moves its top face down by
    # 0.01893253 (the target accessor's declared max): 2 − 1.893253 thick
    thickness = np.ptp(positions, axis=0).min()
    assert thickness == pytest.approx({(0, 0): 2.0, (1, 0): 2.0 - 1.893253, (0, 1): 2.0}[weights], abs=1e-4)


def test_morph_weights_that_do_not_match_the_targets_are_said_and_padded(tmp_path):
    path = _simple_morph(tmp_path, lambda d: d["meshes"][0].update(weights=[1.0]))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        vertex = _third_vertex(path)
    assert [str(w.message) for w in caught] == [
        "SimpleMorph.gltf: meshes[0].primitives[0]: 1 morph weights for 2 targets; the missing ones are 0"]
    np.testing.assert_allclose(vertex, [-0.5, 1.5, 0.0], atol=1e-7)


@pytest.mark.parametrize("frequency", ["gouraud", "phong"])
def test_a_morphed_cube_on_the_gpu_matches_the_float64_reference(renderer, tmp_path, frequency):
    from support import EDGE_BAND, compare

    from dataclasses import replace

    from wgpu_shading.assets.mesh_scene import mesh_scene
    from wgpu_shading.study import reference as ref

    path = tmp_path / "cube.gltf"
    path.write_text(json.dumps(_cube((0.3, 0.6))))
    scene = mesh_scene(str(path), (64, 64))
    scene = replace(scene, shading=replace(scene.shading, frequency=frequency))
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    compare(gpu, ref.render_reference(scene), EDGE_BAND, f"morphed cube / {frequency}")
