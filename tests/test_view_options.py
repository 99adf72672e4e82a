"""One view vocabulary (wgpu_shading/scene/view/options.py): every option has its four
spellings (the `render` flag, the `batch` flag, the manifest column, the scene-file key),
they read to the same value, and `render` and a one-job `batch` draw the same pixels."""

from __future__ import annotations

import dataclasses
import hashlib
import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.assets.scenefile import load_scene
from wgpu_shading.assets.view_loader import load_view
from wgpu_shading.cli import main
from wgpu_shading.cli.arguments import view_options_from_args
from wgpu_shading.cli.main import build_parser
from wgpu_shading.dataset.manifest import read_manifest, row_view_options
from wgpu_shading.errors import UsageError
from wgpu_shading.scene import Camera
from wgpu_shading.scene.view.apply import unappliable
from wgpu_shading.scene.view.options import VIEW_OPTIONS, ViewOptions, render_command, spellings_table
from wgpu_shading.scene.view.reading import parse_light, spell

DOCS = Path(__file__).resolve().parent.parent / "docs"

# Every option's sample is its row's `example` (a value that changes the picture of the tall
# box below: no normals in the file, Y up unless --up), spelled four ways: command-line
# words, a manifest cell, the value, scene-file text ("OBJECT key = value" goes on the
# object, "LIGHT key = value" on the light, other text before them).


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml(item) for item in value) + "]"
    return json.dumps(value) if isinstance(value, str) else repr(value)


def _scene_text(option, value) -> str:
    if option.key is None:
        return ""
    if option.key == "lights":
        tables = []
        for light in (parse_light(spec, Camera()) for spec in value):
            keys = {"type": light.kind, **dataclasses.asdict(light)}
            tables.append("[[lights]]\n" + "".join(f"{key} = {_toml(v)}\n" for key, v in keys.items()))
        return "".join(tables)
    if option.section == "objects" and option.field.startswith("material."):
        return f'OBJECT material = {{ base = "gold", {option.field.removeprefix("material.")} = {_toml(value)} }}'
    if option.section in ("objects", "lights"):
        return f"{option.section.upper().rstrip('S')} {option.field} = {_toml(value)}"
    return f"[{option.section}]\n{option.field} = {_toml(value)}"


# Where a key alone does not say what the option says: a scene file's ortho_height keeps a
# perspective camera unless it says `projection` (the flag implies orthographic).
SCENE_TEXT = {"camera_ortho_height": '[camera]\nprojection = "orthographic"\northo_height = 8.0'}


def _sample(option) -> tuple:
    value = option.example
    words = render_command("x", ViewOptions(**{option.name: value}))[3:]
    cell = ";".join(value) if option.repeated else spell(value)
    return words, cell, value, SCENE_TEXT.get(option.name, _scene_text(option, value))


SAMPLES = {option.name: _sample(option) for option in VIEW_OPTIONS}
# What else a sample needs to show in the pictures below.
WITH = {"blinn_exponent_scale": ["--reflection", "blinn-phong"], "edge_color": ["--edges"], "edge_width": ["--edges"]}
# no back faces, colours, file lights, points or lines (tests/test_primitives_drawing.py draws those)
_NO_EFFECT_ON_THE_BOX = ("two_sided", "clamp_vertex_colors", "viewer_lights", "point_size", "line_width")
# One convex box shadows only its own sides that face away from a light, which that light
# does not reach anyway (docs/shadows.md): its shadow options draw the same box (pixels
# compared, not asserted different; tests/test_shadows_*.py show them at work).
_NO_EFFECT_ON_THE_BOX += ("shadows", "cast_shadows", "receive_shadows", "shadow_map_size", "shadow_filter", "shadow_bias")
BOX = "".join(f"v {x} {y} {z}\n" for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-1.5, 1.5)) + "".join(
    f"f {a} {b} {c}\n" for a, b, c in ((1, 2, 4), (1, 4, 3), (5, 7, 8), (5, 8, 6), (1, 5, 6), (1, 6, 2),
                                       (3, 4, 8), (3, 8, 7), (1, 3, 7), (1, 7, 5), (2, 6, 8), (2, 8, 4))
)


