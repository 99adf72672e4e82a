"""docs/real-world-files.md on files: one draw per (part, material), glTF scene graphs, vertex colors,
alpha modes, unlit, samplers, opaque output. Small generated files, and a few real ones
committed under tests/data/real (see its LICENCES.md).

Every scene looks straight at the z = 0 plane under one head-on white directional light,
without ambient light: a lit pixel is exactly the diffuse color (× texel, × vertex color).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gltf_builder import quad, write_gltf
from wgpu_shading import Camera, Scene, SceneObject, load_mesh
from wgpu_shading.scene import DirectionalLight, Material, Shading

REAL = Path(__file__).parent / "data" / "real"
WHITE_LIGHT = DirectionalLight(direction=(0.0, 0.0, -1.0), ambient=(0, 0, 0, 1), diffuse=(1, 1, 1, 1), specular=(0, 0, 0, 1))


def head_on(objects, frequency="phong", size=(64, 32), background=(0.0, 0.0, 0.0, 1.0), half_width=2.0) -> Scene:
    """Camera on +Z looking at the origin; the view is `2·half_width` wide at z = 0."""
    import math

    distance = 10.0
    fov_y = 2 * math.degrees(math.atan(half_width * size[1] / size[0] / distance))
    return Scene(
        objects=tuple(objects), lights=(WHITE_LIGHT,), camera=Camera(eye=(0, 0, distance), fov_y=fov_y, near=1, far=20),
        shading=Shading(frequency=frequency), ambient=(0, 0, 0, 1), size=size, background=background,
    )


def pixel(image, x: float, y: float, half_width=2.0):
    """The pixel at world (x, y) on the z = 0 plane of a head_on view."""
    height, width = image.shape[:2]
    column = int((x / half_width + 1) / 2 * width)
    row = int((1 - (y / (half_width * height / width) + 1) / 2) * height)
    return image[row, column].astype(int)


# --------------------------------------------------------------------------- OBJ parts


def test_obj_usemtl_parts_keep_their_materials_and_relative_indices_resolve_per_object(tmp_path, renderer):
    """Two objects with relative indices (`f -4 -3 -2 -1` after each object's own vertices)
    and a material each. trimesh 5.2 resolves relative indices against the end of the file
    (trimesh issue #2364) and draws the second square twice; both must appear, each in its color."""
    (tmp_path / "two.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\n")
    (tmp_path / "two.obj").write_text(
        "mtllib two.mtl\no left\nusemtl red\nv -1.5 -0.5 0\nv -0.5 -0.5 0\nv -0.5 0.5 0\nv -1.5 0.5 0\nf -4 -3 -2 -1\n"
        "o right\nusemtl green\nv 0.5 -0.5 0\nv 1.5 -0.5 0\nv 1.5 0.5 0\nv 0.5 0.5 0\nf -4 -3 -2 -1\n"
    )
    mesh = load_mesh(tmp_path / "two.obj")
    assert [(p.name, p.count) for p in mesh.parts] == [("red", 2), ("green", 2)]
    for frequency in ("flat", "gouraud", "phong"):
        image = renderer.render(head_on([SceneObject(mesh)], frequency))
        assert tuple(pixel(image, -1.0, 0.0)[:3]) == (255, 0, 0), frequency
        assert tuple(pixel(image, 1.0, 0.0)[:3]) == (0, 255, 0), frequency
        assert tuple(pixel(image, 0.0, 0.0)[:3]) == (0, 0, 0), frequency  # the gap between them


def test_relative_indices_file_from_the_corpus_keeps_both_squares():
    mesh = load_mesh(REAL / "negative_indices_two_objects.obj")
    xs = sorted(set(np.round(mesh.world_positions()[mesh.indices.reshape(-1), 0], 3)))
    assert xs[0] < 2.0 and xs[-1] > 4.0  # the first square (x 0..1) and the second (x 5..6)


def test_cornell_box_keeps_red_and_green_walls():
    """tinyobjloader's Cornell box: white, red, green and light parts (blue is declared, unused)."""
    mesh = load_mesh(REAL / "cornell_box.obj")
    diffuse = {p.name: p.material.diffuse[:3] for p in mesh.parts}
    assert diffuse == {"white": (1, 1, 1), "red": (1, 0, 0), "green": (0, 1, 0), "light": (1, 1, 1)}
    assert {p.name: p.material.ambient[0] for p in mesh.parts}["light"] == 20.0  # Ka 20 kept, not clipped to 1
    assert sum(p.count for p in mesh.parts) == mesh.triangle_count == 36


def test_an_explicit_material_replaces_every_part(tmp_path, renderer):
    (tmp_path / "two.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\n")
    (tmp_path / "two.obj").write_text(
        "mtllib two.mtl\nv -1.5 -0.5 0\nv -0.5 -0.5 0\nv -0.5 0.5 0\nv 0.5 -0.5 0\nv 1.5 -0.5 0\nv 1.5 0.5 0\n"
        "usemtl red\nf 1 2 3\nusemtl green\nf 4 5 6\n"
    )
    blue = Material(diffuse=(0, 0, 1, 1))
    image = renderer.render(head_on([SceneObject(load_mesh(tmp_path / "two.obj"), blue)]))
    assert tuple(pixel(image, -0.7, -0.3)[:3]) == (0, 0, 255) == tuple(pixel(image, 1.3, -0.3)[:3])


def test_mtl_ns_0_gives_no_highlight_and_d_blends(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl dull\nKd 1 1 1\nKs 1 1 1\nNs 0\nnewmtl glass\nKd 1 1 1\nTr 0.25\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl dull\nf 1 2 3\nusemtl glass\nf 1 3 2\n")
    dull, glass = (p.material for p in load_mesh(tmp_path / "m.obj").parts)
    assert dull.specular[:3] == (0, 0, 0) and dull.alpha_mode == "opaque"
    assert glass.diffuse[3] == 0.75 and glass.alpha_mode == "blend"  # Tr 0.25 = d 0.75


def test_missing_map_kd_is_a_warning_naming_the_file(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl t\nKd 1 1 1\nmap_Kd -s 1 1 1 my texture.png\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nusemtl t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n")
    with pytest.warns(UserWarning, match="texture 'my texture.png' not found"):
        mesh = load_mesh(tmp_path / "m.obj")
    assert mesh.parts[0].material.texture is None


def test_map_kd_with_options_and_spaces_is_found(tmp_path):
    import imageio.v3 as iio

    iio.imwrite(tmp_path / "my texture.png", np.full((2, 2, 3), 200, np.uint8))
    (tmp_path / "m.mtl").write_text("newmtl t\nmap_Kd -s 1 1 1 -bm 0.5 my texture.png\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nusemtl t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n")
    texture = load_mesh(tmp_path / "m.obj").parts[0].material.texture
    assert texture is not None and texture.pixels[0, 0, 0] == 200


# --------------------------------------------------------------------------- glTF parts and scene graph


def _checker() -> np.ndarray:
    pixels = np.zeros((2, 2, 4), np.uint8)
    pixels[...] = (0, 0, 255, 255)
    pixels[0, 0] = pixels[1, 1] = (255, 255, 0, 255)
    return pixels


def test_gltf_textured_and_untextured_parts_with_instanced_nodes(tmp_path, renderer):
    """Like CesiumMilkTruck: a textured primitive, an untextured one without TEXCOORD_0, and a
    mesh used by two nodes (the wheels): every instance is drawn with its own material."""
    textured_positions, indices = quad(-1.75, -0.5)
    plain_positions, _ = quad(-0.5, -0.5, 0.5)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    path = write_gltf(
        tmp_path / "truck.gltf",
        meshes=[
            [{"positions": textured_positions, "indices": indices, "normals": normals, "uvs": uvs, "material": 0}],
            [{"positions": plain_positions, "indices": indices, "normals": normals, "material": 1}],
        ],
        materials=[
            {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}},
            {"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0.0}},
        ],
        images=[_checker()],
        samplers=[{"magFilter": 9728, "minFilter": 9728}],
        textures=[{"source": 0, "sampler": 0}],
        nodes=[{"mesh": 0}, {"mesh": 1, "translation": [0.75, 0, 0]}, {"mesh": 1, "translation": [1.75, 0, 0]}],
    )
    mesh = load_mesh(path)
    assert len(mesh.parts) == 3 and mesh.parts[0].material.texture.nearest
    image = renderer.render(head_on([SceneObject(mesh)], size=(128, 64)))
    # Nearest sampling: only the two texel colors, no blend between them. glTF's uv (0, 0) is the
    # image's top-left corner, so the quad's upper-left quarter shows the image's lower-left texel.
    assert tuple(pixel(image, -1.5, 0.25)[:3]) == (0, 0, 255) and tuple(pixel(image, -1.0, 0.25)[:3]) == (255, 255, 0)
    for x in (0.5, 1.5):  # both instances of the red quad, each at its node's translation
        assert tuple(pixel(image, x, -0.25)[:3]) == (255, 0, 0)
    assert tuple(pixel(image, 1.1, -0.25)[:3]) == (0, 0, 0)


def test_gltf_without_normal_is_flat_and_file_normals_win(tmp_path):
    positions = np.float32([[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0.5], [0.5, 0.5, 2]])
    indices = np.uint32([[0, 1, 4], [1, 2, 4]])  # two faces meeting at a shallow angle: 60° would smooth them
    given = np.tile(np.float32([0, 0.6, 0.8]), (5, 1))
    path = write_gltf(tmp_path / "n.gltf", meshes=[[{"positions": positions, "indices": indices}], [{"positions": positions, "indices": indices, "normals": given}]])
    mesh = load_mesh(path)
    flat, own = mesh.parts
    p = mesh.world_positions()
    for face in mesh.indices[flat.first : flat.first + flat.count]:
        face_normal = np.cross(p[face[1]] - p[face[0]], p[face[2]] - p[face[0]])
        np.testing.assert_allclose(mesh.normals[face], np.tile(face_normal / np.linalg.norm(face_normal), (3, 1)), atol=1e-6)
    np.testing.assert_allclose(mesh.normals[mesh.indices[own.first :].reshape(-1)], np.tile(given[0], (6, 1)), atol=1e-6)


def test_gltf_vertex_colors_multiply_the_base_color(tmp_path, renderer):
    positions, indices = quad(-1.0, -0.5)
    colors = np.tile(np.float32([0, 1, 0.5, 1]), (4, 1))
    path = write_gltf(
        tmp_path / "c.gltf",
        meshes=[[{"positions": positions, "indices": indices, "normals": np.tile(np.float32([0, 0, 1]), (4, 1)), "colors": colors, "material": 0}]],
        materials=[{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 1, 1], "metallicFactor": 0.0}}],
    )
    for frequency in ("flat", "gouraud", "phong"):
        image = renderer.render(head_on([SceneObject(load_mesh(path))], frequency))
        # (0, 1, 0.5) × (1, 0.5, 1) = (0, 0.5, 0.5) in linear light, sRGB-encoded: 0.5 → 188
        np.testing.assert_allclose(pixel(image, -0.5, 0.0)[:3], [0, 188, 188], atol=1, err_msg=frequency)


def test_gltf_alpha_modes(tmp_path, renderer):
    """OPAQUE ignores alpha; MASK discards below the cutoff; BLEND blends over what is behind."""
    back_positions, indices = quad(-2.0, -1.0, 4.0, z=-1.0)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    primitives = [[{"positions": back_positions, "indices": indices, "normals": normals, "material": 0}]]
    materials = [{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 1], "metallicFactor": 0}}]
    modes = [("OPAQUE", {}), ("MASK", {"alphaCutoff": 0.5}), ("MASK", {"alphaCutoff": 0.2}), ("BLEND", {})]
    for index, (mode, extra) in enumerate(modes):
        positions, _ = quad(-1.9 + index, -0.4, 0.8)
        primitives.append([{"positions": positions, "indices": indices, "normals": normals, "material": index + 1}])
        materials.append({"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 0.25], "metallicFactor": 0}, "alphaMode": mode} | extra)
    mesh = load_mesh(write_gltf(tmp_path / "a.gltf", meshes=primitives, materials=materials))
    image = renderer.render(head_on([SceneObject(mesh)], size=(128, 64)))
    assert tuple(pixel(image, -1.5, 0.0)) == (255, 0, 0, 255)  # OPAQUE: alpha ignored
    assert tuple(pixel(image, -0.5, 0.0)) == (0, 0, 255, 255)  # MASK 0.5 > 0.25: discarded, blue behind
    assert tuple(pixel(image, 0.5, 0.0)) == (255, 0, 0, 255)  # MASK 0.2 < 0.25: drawn, opaque
    np.testing.assert_allclose(pixel(image, 1.5, 0.0), [64, 0, 191, 255], atol=1)  # BLEND: 0.25 red over blue


def test_blended_parts_are_drawn_back_to_front(tmp_path, renderer):
    near, indices = quad(-1.0, -0.5, z=0.5)
    far, _ = quad(-1.0, -0.5, z=-0.5)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    path = write_gltf(
        tmp_path / "b.gltf",
        meshes=[[{"positions": near, "indices": indices, "normals": normals, "material": 0}],  # the near one comes first in the file
                [{"positions": far, "indices": indices, "normals": normals, "material": 1}]],
        materials=[{"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 0.5], "metallicFactor": 0}, "alphaMode": "BLEND"},
                   {"pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 0.5], "metallicFactor": 0}, "alphaMode": "BLEND"}],
    )
    image = renderer.render(head_on([SceneObject(load_mesh(path))], background=(0, 0, 0, 0)))
    # far green first: 0.5·green; then near red over it: 0.5·red + 0.25·green; alpha 0.5 + 0.5·0.5
    np.testing.assert_allclose(pixel(image, -0.5, 0.0), [128, 64, 0, 191], atol=1)


def test_unlit_shows_the_base_color_as_is(tmp_path, renderer):
    positions, indices = quad(-1.0, -0.5)
    path = write_gltf(
        tmp_path / "u.gltf",
        meshes=[[{"positions": positions, "indices": indices, "normals": np.tile(np.float32([0, 0.8, 0.6]), (4, 1)), "material": 0}]],
        materials=[{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1]}, "extensions": {"KHR_materials_unlit": {}}}],
        extra={"extensionsUsed": ["KHR_materials_unlit"]},
    )
    image = renderer.render(head_on([SceneObject(load_mesh(path))]))  # lit, the tilted normal would darken it to 0.6×
    # The linear factor (0.2, 0.4, 0.6), sRGB-encoded as glTF viewers show it.
    np.testing.assert_allclose(pixel(image, -0.5, 0.0)[:3], [124, 170, 203], atol=1)


def test_gltf_material_mapping_formula(tmp_path):
    """docs/real-world-files.md: s = metallic·(1 − roughness²), diffuse = base·(1 − s),
    specular = f0·(1 − metallic) + base·s, shininess = clamp((2/α² − 2)/4, 1, 512) with α = roughness²."""
    positions, indices = quad(0, 0)
    materials = [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.4, 0.2, 1], "metallicFactor": 0.25, "roughnessFactor": 0.5}},
        {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [30, 1, 1]}}},
    ]
    primitives = [[{"positions": positions, "indices": indices, "material": k}] for k in range(2)]
    first, second = (p.material for p in load_mesh(write_gltf(tmp_path / "m.gltf", meshes=primitives, materials=materials)).parts)
    share = 0.25 * (1 - 0.5**2)  # s = 0.1875
    np.testing.assert_allclose(first.diffuse[:3], np.array([0.8, 0.4, 0.2]) * (1 - share))
    np.testing.assert_allclose(first.ambient[:3], [0.8, 0.4, 0.2])
    np.testing.assert_allclose(first.specular[:3], 0.04 * 0.75 + np.array([0.8, 0.4, 0.2]) * share)
    assert first.shininess == pytest.approx((2 / 0.25**2 - 2) / 4)  # α = 0.5² = 0.25: 7.5
    np.testing.assert_allclose(second.specular[:3], [0.5, 0.02, 0.02])  # min(0.04·color, 1)·factor


