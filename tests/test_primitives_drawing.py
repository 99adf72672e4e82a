"""Points, lines and edges drawn (issue 27, docs/primitives.md), against closed forms and the
float64 reference:

- a point of size s without a normal covers exactly s × s pixels; with a normal facing the
  camera, exactly the pixel centres within s/2 of its centre (a disc, ~πs²/4); tilted by θ,
  the ellipse with axes s and s·cos θ;
- a line of width w covers exactly the pixel centres of the w-wide rectangle along it;
- a disc's centre pixel is the reference lighting (study/reference) at the point and its
  normal, in float32 output, to float32 rounding; points without normals and lines are
  their colour (material diffuse × vertex colour);
- edges are drawn over their surface at every pixel of the edge, even at grazing angles
  (no z-fighting), and not through the surface in front;
- a scene without points, lines or edges builds no stroke pipeline, upload or code.

The camera is orthographic with one world unit per pixel: pixel (column i, row j) has
its centre at x = i + 0.5 − W/2, y = H/2 − (j + 0.5)."""

from __future__ import annotations

import dataclasses

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading.scene import Camera, DirectionalLight, Material, Mesh, PositionalLight, Scene, SceneObject, Shading, SpotLight
from wgpu_shading.scene.geometry.mesh_parts import MeshPart
from wgpu_shading.study import reference as ref

W = H = 64
PIXEL_CAMERA = Camera(eye=(0.0, 0.0, 10.0), target=(0.0, 0.0, 0.0), projection="orthographic", ortho_height=float(H), near=1.0, far=20.0)


def world(i: float, j: float, z: float = 0.0) -> tuple[float, float, float]:
    """The world point at the centre of pixel (column i, row j) (fractions: between centres)."""
    return (i + 0.5 - W / 2, H / 2 - (j + 0.5), z)


def scene_of(mesh: Mesh, *, material: Material | None = None, lights=(), camera=PIXEL_CAMERA, **shading) -> Scene:
    return Scene(objects=(SceneObject(mesh, material or Material(diffuse=(1.0, 1.0, 1.0, 1.0))),), lights=tuple(lights),
                 camera=camera, shading=Shading(**shading), size=(W, H), ambient=(0.0, 0.0, 0.0, 1.0))


def drawn(renderer, scene: Scene) -> np.ndarray:
    return renderer.render(scene)[..., :3].max(axis=2) > 0


def _components(mask: np.ndarray) -> list[np.ndarray]:
    """Pixel sets of the 4-connected components of `mask`."""
    seen = np.zeros_like(mask)
    found = []
    for start in zip(*np.nonzero(mask)):
        if seen[start]:
            continue
        stack, pixels = [start], []
        seen[start] = True
        while stack:
            j, i = stack.pop()
            pixels.append((j, i))
            for dj, di in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                n = (j + dj, i + di)
                if 0 <= n[0] < mask.shape[0] and 0 <= n[1] < mask.shape[1] and mask[n] and not seen[n]:
                    seen[n] = True
                    stack.append(n)
        found.append(np.array(pixels))
    return found


