"""The shipped examples (`example:NAME`): sample meshes and scenes that work from any folder,
and a clear error for the example scenes whose models are not shipped."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading.assets import load_mesh, load_scene
from wgpu_shading.assets.examples import example_names, examples_folder
from wgpu_shading.cli import main
from wgpu_shading.errors import SceneError

REPOSITORY_EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_every_example_of_the_repository_is_installed():
    shipped = {p.name for p in REPOSITORY_EXAMPLES.iterdir() if p.suffix in (".toml", ".obj", ".ply", ".glb")}
    assert shipped and shipped == set(example_names())
    assert (examples_folder() / "LICENSE.md").is_file()


def test_sample_meshes_are_small_closed_and_load_by_name():
    total = sum(p.stat().st_size for p in REPOSITORY_EXAMPLES.iterdir() if p.suffix in (".obj", ".ply", ".glb"))
    assert total <= 2 * 2**20
    knot = load_mesh("example:knot.obj")
    gear = load_mesh("example:gear.ply")
    assert knot.triangle_count == 6480 and gear.triangle_count == 14 * 4 * 8
    # Outward winding: the smooth normals (from the winding) point away from the knot's middle
    # on its outer rim (the vertices farthest from the Z axis).
    radial = np.hypot(knot.positions[:, 0], knot.positions[:, 1])
    rim = radial > 0.95 * radial.max()
    outward = np.sum(knot.normals[rim, :2] * knot.positions[rim, :2], axis=1)
    assert np.all(outward > 0)


def test_example_scene_loads_from_another_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert load_scene("example:gold_torus_phong.toml").objects[0].material.name == "gold"


def test_unknown_example_suggests_the_name(capsys):
    assert main(["render", "example:knot", "-o", "x.png"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "did you mean 'example:knot.obj'?" in err


def test_example_needing_the_model_collection_says_where_to_get_it(tmp_path, capsys):
    folder = tmp_path / "a" / "b"
    folder.mkdir(parents=True)
    shutil.copy(REPOSITORY_EXAMPLES / "suzanne_inverse_square.toml", folder)
    with pytest.raises(SceneError, match=r"common-3d-test-models.*shared/models"):
        load_scene(folder / "suzanne_inverse_square.toml")
    assert main(["render", str(folder / "suzanne_inverse_square.toml"), "-o", str(tmp_path / "s.png")]) == 2
    assert "github.com/alecjacobson/common-3d-test-models" in capsys.readouterr().err