def test_draco_decodes_through_the_extra(renderer):
    pytest.importorskip("DracoPy")
    mesh = load_mesh(REAL / "BoxTextured_draco.glb")
    lower, upper = mesh.bounds()
    np.testing.assert_allclose(lower, -0.5, atol=1e-3) and np.testing.assert_allclose(upper, 0.5, atol=1e-3)
    assert mesh.parts[0].material.texture is not None and mesh.triangle_count == 12


def test_draco_without_the_extra_is_an_error_naming_it(monkeypatch):
    import sys

    from wgpu_shading import MeshError

    monkeypatch.setitem(sys.modules, "DracoPy", None)  # `import DracoPy` raises ImportError
    with pytest.raises(MeshError, match=r"Draco mesh compression \(KHR_draco_mesh_compression\); to decode it, install the \[draco\] extra into this environment: .* -m pip install 'DracoPy"):
        load_mesh(REAL / "BoxTextured_draco.glb")


def test_gltf_color_0_file_from_blender(renderer):
    mesh = load_mesh(REAL / "cubevc.glb")  # COLOR_0, no material: the glTF default (white, linear)
    assert mesh.colors is not None and mesh.parts[0].material.name == "glTF default"
    np.testing.assert_allclose(mesh.colors, np.tile([1, 0, 1, 1], (mesh.vertex_count, 1)))  # magenta, as f3d shows it
    image = renderer.render(head_on([SceneObject(mesh, Material(diffuse=(1, 1, 1, 1)))], half_width=3.0))
    assert tuple(pixel(image, 0.0, 0.0, 3.0)[:3]) == (255, 0, 255)  # the cube's front face, head-on