@pytest.mark.parametrize("size", [1, 3, 5, 8])
def test_a_point_of_size_s_covers_s_by_s_pixels(renderer, size):
    """Odd sizes centred on a pixel centre, even ones on a pixel corner: exactly s × s."""
    offset = 0.0 if size % 2 else 0.5
    centres = [(10, 12), (40, 20), (25, 50)]
    mesh = Mesh.from_arrays([world(i + offset, j + offset) for i, j in centres])
    mask = drawn(renderer, scene_of(mesh, point_size=float(size)))
    parts = _components(mask)
    assert len(parts) == 3 and all(len(p) == size * size for p in parts), [len(p) for p in parts]
    for (i, j), part in zip(sorted(centres, key=lambda c: (c[1], c[0])), sorted(parts, key=lambda p: tuple(p.min(0)))):
        low = (j - (size - 1) // 2, i - (size - 1) // 2)
        assert tuple(part.min(0)) == low


def _lattice_count(radius_squared: float) -> int:
    """Pixel centres within the circle: the integer points (a, b) with a² + b² ≤ r² (Gauss)."""
    r = int(np.sqrt(radius_squared)) + 1
    a, b = np.meshgrid(np.arange(-r, r + 1), np.arange(-r, r + 1))
    return int((a * a + b * b <= radius_squared).sum())


@pytest.mark.parametrize("size", [5, 9, 15])
def test_a_disc_facing_the_camera_covers_the_pixel_centres_within_half_its_size(renderer, size):
    """Gauss's count of integer points within s/2 (s odd: no pixel centre lies on the circle), ≈ πs²/4."""
    mesh = Mesh.from_arrays([world(16, 16), world(46, 40)], normals=[(0, 0, 1), (0, 0, -1)])  # either sign: towards the camera
    mask = drawn(renderer, scene_of(mesh, point_size=float(size), lights=[DirectionalLight(direction=(0, 0, -1))]))
    expected = _lattice_count(size * size / 4.0)
    assert [len(p) for p in _components(mask)] == [expected, expected]
    assert abs(expected - np.pi * size * size / 4) < np.pi * size  # the area, within its rim


@pytest.mark.parametrize("degrees", [40.0, 70.0])
def test_a_tilted_disc_is_the_ellipse_its_plane_cuts(renderer, degrees):
    """Tilted by θ about the x axis, the disc seen straight on is an ellipse with half axes
    s/2 and s/2·cos θ: the pixel centres inside it, except those within 0.02 px of the rim."""
    size, angle = 21, np.radians(degrees)
    normal = (0.0, np.sin(angle), np.cos(angle))
    mesh = Mesh.from_arrays([world(31, 31), world(500, 500)], normals=[normal, normal])  # (the second one off the image)
    mask = drawn(renderer, scene_of(mesh, point_size=float(size), lights=[DirectionalLight(direction=(0, 0, -1))]))
    j, i = np.mgrid[0:H, 0:W]
    x, y = i - 31.0, -(j - 31.0)
    level = (x / (size / 2)) ** 2 + (y / (size / 2 * np.cos(angle))) ** 2
    inside, clear = level <= 1.0, np.abs(level - 1.0) > 0.02
    np.testing.assert_array_equal(mask[clear], inside[clear])


def test_a_disc_centre_is_the_reference_lighting_at_the_point(renderer):
    """Three lights of every kind with specular highlights, a perspective camera, a point
    with a vertex colour: the centre pixel (float32 output) is ref.shade + ref.combine at
    the point and its normal, in eye space, to float32 rounding."""
    camera = Camera(eye=(0.3, 0.4, 4.0), target=(0.0, 0.0, 0.0), fov_y=40.0, near=0.5, far=20.0)
    lights = (
        DirectionalLight(direction=(-0.3, -0.5, -1.0), diffuse=(0.7, 0.6, 0.5, 1.0), specular=(1.0, 1.0, 1.0, 1.0)),
        PositionalLight(position=(1.0, 1.5, 2.0), diffuse=(0.4, 0.5, 0.9, 1.0), specular=(0.5, 0.5, 0.5, 1.0), attenuation=(1.0, 0.1, 0.05)),
        SpotLight(position=(-1.0, 0.5, 2.5), direction=(0.4, -0.2, -1.0), cutoff=40.0, exponent=5.0, diffuse=(0.3, 0.9, 0.3, 1.0)),
    )
    material = Material(ambient=(0.2, 0.1, 0.1, 1.0), diffuse=(0.8, 0.6, 0.4, 1.0), specular=(0.9, 0.9, 0.9, 1.0), shininess=20.0)
    point, normal, colour = np.array([0.2, -0.1, 0.3]), np.array([0.2, 0.4, 1.0]) / np.linalg.norm([0.2, 0.4, 1.0]), (0.9, 0.7, 1.0, 1.0)
    mesh = Mesh.from_arrays([point, [5.0, 5.0, -30.0]], normals=[normal, (0, 0, 1)], colors=[colour, colour])
    scene = Scene(objects=(SceneObject(mesh, material),), lights=lights, camera=camera, size=(W, H), ambient=(0.1, 0.1, 0.1, 1.0),
                  shading=Shading(point_size=9.0))
    image = renderer.render(scene, float32=True)
    view = ref.eye_from_world(camera)
    eye_point = (view @ np.append(point, 1.0))[:3]
    eye_normal = view[:3, :3] @ normal
    # where the point lands: the reference's window coordinates of the eye point
    x, y = ref.transforms.window_coordinates(eye_point[None], camera, (W, H))[0][:2]
    column, row = int(np.floor(x)), int(np.floor(y))
    coloured = replace(material, ambient=tuple(np.multiply(material.ambient, colour)), diffuse=tuple(np.multiply(material.diffuse, colour)))
    # the pixel centre's eye-space ray meets the disc's plane a fraction of a pixel from the point: light it there
    origins, directions = ref.window_rays(camera, (W, H), np.array([column + 0.5]), np.array([row + 0.5]))
    t = np.dot(eye_normal, eye_point - origins[0]) / np.dot(eye_normal, directions[0])
    at_pixel = origins[0] + t * directions[0]
    ambient_diffuse, specular = ref.shade(at_pixel[None], eye_normal[None], ref.view_vectors(at_pixel[None], eye_normal[None], True),
                                          scene, coloured)
    expected = ref.combine(ambient_diffuse, specular, coloured, None)[0][:3]
    np.testing.assert_allclose(image[row, column, :3], expected, atol=2e-5)
    assert np.linalg.norm(at_pixel - eye_point) < 0.05  # within a pixel (0.042 there) of the point itself


def test_points_without_normals_and_lines_are_their_colour(renderer):
    """Vertex colours × the material's diffuse, unlit: exactly (to 8-bit rounding)."""
    colours = np.array([[1.0, 0.0, 0.0, 1.0], [0.0, 0.5, 1.0, 1.0], [0.2, 0.9, 0.3, 1.0], [0.2, 0.9, 0.3, 1.0]])
    positions = [world(10, 10), world(50, 10), world(10, 40), world(50, 40)]
    parts = (MeshPart(0, 2, primitive="points"), MeshPart(0, 1, primitive="lines"))
    mesh = Mesh.from_arrays(positions, lines=[[2, 3]], colors=colours, parts=parts)
    image = renderer.render(scene_of(mesh, material=Material(diffuse=(0.5, 1.0, 1.0, 1.0)), point_size=3.0, line_width=3.0))
    np.testing.assert_allclose(image[10, 10, :3], [127.5, 0, 0], atol=0.5)
    np.testing.assert_allclose(image[10, 50, :3], [0, 127.5, 255], atol=0.5)
    np.testing.assert_allclose(image[40, 30, :3], [25.5, 229.5, 76.5], atol=0.51)  # (0.1, 0.9, 0.3) along the line (8-bit rounding either way)


@pytest.mark.parametrize("width", [1, 3, 4])
def test_a_line_of_width_w_covers_the_rectangle_along_it(renderer, width):
    """Horizontal and vertical segments between pixel corners cover exactly the pixels of
    the rectangle (square-cut ends); a diagonal one exactly the pixel centres inside its
    w-wide rectangle, except those within 0.01 px of its sides."""
    half = width / 2
    ends = [((10, 20), (30, 20)), ((50, 5), (50, 25)), ((8, 58), (40, 34))]  # pixel corners (x right, y down)
    positions = [world(x - 0.5, y - 0.5) for segment in ends for x, y in segment]
    mesh = Mesh.from_arrays(positions, lines=[[0, 1], [2, 3], [4, 5]])
    mask = drawn(renderer, scene_of(mesh, line_width=float(width)))
    j, i = np.mgrid[0:H, 0:W]
    expected = np.zeros((H, W), bool)
    clear = np.ones((H, W), bool)
    for (x0, y0), (x1, y1) in ends:
        px, py = i + 0.5 - x0, j + 0.5 - y0
        length = np.hypot(x1 - x0, y1 - y0)
        along = (px * (x1 - x0) + py * (y1 - y0)) / length
        across = (px * -(y1 - y0) + py * (x1 - x0)) / length
        expected |= (along >= 0) & (along <= length) & (np.abs(across) <= half)
        clear &= (np.abs(np.abs(across) - half) > 0.01) & (np.abs(along) > 0.01) & (np.abs(along - length) > 0.01)
    np.testing.assert_array_equal(mask[clear], expected[clear])
    row = mask[19:21].any(axis=0)  # (a 1-pixel line on a pixel boundary takes the row the fill rule gives it)
    assert row[10:30].all() and not row[30] and not row[9]  # the horizontal one ends where it ends


# A camera with room in depth for a square seen at a grazing angle.
DEEP_CAMERA = replace(PIXEL_CAMERA, eye=(0.0, 0.0, 40.0), far=80.0)


def _tilted_quad(degrees: float) -> Mesh:
    """A 40 × 40 square through the origin, turned by `degrees` about the y axis (grazing at 80)."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    corners = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], float)
    turned = corners @ np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]]).T
    return Mesh.from_arrays(turned, [[0, 1, 2], [0, 2, 3]])


def _diagonal_rows_drawn(image: np.ndarray, degrees: float) -> np.ndarray:
    """For each row the tilted square's diagonal crosses, whether an edge-coloured (red) pixel is on it."""
    c = np.cos(np.radians(degrees))
    # the diagonal from (-20c, -20) to (20c, 20) on screen: one pixel per row it crosses
    rows = np.arange(H // 2 - 18, H // 2 + 18)
    columns = np.floor((H / 2 - (rows + 0.5)) * c + W / 2).astype(int)
    return np.array([(image[r, k - 1 : k + 2, :3] == [255, 0, 0]).all(axis=1).any() for r, k in zip(rows, columns)])


@pytest.mark.parametrize("degrees", [0.0, 60.0, 80.0])
def test_edges_are_drawn_over_their_surface_without_z_fighting(renderer, degrees, monkeypatch):
    """Every pixel along the square's diagonal edge (an interior edge, level with both its
    triangles) is the edge colour, however steeply the square is seen; the surface elsewhere
    keeps its colour. Control: without the surfaces' depth bias, the tilted square's
    diagonal loses pixels to its own triangles."""
    mesh = _tilted_quad(degrees)
    red = (1.0, 0.0, 0.0, 1.0)
    lights = [DirectionalLight(direction=(0, 0, -1))]
    plain = renderer.render(scene_of(mesh, lights=lights, camera=DEEP_CAMERA))
    with_edges = scene_of(mesh, lights=lights, camera=DEEP_CAMERA, edges=True, edge_color=red, edge_width=1.0)
    image = renderer.render(with_edges)
    on_edge = _diagonal_rows_drawn(image, degrees)
    assert on_edge.all(), f"rows where the diagonal edge is missing: {np.flatnonzero(~on_edge).tolist()}"
    if degrees:
        import wgpu_shading.render.features as features

        monkeypatch.setattr(features, "surface_offset", lambda scene, mesh=None: 0)
        # A new Scene object: the renderer keeps what it prepared for the old one (gpu/frame_plans.py).
        assert not _diagonal_rows_drawn(renderer.render(dataclasses.replace(with_edges)), degrees).all()
    c = np.cos(np.radians(degrees))
    j, i = np.mgrid[0:H, 0:W]
    away = np.abs(i + 0.5 - ((H / 2 - (j + 0.5)) * c + W / 2)) > 3  # 3 pixels across the rows from the diagonal
    surface = (plain[..., :3].max(axis=2) > 0) & away
    inner = surface.copy()
    inner[:, :] &= np.roll(surface, 2, 0) & np.roll(surface, -2, 0) & np.roll(surface, 2, 1) & np.roll(surface, -2, 1)
    np.testing.assert_array_equal(image[inner], plain[inner])  # away from edges, the surface as it was


@pytest.mark.parametrize("degrees", [0.0, 60.0])
def test_a_meshs_own_lines_over_its_triangles_are_drawn_without_z_fighting(renderer, degrees, monkeypatch):
    """A mesh's own segments lying on its triangles (a PLY `edge` element over its faces,
    OBJ `l` beside `f`) win the depth test at every pixel along them, as `--edges` do:
    the surfaces of such a mesh are pushed back by ceil(line_width / 2) + 1 pixels of their
    slope. Control: without that bias, the tilted square's diagonal loses pixels."""
    quad = _tilted_quad(degrees)
    white, red = Material(diffuse=(1.0, 1.0, 1.0, 1.0)), Material(diffuse=(1.0, 0.0, 0.0, 1.0))
    mesh = Mesh.from_arrays(quad.world_positions(), quad.indices, lines=[[0, 2]],
                            parts=(MeshPart(0, 2, white, "faces"), MeshPart(0, 1, red, "diagonal", "lines")))
    scene = replace(scene_of(mesh, lights=[DirectionalLight(direction=(0, 0, -1))], camera=DEEP_CAMERA),
                    objects=(SceneObject(mesh),))  # the parts' own materials
    on_diagonal = _diagonal_rows_drawn(renderer.render(scene), degrees)
    assert on_diagonal.all(), f"rows where the diagonal is missing: {np.flatnonzero(~on_diagonal).tolist()}"
    if degrees:
        import wgpu_shading.render.features as features

        monkeypatch.setattr(features, "surface_offset", lambda scene, mesh=None: 0)
        # A new Scene object: the renderer keeps what it prepared for the old one (gpu/frame_plans.py).
        assert not _diagonal_rows_drawn(renderer.render(dataclasses.replace(scene)), degrees).all()


def test_edges_behind_a_surface_stay_hidden(renderer):
    """A big square in front of a smaller one: the hidden square's edges do not show through."""
    front = Mesh.from_arrays([world(4, 4, 1.0), world(60, 4, 1.0), world(60, 60, 1.0), world(4, 60, 1.0)], [[0, 3, 2], [0, 2, 1]])
    back = Mesh.from_arrays([world(20, 20, -1.0), world(40, 20, -1.0), world(40, 40, -1.0), world(20, 40, -1.0)], [[0, 3, 2], [0, 2, 1]])
    green, red = Material(diffuse=(0.0, 1.0, 0.0, 1.0), ambient=(0.0, 1.0, 0.0, 1.0)), (1.0, 0.0, 0.0, 1.0)
    scene = Scene(objects=(SceneObject(front, green), SceneObject(back, green)), camera=PIXEL_CAMERA, size=(W, H),
                  ambient=(1.0, 1.0, 1.0, 1.0), shading=Shading(edges=True, edge_color=red, edge_width=1.0))
    image = renderer.render(scene)
    red_pixels = (image[..., :3] == [255, 0, 0]).all(axis=2)
    assert red_pixels[32, 3:6].any() and red_pixels[30:35, 29:35].any()  # the front square's outline and diagonal
    assert not red_pixels[18:23, 30:38].any() and not red_pixels[38:43, 22:30].any()  # not the back square's top and bottom


def test_a_scene_without_points_lines_or_edges_makes_no_stroke_pipeline_upload_or_code():
    """No stroke pipeline, upload or WGSL for triangle scenes; point_size and line_width do
    not change their pixels (byte for byte)."""
    from wgpu_shading import Renderer
    from wgpu_shading.scene import builtin

    renderer = Renderer()  # a fresh cache to look into
    mesh = builtin("builtin:torus")
    scene = Scene(objects=(SceneObject(mesh, Material()),), lights=(DirectionalLight(),), size=(48, 48))
    image = renderer.render(scene)
    cache = renderer.device_cache
    entries = cache.pipelines.entries()
    assert entries
    assert all(entry.key.render_pass.name == "colour" for entry in entries)
    for entry in entries:
        for name in ("quad_corner", "stroke_pixels", "edge_color", "point_on_disc", "viewport_size"):
            assert name not in entry.descriptor.source
    assert all(cache.meshes.get(mesh, kind) is None for kind in ("points", "lines", "edges"))
    other = renderer.render(replace(scene, shading=Shading(point_size=40.0, line_width=30.0, edge_width=9.0, edge_color=(1.0, 0.0, 0.0))))
    assert np.array_equal(image, other)


def test_ids_and_normals_of_points_and_lines_cover_what_the_colour_covers(renderer):
    """The extra outputs draw the same quads: ids where colour is, a disc's normal turned to
    the camera (eye space), a square point's and a line's normal zero."""
    positions = [world(10, 10), world(30, 10), world(10, 40), world(50, 40)]
    normals = [(0.0, 0.0, -1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
    parts = (MeshPart(0, 2, primitive="points"), MeshPart(0, 1, primitive="lines"))
    mesh = Mesh.from_arrays(positions, lines=[[2, 3]], normals=normals, parts=parts)
    scene = scene_of(mesh, lights=[DirectionalLight(direction=(0, 0, -1))], point_size=7.0, line_width=3.0)
    frame = renderer.render_frame(scene, depth=True, normals="eye", ids=True)
    colour = frame.color[..., :3].max(axis=2) > 0
    np.testing.assert_array_equal(frame.ids > 0, colour)
    np.testing.assert_array_equal(np.isfinite(frame.depth), colour)
    assert set(np.unique(frame.ids[10, 5:15])) == {0, 1} and frame.ids[40, 30] == 2
    np.testing.assert_allclose(frame.normals[10, 10], [0.0, 0.0, 1.0], atol=1e-6)  # (0, 0, -1) turned to the camera
    assert not frame.normals[10, 30].any() and not frame.normals[40, 30].any()
    assert _lattice_count(49 / 4) == (frame.ids[:, :20] == 1).sum()  # the disc, as in the colour pass


def test_msaa_with_depth_draws_points_and_lines(renderer):
    positions = [world(10, 10), world(30, 10), world(10, 40), world(50, 40)]
    mesh = Mesh.from_arrays(positions, lines=[[2, 3]], parts=(MeshPart(0, 2, primitive="points"), MeshPart(0, 1, primitive="lines")))
    frame = renderer.render_frame(replace(scene_of(mesh, point_size=5.0, line_width=2.0), samples=4), depth=True)
    assert np.isfinite(frame.depth[10, 10]) and np.isfinite(frame.depth[40, 30]) and frame.color[10, 10, :3].max() > 0


def test_the_command_line_draws_a_real_point_cloud_with_its_outputs(tmp_path):
    """`render` on Blender's eight cube corners (a PLY without faces): `--point-size s` covers
    exactly 8·s² pixels; `batch` on Open3D's SLAC fragment writes depth, normals and ids
    that cover what its colour image covers (both committed in tests/data/real/primitives)."""
    from PIL import Image

    from wgpu_shading.cli import main

    real = Path(__file__).parent / "data" / "real" / "primitives"
    for size in (1, 4):
        out = tmp_path / f"p{size}.png"
        assert main(["render", str(real / "ply_points_ascii.ply"), "--size", "96", "--point-size", str(size), "--no-background",
                     "-o", str(out), "-q"]) == 0
        assert (np.asarray(Image.open(out))[..., 3] > 0).sum() == 8 * size * size
    cloud = real / "livingroom1_slac_fragment_000.ply"
    assert main(["batch", "--meshes", str(cloud), "--views", "1", "--size", "64", "--depth", "npy", "--normals", "eye", "--ids",
                 "-o", str(tmp_path / "batch"), "-q"]) == 0
    folder = tmp_path / "batch" / cloud.stem
    colour = np.asarray(Image.open(folder / "view_000.png"))[..., :3].max(axis=2) > 0
    depth = np.load(folder / "view_000_depth.npy")
    normals = np.load(folder / "view_000_normals_eye.npy")
    ids = np.asarray(Image.open(folder / "view_000_ids.png"))
    assert colour.sum() > 100
    np.testing.assert_array_equal(np.isfinite(depth), ids > 0)
    assert ((np.abs(normals).sum(axis=2) > 0) == (ids > 0)).mean() > 0.99  # every disc has its normal
    assert (colour & (ids == 0)).sum() == 0


@pytest.mark.parametrize("text, suffix", [
    ("v 5 -2 7\n", ".obj"),  # one point, away from the origin
    ("v 1 1 1\nv 1 1 1\nv 1 1 1\n", ".obj"),  # three at one place
    ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", ".ply"),
])
def test_a_point_cloud_at_a_single_place_is_a_dot_in_the_middle(tmp_path, text, suffix):
    # Refused before: "the mesh is 0 units across; between 1e-09 and 1e+09 are supported".
    # A point is so many pixels across from any distance: the bare-mesh view frames a unit
    # sphere around it, and the dot is the point size, centred (f3d draws it too).
    import imageio.v3 as iio

    from wgpu_shading.cli.main import main

    source, output = tmp_path / f"one{suffix}", tmp_path / "one.png"
    source.write_text(text)
    assert main(["render", str(source), "--size", "64", "--point-size", "5", "-o", str(output), "-q"]) == 0
    rows, columns = np.nonzero((iio.imread(output)[..., :3] != 0).any(axis=-1))
    assert (rows.min(), rows.max(), columns.min(), columns.max()) == (29, 33, 29, 33)  # 5 × 5 pixel centres within 2.5 of (32, 32)


def test_only_points_may_lie_at_a_single_place():
    from wgpu_shading import MeshError

    place = np.zeros((3, 3))
    with pytest.raises(MeshError, match="0 units across"):
        Mesh.from_arrays(place, np.array([[0, 1, 2]]))
    with pytest.raises(MeshError, match="0 units across"):
        Mesh.from_arrays(place, lines=np.array([[0, 1]]))
    with pytest.raises(MeshError, match="1e-12 units across"):  # two points, too close to frame: as before
        Mesh.from_arrays(np.array([[0.0, 0, 0], [1e-12, 0, 0]]))
    assert Mesh.from_arrays(place).point_count == 3
