"""A file's tangents (glTF TANGENT) as the normal map's frame (docs/conventions.md, "Material
maps"): read from glTF, carried by the Mesh, against the float64 reference, and by hand
where they disagree with the derivative frame."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.assets.meshes import load_mesh
from wgpu_shading.render.features import object_features
from wgpu_shading.scene import Camera, DirectionalLight, Material, Scene, SceneObject, Shading, Texture, cube, plane, torus
from wgpu_shading.study import reference as ref

from gltf_builder import quad, write_gltf
from test_maps_vs_reference import normal_map_criterion, scene_with, smooth_normal_map


def with_tangents(mesh, direction, w: float):
    """The mesh with a constant tangent direction (projected per fragment) and handedness w."""
    tangents = np.concatenate([np.tile(np.float32(direction), (mesh.vertex_count, 1)), np.full((mesh.vertex_count, 1), w, np.float32)], axis=1)
    return replace(mesh, tangents=tangents)


@pytest.mark.parametrize("two_sided", [False, True])
def test_vertex_tangents_match_the_reference(renderer, two_sided):
    material = Material(diffuse=(0.8, 0.7, 0.6, 1), specular=(0.5, 0.5, 0.5, 1), shininess=40.0,
                        normal_map=smooth_normal_map(), normal_scale=0.8)
    base = scene_with(material, "phong", two_sided=two_sided)
    meshes = (with_tangents(torus(0.45, 0.2, 32, 16), (0.0, 0.0, 1.0), 1.0),
              with_tangents(cube(0.8), (0.3, 1.0, 0.2), -1.0),
              with_tangents(plane(1.2, 2), (0.0, 1.0, 0.0), 1.0))
    scene = replace(base, objects=tuple(replace(obj, mesh=mesh) for obj, mesh in zip(base.objects, meshes)))
    assert all(object_features(scene, obj).vertex_tangents for obj in scene.objects)
    assert not object_features(base, base.objects[0]).vertex_tangents
    reference = ref.render_reference(scene)
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    normal_map_criterion(gpu, reference, f"vertex tangents, two_sided={two_sided}")
    # the file's frame is not the derivative frame here: the pictures differ
    assert np.abs(renderer.render(base, float32=True) - gpu.color).max() > 0.05


def _tilted_scene(mesh, light_from, texel=(round(0.8 * 255), 128, round(0.9 * 255))):
    """A plane facing the viewer, uv = (x, y): the derivative frame is T = +x, B = +y. The map
    normal is (0.6, 0, 0.8) in the frame; a light from `light_from` (unit, in the plane)."""
    texel = np.array([[texel]], np.uint8)
    material = Material(ambient=(0, 0, 0, 1), diffuse=(1, 1, 1, 1), normal_map=Texture(texel, encoding="linear"))
    light = DirectionalLight(direction=tuple(-np.float64(light_from)), diffuse=(1, 1, 1, 1))
    return Scene(objects=(SceneObject(mesh, material),), lights=(light,), ambient=(0, 0, 0, 1),
                 camera=Camera(eye=(0, 0, 2.0)), size=(32, 32), shading=Shading())


def test_a_tangent_turned_90_degrees_turns_the_mapped_normal_by_hand(renderer):
    """With T = +y (w = 1, so B = N × T = −x) the map's (0.6, 0, 0.8) is N = (0, 0.6, 0.8):
    a light from +y gives 0.6, one from +x gives 0. The derivative frame gives the opposite."""
    texel_normal = np.array([round(0.8 * 255), 128, round(0.9 * 255)]) / 255.0 * 2.0 - 1.0
    expected = texel_normal[0] / np.linalg.norm(texel_normal)
    rotated = with_tangents(plane(1.0), (0.0, 1.0, 0.0), 1.0)
    from_y, from_x = (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)
    assert renderer.render(_tilted_scene(rotated, from_y), float32=True)[16, 16, 0] == pytest.approx(expected, abs=1.5 / 255)
    assert renderer.render(_tilted_scene(rotated, from_x), float32=True)[16, 16, 0] == pytest.approx(0.0, abs=1.5 / 255)
    assert renderer.render(_tilted_scene(plane(1.0), from_x), float32=True)[16, 16, 0] == pytest.approx(expected, abs=1.5 / 255)
    assert renderer.render(_tilted_scene(plane(1.0), from_y), float32=True)[16, 16, 0] == pytest.approx(0.0, abs=1.5 / 255)
    assert ref.render_reference(_tilted_scene(rotated, from_y)).color[16, 16, 0] == pytest.approx(expected, abs=1e-9)
    # w flips B: a map tilted along v, (0, 0.6, 0.8), faces B = N × T · w = ∓x
    along_v = (128, round(0.8 * 255), round(0.9 * 255))
    mirrored = with_tangents(plane(1.0), (0.0, 1.0, 0.0), -1.0)
    for mesh, lit_from in ((rotated, (-1.0, 0.0, 0.0)), (mirrored, (1.0, 0.0, 0.0))):
        for frame in (lambda s: renderer.render(s, float32=True), lambda s: ref.render_reference(s).color):
            assert frame(_tilted_scene(mesh, lit_from, along_v))[16, 16, 0] == pytest.approx(expected, abs=1.5 / 255)
            assert frame(_tilted_scene(mesh, tuple(-c for c in lit_from), along_v))[16, 16, 0] == pytest.approx(0.0, abs=1.5 / 255)


def _tangent_gltf(path, tangents):
    positions, indices = quad(-0.5, -0.5)
    uvs = np.stack([positions[:, 0] + 0.5, 0.5 - positions[:, 1]], axis=1)  # glTF v runs down: v_flipped = y + 0.5
    primitive = dict(positions=positions, indices=indices, normals=np.tile([0.0, 0.0, 1.0], (4, 1)), uvs=uvs, material=0)
    if tangents is not None:
        primitive["tangents"] = np.tile(np.float32(tangents), (4, 1))
    texel = np.array([[[round(0.8 * 255), 128, round(0.9 * 255), 255]]], np.uint8)
    material = {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}, "normalTexture": {"index": 0}}
    return write_gltf(path, [[primitive]], materials=[material], images=[texel])


def test_gltf_tangent_is_read_and_used(renderer, tmp_path):
    with_file_frame = load_mesh(_tangent_gltf(tmp_path / "tangent.gltf", (0.0, 1.0, 0.0, 1.0)))
    without = load_mesh(_tangent_gltf(tmp_path / "plain.gltf", None))
    assert with_file_frame.tangents is not None and without.tangents is None
    np.testing.assert_allclose(with_file_frame.tangents, np.tile([0.0, 1.0, 0.0, 1.0], (4, 1)))
    images = []
    for mesh in (with_file_frame, without):
        scene = _tilted_scene(mesh, (0.0, 1.0, 0.0))
        scene = replace(scene, objects=(replace(scene.objects[0], material=mesh.material),))
        assert object_features(scene, scene.objects[0]).vertex_tangents == (mesh is with_file_frame)
        images.append(renderer.render(scene, float32=True)[16, 16, 0])
    assert images[0] > images[1] + 0.3  # lit from +y only in the file's frame
    # no normal map: the tangents are not kept
    positions, indices = quad(-0.5, -0.5)
    bare = write_gltf(tmp_path / "bare.gltf", [[dict(positions=positions, indices=indices, normals=np.tile([0.0, 0.0, 1.0], (4, 1)),
                                                     tangents=np.tile(np.float32([0, 1, 0, 1]), (4, 1)))]])
    assert load_mesh(bare).tangents is None