# --------------------------------------------------------------------------- PLY colors, opaque output


def test_ply_vertex_and_face_colors(tmp_path, renderer):
    header = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    vertices = "-1 -0.5 0\n0 -0.5 0\n0 0.5 0\n-1 0.5 0\n"
    (tmp_path / "v.ply").write_text(
        header + "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
        + "".join(line + " 0 0 255\n" for line in vertices.splitlines()) + "3 0 1 2\n3 0 2 3\n"
    )
    (tmp_path / "f.ply").write_text(
        header + "element face 2\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
        + vertices + "3 0 1 2 255 0 0\n3 0 2 3 0 255 0\n"
    )
    white = Material(diffuse=(1, 1, 1, 1))
    image = renderer.render(head_on([SceneObject(load_mesh(tmp_path / "v.ply"), white)]))
    assert tuple(pixel(image, -0.5, 0.0)[:3]) == (0, 0, 255)
    image = renderer.render(head_on([SceneObject(load_mesh(tmp_path / "f.ply"), white)], "gouraud"))
    assert tuple(pixel(image, -0.2, -0.3)[:3]) == (255, 0, 0) and tuple(pixel(image, -0.8, 0.3)[:3]) == (0, 255, 0)


def test_obj_vertex_colors(tmp_path, renderer):
    (tmp_path / "c.obj").write_text("v -1 -0.5 0 1 0.5 0\nv 0 -0.5 0 1 0.5 0\nv 0 0.5 0 1 0.5 0\nf 1 2 3\n")
    image = renderer.render(head_on([SceneObject(load_mesh(tmp_path / "c.obj"), Material(diffuse=(1, 1, 1, 1)))]))
    np.testing.assert_allclose(pixel(image, -0.2, -0.3)[:3], [255, 128, 0], atol=1)


