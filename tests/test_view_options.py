"""One view vocabulary (wgpu_shading/scene/view_options.py): every option has its four
spellings (the `render` flag, the `batch` flag, the manifest column, the scene-file key),
they read to the same value, and `render` and a one-job `batch` draw the same pixels."""

from __future__ import annotations

import dataclasses
import hashlib
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
from wgpu_shading.scene.view_options import VIEW_OPTIONS, ViewOptions, render_command, spellings_table

DOCS = Path(__file__).resolve().parent.parent / "docs"

# name: (command-line words, manifest cell, value, scene-file text). Each changes the picture
# of the tall box below (no normals in the file, Y up unless --up).
SAMPLES = {
    "size": (["--size", "40x32"], "40x32", (40, 32), "[output]\nsize = [40, 32]"),
    "samples": (["--samples", "4"], "4", 4, "[output]\nsamples = 4"),
    "background": (["--background-color", "0.2,0.3,0.4"], "0.2 0.3 0.4", (0.2, 0.3, 0.4), "[output]\nbackground = [0.2, 0.3, 0.4]"),
    "transparent": (["--no-background"], "true", True, "[output]\ntransparent = true"),
    "material": (["--material", "silver"], "silver", "silver", 'OBJECT material = "silver"'),
    "shininess": (["--shininess", "3"], "3", 3.0, 'OBJECT material = { base = "gold", shininess = 3.0 }'),
    "frequency": (["--frequency", "gouraud"], "gouraud", "gouraud", '[shading]\nfrequency = "gouraud"'),
    "reflection": (["--reflection", "blinn-phong"], "blinn-phong", "blinn-phong", '[shading]\nreflection = "blinn-phong"'),
    "blinn_exponent_scale": (["--reflection", "blinn-phong", "--blinn-exponent-scale", "0.25"], "0.25", 0.25,
                             "[shading]\nblinn_exponent_scale = 0.25"),
    "local_viewer": (["--infinite-viewer"], "false", False, "[shading]\nlocal_viewer = false"),
    "two_sided": (["--two-sided"], "true", True, "[shading]\ntwo_sided = true"),
    "clamp_vertex_colors": (["--clamp-vertex-colors"], "true", True, "[shading]\nclamp_vertex_colors = true"),
    "color_space": (["--color-space", "linear"], "linear", "linear", '[shading]\ncolor_space = "linear"'),
    "crease_angle": (["--crease-angle", "120"], "120", 120.0, "OBJECT crease_angle = 120"),
    "up": (["--up", "+Z"], "+Z", "+Z", 'OBJECT up = "+Z"'),
    "camera_position": (["--camera-position", "2,1,5"], "2 1 5", (2.0, 1.0, 5.0), "[camera]\neye = [2, 1, 5]"),
    "camera_focal_point": (["--camera-focal-point", "0.3,0.2,0.1"], "0.3 0.2 0.1", (0.3, 0.2, 0.1), "[camera]\ntarget = [0.3, 0.2, 0.1]"),
    "camera_direction": (["--camera-direction=-1,-1,-1"], "-1 -1 -1", (-1.0, -1.0, -1.0), "[camera]\ndirection = [-1, -1, -1]"),
    "camera_view_up": (["--camera-view-up", "1,1,0"], "1 1 0", (1.0, 1.0, 0.0), "[camera]\nup = [1, 1, 0]"),
    "camera_view_angle": (["--camera-view-angle", "30"], "30", 30.0, "[camera]\nfov_y = 30"),
    "camera_near": (["--camera-near", "5.0"], "5.0", 5.0, "[camera]\nnear = 5.0"),
    "camera_far": (["--camera-far", "5.5"], "5.5", 5.5, "[camera]\nfar = 5.5"),
    "camera_projection": (["--camera-orthographic"], "orthographic", "orthographic", '[camera]\nprojection = "orthographic"'),
    "camera_ortho_height": (["--camera-ortho-height", "8"], "8", 8.0, '[camera]\nprojection = "orthographic"\northo_height = 8'),
    "camera_azimuth": (["--camera-azimuth-angle", "40"], "40", 40.0, "[camera]\nazimuth = 40"),
    "camera_elevation": (["--camera-elevation-angle=-30"], "-30", -30.0, "[camera]\nelevation = -30"),
    "camera_distance": (["--camera-distance", "9"], "9", 9.0, "[camera]\ndistance = 9"),
    "lights": (["--light", "directional:dir=-1,-1,-1:color=1,0.5,0.5"], "directional:dir=-1,-1,-1:color=1,0.5,0.5",
               ("directional:dir=-1,-1,-1:color=1,0.5,0.5",),
               "[[lights]]\ntype = \"directional\"\ndirection = [-1, -1, -1]\ndiffuse = [1, 0.5, 0.5]\nspecular = [1, 0.5, 0.5]"),
    # glTF files' own lights (tests/test_gltf_lights.py): nothing to change on an OBJ box or in a scene file
    "viewer_lights": (["--viewer-lights"], "true", True, ""),
}
_NO_EFFECT_ON_THE_BOX = ("two_sided", "clamp_vertex_colors", "viewer_lights")
BOX = "".join(f"v {x} {y} {z}\n" for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-1.5, 1.5)) + "".join(
    f"f {a} {b} {c}\n" for a, b, c in ((1, 2, 4), (1, 4, 3), (5, 7, 8), (5, 8, 6), (1, 5, 6), (1, 6, 2),
                                       (3, 4, 8), (3, 8, 7), (1, 3, 7), (1, 7, 5), (2, 6, 8), (2, 8, 4))
)