# Options that only a glTF file can show (its animations, its cameras): their samples draw
# the same box as a glTF file with two animations (0 turns it about Y, 1 about X: a bare
# mesh is framed, so a move alone would not show) and a camera.
GLTF_ONLY = ("animation_time", "animation_index", "camera_index")


@pytest.fixture(scope="module")
def box(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("box")
    path = folder / "box.obj"
    path.write_text(BOX)
    _gltf_box(folder / "box.gltf")
    return path


def _gltf_box(path: Path) -> None:
    import base64

    from gltf_builder import write_gltf

    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-1.5, 1.5)], np.float32)
    faces = np.array([[int(i) - 1 for i in line.split()[1:]] for line in BOX.splitlines() if line.startswith("f ")])
    write_gltf(path, [[{"positions": corners, "indices": faces}]], nodes=[{"mesh": 0}, {"camera": 0, "translation": [1, 2, 6]}])
    document = json.loads(path.read_text())
    half = float(np.sqrt(0.5))
    keys = np.array([0.0, 1.0], np.float32).tobytes()
    turns = np.array([[0, 0, 0, 1], [0, half, 0, half]], np.float32).tobytes()
    tilts = np.array([[half, 0, 0, half], [0, 0, 0, 1]], np.float32).tobytes()  # from 90° about X back: seen alone (its start)
    payload = keys + turns + tilts
    document["buffers"].append({"byteLength": len(payload), "uri": "data:application/octet-stream;base64," + base64.b64encode(payload).decode()})
    first_view, first_accessor = len(document["bufferViews"]), len(document["accessors"])
    for offset, length in ((0, 8), (8, 32), (40, 32)):
        document["bufferViews"].append({"buffer": 1, "byteOffset": offset, "byteLength": length})
    for view, kind, count in ((0, "SCALAR", 2), (1, "VEC4", 2), (2, "VEC4", 2)):
        document["accessors"].append({"bufferView": first_view + view, "componentType": 5126, "count": count, "type": kind}
                                     | ({"min": [0.0], "max": [1.0]} if kind == "SCALAR" else {}))
    document["animations"] = [
        {"samplers": [{"input": first_accessor, "output": first_accessor + path_index}],
         "channels": [{"sampler": 0, "target": {"node": 0, "path": name}}]}
        for path_index, name in ((1, "rotation"), (2, "rotation"))
    ]
    document["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.5}}]
    document["scenes"] = [{"nodes": [0, 1]}]
    path.write_text(json.dumps(document))


def _source(option, box: Path) -> Path:
    return box.with_suffix(".gltf") if option.name in GLTF_ONLY else box


HEADS = {
    "render": ["render", "x.obj"],
    "batch": ["batch", "--meshes", "x.obj", "-o", "out"],
    "turntable": ["turntable", "x.obj"],
    "check": ["check", "x.obj", "--ref", "r.png"],
    "shader": ["shader", "x.obj"],
}


def _parse(command: str, words: list[str]):
    return view_options_from_args(build_parser().parse_args(HEADS[command] + words))


def test_every_option_has_an_example_its_spellings_and_a_way_to_apply():
    for option in VIEW_OPTIONS:
        assert option.all_flags and option.column and option.scene_key and option.help, option.name
        assert option.read(option.example, option.name) == option.example, option.name
        assert unappliable(option) is None


@pytest.mark.parametrize("option", VIEW_OPTIONS, ids=lambda option: option.name)
def test_render_flag_batch_flag_and_manifest_column_read_the_same_value(option):
    words, cell, value, _ = SAMPLES[option.name]
    for command in HEADS:  # every command that renders takes every view flag
        assert getattr(_parse(command, words), option.name) == value, command
    assert getattr(row_view_options({option.column: cell}, "row"), option.name) == value
    # every flag of the option is accepted by both commands (aliases included)
    for flag in option.all_flags:
        for command in ("render", "batch"):
            arguments = [flag] if option.switch_constant(flag)[0] else [f"{flag}={cell}"]
            assert getattr(_parse(command, arguments), option.name) is not None, (command, flag)


def _scene_file(folder: Path, extra: str, mesh: str = "box.obj") -> Path:
    """The box, lit by one light, as a scene file with one option's key: "OBJECT key = value"
    goes on the object, "LIGHT key = value" on the light, other text before them."""
    tables = {"objects": {"mesh": f'"{mesh}"', "material": '"gold"'}, "lights": {"type": '"positional"'}}
    top = ""
    if extra.startswith(("OBJECT ", "LIGHT ")):
        table, _, rest = extra.partition(" ")
        key, _, value = rest.partition(" = ")
        tables[table.lower() + "s"][key] = value
    else:
        top = extra
    if "[[lights]]" in top:
        del tables["lights"]
    path = folder / f"scene-{hashlib.sha1((extra + mesh).encode()).hexdigest()[:8]}.toml"
    path.write_text(top + "".join(f"\n[[{name}]]\n" + "".join(f"{key} = {value}\n" for key, value in keys.items())
                                  for name, keys in tables.items()))
    return path


def _view(scene) -> tuple:
    """What a scene draws, minus mesh identity: comparable with ==."""
    objects = tuple((o.part_materials(), o.up, o.translate, o.rotate, o.scale, o.mesh.normals.tobytes(), o.cast_shadows,
                     o.receive_shadows) for o in scene.objects)
    return scene.camera, scene.shading, scene.shadows, scene.lights, scene.size, scene.samples, scene.background, objects


@pytest.mark.parametrize("option", VIEW_OPTIONS, ids=lambda option: option.name)
def test_the_scene_file_key_means_what_the_option_means(option, box):
    _, _, value, toml = SAMPLES[option.name]
    mesh = _source(option, box).name
    with_key = load_scene(_scene_file(box.parent, toml, mesh))
    with_option = load_view(str(_scene_file(box.parent, "", mesh)), ViewOptions(**{option.name: value}))
    assert _view(with_key) == _view(with_option)
    # crease_angle: the box has no smooth edge; the others have no scene-file key (a scene file places its own camera)
    assert (_view(with_key) != _view(load_scene(_scene_file(box.parent, "", mesh)))
            or option.name in ("crease_angle", "viewer_lights", "camera_index"))


def _pixels(path: Path) -> np.ndarray:
    return np.asarray(Image.open(path))


@pytest.mark.parametrize("option", VIEW_OPTIONS, ids=lambda option: option.name)
def test_render_and_a_one_job_batch_draw_the_same_pixels(option, box, tmp_path):
    words = WITH.get(option.name, []) + SAMPLES[option.name][0]
    size = [] if option.name == "size" else ["--size", "48"]
    if option.name in ("frequency", "reflection", "local_viewer"):
        size += ["--crease-angle", "180"]  # a smooth box: the shading options show
    source = _source(option, box)
    assert main(["render", str(source), *size, *words, "-o", str(tmp_path / "render.png"), "-q"]) == 0
    assert main(["batch", "--meshes", str(source), "--views", "1", *size, *words, "-o", str(tmp_path / "batch"), "-q"]) == 0
    rendered = _pixels(tmp_path / "render.png")
    assert np.array_equal(rendered, _pixels(tmp_path / "batch" / "box" / "view_000.png"))
    plain = tmp_path / "plain.png"
    assert main(["render", str(source), *size, "-o", str(plain), "-q"]) == 0
    if option.name not in _NO_EFFECT_ON_THE_BOX:  # a closed box without vertex colours or file lights
        assert not np.array_equal(rendered, _pixels(plain)), "the sample value should change the picture"


def test_a_manifest_row_per_option_draws_what_render_draws(box, tmp_path):
    options = [option for option in VIEW_OPTIONS if option.name != "size"]
    columns = sorted({option.column for option in options} | {"reflection", "edges"})
    lines = [",".join(["mesh", "name", "size", *columns])]
    for option in options:
        row = {option.column: SAMPLES[option.name][1]}
        if option.name == "blinn_exponent_scale":
            row["reflection"] = "blinn-phong"
        if option.name in ("edge_color", "edge_width"):
            row["edges"] = "true"
        lines.append(",".join([str(box), option.name, "40x32", *(f'"{row.get(c, "")}"' for c in columns)]))
    manifest = tmp_path / "jobs.csv"
    manifest.write_text("\n".join(lines) + "\n")
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    for option in options:
        output = tmp_path / f"{option.name}.png"
        assert main(["render", str(box), "--size", "40x32", *WITH.get(option.name, []), *SAMPLES[option.name][0], "-o", str(output), "-q"]) == 0
        assert np.array_equal(_pixels(output), _pixels(tmp_path / "out" / "box" / f"{option.name}.png")), option.name


def test_render_command_spells_every_option_back_exactly():
    values = {name: sample[2] for name, sample in SAMPLES.items()}
    values.update(camera_position=(0.1 + 0.2, -1e-7, 3.0), shininess=1 / 3, camera_azimuth=-0.0 + 1e-300)
    options = ViewOptions(**values)
    argv = render_command("builtin:torus", options)
    assert argv[:3] == ["wgpu-shading", "render", "builtin:torus"]
    assert view_options_from_args(build_parser().parse_args(argv[1:])) == options
    for name in ("local_viewer", "two_sided", "transparent", "clamp_vertex_colors"):
        flipped = dataclasses.replace(options, **{name: not getattr(options, name)})
        assert view_options_from_args(build_parser().parse_args(render_command("x", flipped)[1:])) == flipped


def test_the_docs_table_is_the_table_in_the_code():
    text = (DOCS / "view-options.md").read_text(encoding="utf-8")
    assert spellings_table() in text, "docs/view-options.md: paste spellings_table()'s output (python -m wgpu_shading.scene.view.options)"


def test_a_manifest_up_column_means_the_model_axis_and_a_vector_the_camera_up(tmp_path):
    manifest = tmp_path / "jobs.csv"
    manifest.write_text('mesh,up\nbuiltin:cube,+Z\nbuiltin:cube,"0 0 1"\n')
    axis, vector = (job.view_options() for job in read_manifest(manifest))
    assert axis.up == "+Z" and axis.camera_view_up is None
    assert vector.up is None and vector.camera_view_up == (0.0, 0.0, 1.0)
    manifest.write_text('mesh,up\nbuiltin:cube,"0 0 1"\n')
    (job,) = read_manifest(manifest, defaults={"up": "+Z"})  # `batch --up +Z` with an old manifest
    assert job.view_options().up == "+Z" and job.view_options().camera_view_up == (0.0, 0.0, 1.0)
    manifest.write_text('mesh,up,camera_up\nbuiltin:cube,"0 0 1","0 1 0"\n')
    with pytest.raises(UsageError, match="camera_up"):
        read_manifest(manifest)


def test_batch_turns_the_meshes_views_on_from_the_camera_flags(tmp_path, box):
    assert main(["batch", "--meshes", str(box), "--views", "2", "--size", "24", "--camera-azimuth-angle", "30",
                 "-o", str(tmp_path / "a"), "-q"]) == 0
    assert main(["render", str(box), "--size", "24", "--camera-azimuth-angle", "210", "-o", str(tmp_path / "b.png"), "-q"]) == 0
    assert np.array_equal(_pixels(tmp_path / "a" / "box" / "view_001.png"), _pixels(tmp_path / "b.png"))


def test_the_readme_batch_example_stands_the_z_up_gear_up(tmp_path):
    """README's `batch --meshes example:gear.ply --up +Z --views 8`: with its up axis the gear
    turns about its own axis, so every view covers about as much of the image; without it
    (the old example) two of the eight views were edge-on slivers."""
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text(encoding="utf-8")
    assert "wgpu-shading batch --meshes example:gear.ply --up +Z --views 8" in readme
    covered = {}
    for up in ("+Z", "+Y"):
        out = tmp_path / up
        assert main(["batch", "--meshes", "example:gear.ply", "--up", up, "--views", "4", "--size", "32", "-o", str(out), "-q"]) == 0
        covered[up] = [int((_pixels(out / "gear" / f"view_{i:03d}.png")[..., :3].max(axis=2) > 0).sum()) for i in range(4)]
    assert min(covered["+Z"]) > 0.8 * max(covered["+Z"]), covered
    assert min(covered["+Y"]) < 0.5 * max(covered["+Y"]), covered  # the sliver the issue saw