def test_output_is_opaque_whatever_the_material_alpha(renderer):
    from wgpu_shading.scene import material

    sphere = load_mesh("builtin:sphere")
    image = renderer.render(head_on([SceneObject(sphere, material("ruby"))], background=(0.2, 0.2, 0.2, 0.0)))
    assert material("ruby").diffuse[3] == 0.55
    assert tuple(pixel(image, 0.0, 0.0)[3:]) == (255,) and tuple(pixel(image, 1.9, 0.9)[3:]) == (0,)


def test_scene_file_material_alpha_mode_blends(tmp_path, renderer):
    from wgpu_shading import load_scene

    (tmp_path / "s.toml").write_text(
        '[output]\nsize = [16, 16]\nbackground = [0, 0, 0, 0]\n[ambient]\ncolor = [1, 1, 1]\n'
        '[[objects]]\nmesh = "builtin:plane"\nscale = [4, 4, 4]\n'
        'material = { ambient = [1, 0, 0, 0.5], diffuse = [0, 0, 0, 0.5], alpha_mode = "blend" }\n'
    )
    scene = load_scene(tmp_path / "s.toml")
    assert scene.objects[0].material.alpha_mode == "blend"
    np.testing.assert_allclose(renderer.render(scene)[8, 8], [128, 0, 0, 128], atol=1)  # half red over transparent black


