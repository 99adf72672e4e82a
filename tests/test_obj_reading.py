"""Defects found by checking files from outside the repository (issue 12's "real files that are
not in the repository"): each test is a small generated file with the same trait as the real
one (named in the test), checked against what the format's author meant."""
from __future__ import annotations

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


def _facet(a, b, c) -> str:
    return "facet normal 0 0 1\nouter loop\n" + "".join(f"vertex {x} {y} 0\n" for x, y in (a, b, c)) + "endloop\nendfacet\n"


def _solid(name: str, x0: float) -> str:
    corners = [(x0, -0.5), (x0 + 1, -0.5), (x0 + 1, 0.5), (x0, 0.5)]
    return f"solid {name}\n" + _facet(corners[0], corners[1], corners[2]) + _facet(corners[0], corners[2], corners[3]) + f"endsolid {name}\n"


def test_ascii_stl_with_several_solids_draws_them_all(tmp_path, renderer):
    """CAD tools export an assembly as one ASCII STL with a `solid` per body (trimesh's
    models/multibody.stl, two_objects_mixed_case_names.stl); f3d and slicers draw every body.
    It used to stop with "expected one mesh, found 2"."""
    (tmp_path / "two.stl").write_text(_solid("left", -1.5) + _solid("Right", 0.5))
    mesh = load_mesh(tmp_path / "two.stl")
    assert sum(p.count for p in mesh.parts) == 4
    image = renderer.render(head_on([SceneObject(mesh)], "flat"))
    left, right, gap = pixel(image, -1.0, 0.0), pixel(image, 1.0, 0.0), pixel(image, 0.0, 0.0)
    assert left[3] == right[3] == 255 and left[:3].sum() > 100
    assert tuple(left) == tuple(right)  # same default material, same facing
    assert tuple(gap[:3]) == (0, 0, 0)


def test_a_file_with_no_mesh_says_it_has_no_triangles(tmp_path):
    """trimesh's models/empty.ply and emptyIO/ply_empty_bin.ply: the message said
    "expected one mesh, found 0"."""
    (tmp_path / "empty.stl").write_text("solid empty\nendsolid empty\n")
    with pytest.raises(MeshError, match=r"empty.stl': contains no triangles"):
        load_mesh(tmp_path / "empty.stl")


def _as_glb(gltf_path, glb_path):
    """The same document as a GLB (JSON chunk only; the buffers stay data URIs)."""
    import struct

    text = gltf_path.read_bytes()
    text += b" " * (-len(text) % 4)
    glb_path.write_bytes(b"glTF" + struct.pack("<II", 2, 20 + len(text)) + struct.pack("<I", len(text)) + b"JSON" + text)
    return glb_path


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_gltf_specular_glossiness_shows_the_diffuse_texture(tmp_path, renderer, suffix):
    """KHR_materials_pbrSpecularGlossiness (older Sketchfab/3ds Max exports; assimp's
    BoxTextured-glTF-pbrSpecularGlossiness): trimesh bakes the specular color into a new base
    color texture, which rendered the box grey and washed out where f3d shows the diffuse
    texture. Under a white head-on light with no specular part, each texel shows as it is."""
    import numpy as np

    from gltf_builder import quad, write_gltf
    from test_file_parts import _checker

    positions, indices = quad(-1.0, -0.5, 1.0)
    path = write_gltf(
        tmp_path / "sg.gltf",
        meshes=[[{"positions": positions * [2, 1, 1], "indices": indices, "normals": np.tile(np.float32([0, 0, 1]), (4, 1)),
                  "uvs": np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32), "material": 0}]],
        materials=[{"extensions": {"KHR_materials_pbrSpecularGlossiness": {
            "diffuseTexture": {"index": 0}, "specularFactor": [0.2, 0.3, 0.4], "glossinessFactor": 0.5}}}],
        images=[_checker()], samplers=[{"magFilter": 9728, "minFilter": 9728}], textures=[{"source": 0, "sampler": 0}],
        extra={"extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"]},
    )
    if suffix == ".glb":
        path = _as_glb(path, tmp_path / "sg.glb")
    material = load_mesh(path).parts[0].material
    assert material.specular[:3] == pytest.approx((0.2, 0.3, 0.4)) and material.diffuse[:3] == (1.0, 1.0, 1.0)
    assert material.shininess == pytest.approx((2 / 0.25**2 - 2) / 4)  # roughness 1 − 0.5, the metallic-roughness rule
    assert material.texture is not None and material.texture.nearest
    image = renderer.render(head_on([SceneObject(load_mesh(path))], size=(128, 64)))  # a light without specular
    # the checker's texels exactly (test_gltf_textured_and_untextured_parts_with_instanced_nodes's layout)
    assert tuple(pixel(image, -1.5, 0.25)[:3]) == (0, 0, 255) and tuple(pixel(image, -0.5, 0.25)[:3]) == (255, 255, 0)


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


def test_gltf_texture_transform_moves_the_uvs(tmp_path, renderer):
    """KHR_texture_transform (assimp's TextureTransformTest.gltf showed its own "not
    supported" tiles; f3d applies it). A 2×2 texture of four colors on two quads, nearest
    sampling: an offset of half the texture in u (left quad) or in glTF's v, which runs down
    the image (right quad), shows the neighbouring texel. Without a transform the quads'
    upper-left quarter shows the image's lower-left texel (blue)."""
    from gltf_builder import quad, write_gltf

    pixels = np.zeros((2, 2, 4), np.uint8)
    pixels[0, 0], pixels[0, 1], pixels[1, 0], pixels[1, 1] = (255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255), (255, 255, 255, 255)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    left, indices = quad(-1.75, -0.5)
    right, _ = quad(0.25, -0.5)

    def material(offset):
        return {"pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {
            "index": 0, "extensions": {"KHR_texture_transform": {"offset": offset}}}}}

    path = write_gltf(
        tmp_path / "tt.gltf",
        meshes=[[{"positions": left, "indices": indices, "normals": normals, "uvs": uvs, "material": 0}],
                [{"positions": right, "indices": indices, "normals": normals, "uvs": uvs, "material": 1}]],
        materials=[material([0.5, 0.0]), material([0.0, 0.5])],
        images=[pixels], samplers=[{"magFilter": 9728, "minFilter": 9728}], textures=[{"source": 0, "sampler": 0}],
        extra={"extensionsUsed": ["KHR_texture_transform"]},
    )
    image = renderer.render(head_on([SceneObject(load_mesh(path))], size=(128, 64)))
    assert tuple(pixel(image, -1.5, 0.25)[:3]) == (255, 255, 255)  # u + 0.5: the lower-right texel
    assert tuple(pixel(image, -1.5, -0.25)[:3]) == (0, 255, 0)  # the upper-right one
    assert tuple(pixel(image, 0.5, 0.25)[:3]) == (255, 0, 0)  # v + 0.5: the upper-left texel
    assert tuple(pixel(image, 0.5, -0.25)[:3]) == (0, 0, 255)  # the lower-left one


def test_indented_obj_lines_are_read(tmp_path):
    """Blanks before a keyword are allowed; they used to hide every line ('0 vertices')."""
    from wgpu_shading.assets import load_mesh

    path = tmp_path / "indented.obj"
    path.write_text("  v 0 0 0\n\tv 1 0 0\n v 0 1 0\n   f 1 2 3\n")
    mesh = load_mesh(path)
    assert (mesh.vertex_count, mesh.triangle_count) == (3, 1)
    assert sorted(map(tuple, mesh.world_positions().round(6).tolist())) == [(0, 0, 0), (0, 1, 0), (1, 0, 0)]
