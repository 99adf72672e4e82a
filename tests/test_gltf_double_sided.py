"""glTF doubleSided (§3.9.6): false culls back faces, true lights both sides with the
flipped normal; --two-sided still draws and lights every back face."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from gltf_builder import quad, write_gltf
from wgpu_shading import load_mesh
from wgpu_shading.cli.main import main
from wgpu_shading import SceneError
from wgpu_shading.scene import Material


def _render(path, tmp_path, *flags) -> np.ndarray:
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-o", str(out), "--size", "64", "--camera-position", "0,0,6", "--camera-focal-point", "0,0,0", *flags]) == 0
    return np.asarray(Image.open(out), dtype=int)


def _facing_away(tmp_path, double_sided: bool):
    # Left: a quad facing the camera (+Z); right: the same quad wound the other way (its
    # back towards the camera). White, no specular (KHR_materials_specular factor 0).
    positions, indices = quad(-1.5, -0.5)
    away_positions, _ = quad(0.5, -0.5)
    material = {"pbrMetallicRoughness": {"metallicFactor": 0.0}, "doubleSided": double_sided,
                "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    return write_gltf(tmp_path / f"sides_{double_sided}.gltf", [[
        {"positions": positions, "indices": indices, "normals": normals, "material": 0},
        {"positions": away_positions, "indices": indices[:, ::-1], "normals": -normals, "material": 0},
    ]], materials=[material])


def test_single_sided_back_faces_are_culled_and_two_sided_forces_them(tmp_path):
    path = _facing_away(tmp_path, double_sided=False)
    assert load_mesh(path).parts[0].material.double_sided is False
    image = _render(path, tmp_path, "--no-background")
    front, back = image[32, 16], image[32, 48]
    assert front[3] == 255 and back[3] == 0  # the back of a single-sided quad is not drawn
    forced = _render(path, tmp_path, "--no-background", "--two-sided")
    assert forced[32, 48, 3] == 255 and abs(forced[32, 48, :3] - forced[32, 16, :3]).max() <= 2


def test_double_sided_back_faces_are_lit_with_the_flipped_normal(tmp_path):
    image = _render(_facing_away(tmp_path, double_sided=True), tmp_path, "--no-background")
    front, back = image[32, 16], image[32, 48]
    assert back[3] == 255
    # The back face's normal points away from the camera (−Z); flipped it faces the
    # lights as the front quad does: the same colour (within the difference in position).
    assert abs(back[:3] - front[:3]).max() <= 6 and back[:3].sum() > 150


def test_a_blended_single_sided_box_covers_half_not_three_quarters(tmp_path):
    # A BLEND cube of alpha 0.5 over a transparent background: only the front layer is
    # drawn (coverage 0.5 = 128/255), not front and back (1 − 0.5² = 0.75).
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float32)
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], np.uint32)
    path = write_gltf(tmp_path / "blend.gltf", [[{"positions": corners, "indices": faces, "material": 0}]],
                      materials=[{"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5]}}])
    mesh = load_mesh(path)
    p = mesh.world_positions()[mesh.indices]
    outward = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p.mean(axis=1))
    assert (outward > 0).all()  # the cube is wound outward, as glTF requires
    image = _render(path, tmp_path, "--no-background")
    assert abs(image[32, 32, 3] - 128) <= 1


def test_double_sided_must_be_a_bool_or_none():
    assert Material(double_sided=True).double_sided is True and Material().double_sided is None
    with pytest.raises(SceneError, match="double_sided"):
        Material(double_sided="yes")


def test_ids_and_normals_outputs_cull_the_same_back_faces(tmp_path, renderer):
    # The dataset's id/normal images must cover what the colour image covers.
    from dataclasses import replace

    from wgpu_shading.assets.mesh_scene import mesh_scene

    scene = mesh_scene(str(_facing_away(tmp_path, double_sided=False)), (64, 64))
    camera = replace(scene.camera, eye=(0.0, 0.0, 6.0), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
    frame = renderer.render_frame(replace(scene, camera=camera), ids=True)
    assert frame.ids[32, 16] == 1 and frame.ids[32, 48] == 0
    forced = renderer.render_frame(replace(scene, camera=camera, shading=replace(scene.shading, two_sided=True)), ids=True)
    assert forced.ids[32, 48] == 2