def test_point_clouds_are_points_and_triangle_strips_triangles(tmp_path, capsys):
    from wgpu_shading import MeshError
    from wgpu_shading.cli import main

    header = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    vertices = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
    (tmp_path / "points.ply").write_text(header + "end_header\n" + vertices)
    (tmp_path / "strips.ply").write_text(header + "element tristrips 1\nproperty list int int vertex_indices\nend_header\n" + vertices + "4 0 1 2 3\n")
    points = load_mesh(tmp_path / "points.ply")  # a PLY without faces is a point cloud (docs/primitives.md)
    assert points.point_count == 4 and points.triangle_count == 0
    assert load_mesh(tmp_path / "strips.ply").triangle_count == 2  # (0 1 2), (2 1 3): tests/test_ply_strips.py
    (tmp_path / "m.obj").write_text("mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert main(["render", str(tmp_path / "m.obj"), "--size", "8", "-q", "-o", str(tmp_path / "m.png")]) == 0
    err = capsys.readouterr().err
    assert err == f"wgpu-shading: warning: {tmp_path / 'm.obj'}: material library 'gone.mtl' not found (looked for {tmp_path / 'gone.mtl'}); parts drawn without it\n"


def test_shader_command_prints_each_parts_shader(tmp_path, capsys):
    from wgpu_shading.cli import main

    positions, indices = quad(0, 0)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    path = write_gltf(
        tmp_path / "two.gltf",
        meshes=[[{"positions": positions, "indices": indices, "normals": normals, "material": 0}],
                [{"positions": positions + 2, "indices": indices, "normals": normals, "material": 1}]],
        materials=[{"pbrMetallicRoughness": {"metallicFactor": 0}}, {"pbrMetallicRoughness": {"metallicFactor": 0}, "alphaMode": "MASK"}],
    )
    assert main(["shader", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.count("// ===== objects 0") == 2 and "alpha=mask" in out and "discard" in out


@pytest.mark.parametrize(
    "wrap_s, expected",
    [  # the colours at u = 0.25, 0.75, 1.25, 1.75 of a 2×1 texture (yellow | blue)
        (10497, ["yellow", "blue", "yellow", "blue"]),  # REPEAT: the texture again
        (33071, ["yellow", "blue", "blue", "blue"]),  # CLAMP_TO_EDGE: the last column goes on
        (33648, ["yellow", "blue", "blue", "yellow"]),  # MIRRORED_REPEAT: the texture backwards
    ],
)
def test_gltf_sampler_wrap_modes(tmp_path, renderer, wrap_s, expected):
    """glTF samplers' wrapS/wrapT decide what u outside [0, 1] shows (they were all REPEAT)."""
    positions, indices = quad(-1.0, -0.5, 2.0)
    uvs = np.array([[0, 0], [2, 0], [2, 1], [0, 1]], np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    texture = np.array([[[255, 255, 0, 255], [0, 0, 255, 255]]], np.uint8)
    path = write_gltf(
        tmp_path / "wrap.gltf",
        meshes=[[{"positions": positions, "indices": indices, "normals": normals, "uvs": uvs, "material": 0}]],
        materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}, "extensions": {"KHR_materials_unlit": {}}}],
        images=[texture],
        samplers=[{"magFilter": 9728, "minFilter": 9728, "wrapS": wrap_s, "wrapT": 33071}],
        textures=[{"source": 0, "sampler": 0}],
        extra={"extensionsUsed": ["KHR_materials_unlit"]},
    )
    mesh = load_mesh(path)
    assert mesh.parts[0].material.texture.wrap[1] == "clamp"
    image = renderer.render(head_on([SceneObject(mesh)], size=(128, 64)))
    colours = {(255, 255, 0): "yellow", (0, 0, 255): "blue"}
    seen = [colours.get(tuple(int(c) for c in pixel(image, x, 0.0)[:3]), "other") for x in (-0.75, -0.25, 0.25, 0.75)]
    assert seen == expected