@pytest.fixture(scope="module")
def box(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("box") / "box.obj"
    path.write_text(BOX)
    return path


HEADS = {
    "render": ["render", "x.obj"],
    "batch": ["batch", "--meshes", "x.obj", "-o", "out"],
    "turntable": ["turntable", "x.obj"],
    "check": ["check", "x.obj", "--ref", "r.png"],
    "shader": ["shader", "x.obj"],
}


def _parse(command: str, words: list[str]):
    return view_options_from_args(build_parser().parse_args(HEADS[command] + words))


def test_every_option_has_a_sample_and_four_spellings():
    assert set(SAMPLES) == {option.name for option in VIEW_OPTIONS}
    for option in VIEW_OPTIONS:
        assert option.all_flags and option.column and option.scene_key and option.help, option.name


@pytest.mark.parametrize("option", VIEW_OPTIONS, ids=lambda option: option.name)
def test_render_flag_batch_flag_and_manifest_column_read_the_same_value(option):
    words, cell, value, _ = SAMPLES[option.name]
    for command in HEADS:  # every command that renders takes every view flag
        assert getattr(_parse(command, words), option.name) == value, command
    assert getattr(row_view_options({option.column: cell}, "row"), option.name) == value
    # every flag of the option is accepted by both commands (aliases included)
    for flag in option.all_flags:
        for command in ("render", "batch"):
            arguments = [flag] if any(flag == f for f, _, _ in option.switches) else [f"{flag}={cell}"]
            assert getattr(_parse(command, arguments), option.name) is not None, (command, flag)


def _scene_file(folder: Path, extra: str) -> Path:
    """The box as a scene file with one option's key: "OBJECT key = value" goes on the
    object, other text before it."""
    object_keys = {"mesh": '"box.obj"', "material": '"gold"'}
    top = ""
    if extra.startswith("OBJECT "):
        key, _, value = extra.removeprefix("OBJECT ").partition(" = ")
        object_keys[key] = value
    else:
        top = extra
    path = folder / f"scene-{hashlib.sha1(extra.encode()).hexdigest()[:8]}.toml"
    path.write_text(top + "\n[[objects]]\n" + "".join(f"{key} = {value}\n" for key, value in object_keys.items()))
    return path


def _view(scene) -> tuple:
    """What a scene draws, minus mesh identity: comparable with ==."""
    objects = tuple((o.part_materials(), o.up, o.translate, o.rotate, o.scale, o.mesh.normals.tobytes()) for o in scene.objects)
    return scene.camera, scene.shading, scene.lights, scene.size, scene.samples, scene.background, objects


@pytest.mark.parametrize("option", VIEW_OPTIONS, ids=lambda option: option.name)
def test_the_scene_file_key_means_what_the_option_means(option, box):
    _, _, value, toml = SAMPLES[option.name]
    with_key = load_scene(_scene_file(box.parent, toml))
    with_option = load_view(str(_scene_file(box.parent, "")), ViewOptions(**{option.name: value}))
    assert _view(with_key) == _view(with_option)
    assert _view(with_key) != _view(load_scene(_scene_file(box.parent, ""))) or option.name in ("crease_angle", "viewer_lights")


def _pixels(path: Path) -> np.ndarray:
    return np.asarray(Image.open(path))


@pytest.mark.parametrize("option", VIEW_OPTIONS, ids=lambda option: option.name)
def test_render_and_a_one_job_batch_draw_the_same_pixels(option, box, tmp_path):
    words = SAMPLES[option.name][0]
    size = [] if option.name == "size" else ["--size", "48"]
    if option.name in ("frequency", "reflection", "local_viewer"):
        size += ["--crease-angle", "180"]  # a smooth box: the shading options show
    assert main(["render", str(box), *size, *words, "-o", str(tmp_path / "render.png"), "-q"]) == 0
    assert main(["batch", "--meshes", str(box), "--views", "1", *size, *words, "-o", str(tmp_path / "batch"), "-q"]) == 0
    rendered = _pixels(tmp_path / "render.png")
    assert np.array_equal(rendered, _pixels(tmp_path / "batch" / "box" / "view_000.png"))
    plain = tmp_path / "plain.png"
    assert main(["render", str(box), *size, "-o", str(plain), "-q"]) == 0
    if option.name not in _NO_EFFECT_ON_THE_BOX:  # a closed box without vertex colours or file lights
        assert not np.array_equal(rendered, _pixels(plain)), "the sample value should change the picture"


def test_a_manifest_row_per_option_draws_what_render_draws(box, tmp_path):
    options = [option for option in VIEW_OPTIONS if option.name != "size"]
    columns = sorted({option.column for option in options} | {"reflection"})
    lines = [",".join(["mesh", "name", "size", *columns])]
    for option in options:
        row = {option.column: SAMPLES[option.name][1]}
        if option.name == "blinn_exponent_scale":
            row["reflection"] = "blinn-phong"
        lines.append(",".join([str(box), option.name, "40x32", *(f'"{row.get(c, "")}"' for c in columns)]))
    manifest = tmp_path / "jobs.csv"
    manifest.write_text("\n".join(lines) + "\n")
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "-q"]) == 0
    for option in options:
        output = tmp_path / f"{option.name}.png"
        assert main(["render", str(box), "--size", "40x32", *SAMPLES[option.name][0], "-o", str(output), "-q"]) == 0
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
    assert spellings_table() in text, "docs/view-options.md: paste spellings_table()'s output (python -m wgpu_shading.scene.view_options)"


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
