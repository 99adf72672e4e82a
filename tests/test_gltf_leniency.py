"""What the glTF specification asks a reader to accept (issue 27), from the cases the
glTF-Validator keeps in its own test corpus: integers written as `1.0` (JSON has one number
type; json/integer_written_as_float.gltf), a primitive without POSITION skipped rather than
the whole file refused (mesh/primitive_no_position.gltf), and a lost texture said once, and
only when the file is drawn (not before the file's own error)."""

from __future__ import annotations

import itertools
import json
import re
import warnings

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from gltf_builder import quad, write_gltf
from wgpu_shading import MeshError, load_mesh


def _two_quads(tmp_path, name="q.gltf", **extra):
    positions, indices = quad(0, 0)
    primitive = {"positions": positions, "indices": indices}
    return write_gltf(tmp_path / name, [[primitive, {**primitive, "positions": positions + [2, 0, 0]}]], **extra)


def _rewrite(path, change):
    document = json.loads(path.read_text())
    change(document)
    path.write_text(json.dumps(document))
    return path


def test_integers_written_as_floats_are_integers(tmp_path):
    # every index and count of the file written 1.0, 2e0, 10e-1, 0.1e1 ... as the validator's case
    reference = load_mesh(_two_quads(tmp_path, "plain.gltf"))
    path = _two_quads(tmp_path)
    text = path.read_text()
    document = json.loads(text)

    def floats(value, key=""):
        if isinstance(value, dict):
            return {k: floats(v, k) for k, v in value.items()}
        if isinstance(value, list):
            return [floats(v, key) for v in value]
        if isinstance(value, int) and not isinstance(value, bool) and key not in ("min", "max"):
            return f"@{value}@"  # replaced below by exotic spellings of the same integer
        return value

    spellings = itertools.cycle(["{}.0", "{}e0", "{}0e-1", "{}.0e0"])

    def spell(match):  # 3 → 3.0, 3e0, 30e-1, 3.0e0 in turn (0 → 0.0: JSON has no 00e-1)
        spelling = next(spellings)
        return "0.0" if match.group(1) == "0" else spelling.format(match.group(1))

    spelled = re.sub(r'"@(-?\d+)@"', spell, json.dumps(floats(document)))
    assert "0e-1" in spelled and "e0" in spelled
    path.write_text(spelled)
    mesh = load_mesh(path)
    np.testing.assert_array_equal(mesh.world_positions(), reference.world_positions())
    assert mesh.triangle_count == reference.triangle_count == 4


@pytest.mark.parametrize("field, value, words", [
    ("indices", 1.5, ["meshes[0].primitives[0].indices", "1.5"]),
    ("count", 2.5, ["accessors[0].count", "2.5"]),
])
def test_a_fractional_index_or_count_is_an_error_naming_the_field(tmp_path, capsys, field, value, words):
    def change(document):
        if field == "indices":
            document["meshes"][0]["primitives"][0]["indices"] = value
        else:
            document["accessors"][0]["count"] = value

    path = _rewrite(_two_quads(tmp_path), change)
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "q.gltf", *words)


def test_a_primitive_without_position_is_skipped_with_a_warning_naming_it(tmp_path):
    path = _rewrite(_two_quads(tmp_path), lambda d: d["meshes"][0]["primitives"][1]["attributes"].pop("POSITION"))
    with pytest.warns(UserWarning, match=r"q.gltf: meshes\[0\].primitives\[1\] has no POSITION attribute; skipped") as caught:
        mesh = load_mesh(path)
    assert len(caught) == 1
    assert mesh.triangle_count == 2  # the other primitive is drawn
    np.testing.assert_allclose(mesh.bounds(), [[0, 0, 0], [1, 1, 0]])


def test_a_file_whose_only_primitive_lacks_position_still_says_why(tmp_path):
    positions, indices = quad(0, 0)
    path = write_gltf(tmp_path / "q.gltf", [[{"positions": positions, "indices": indices}]])
    _rewrite(path, lambda d: d["meshes"][0]["primitives"][0]["attributes"].pop("POSITION"))
    with pytest.warns(UserWarning, match="has no POSITION"), pytest.raises(MeshError, match="contains no triangles"):
        load_mesh(path)


def _textured(tmp_path, primitives=2):
    positions, indices = quad(0, 0)
    uvs = positions[:, :2]
    primitive = {"positions": positions, "indices": indices, "uvs": uvs, "material": 0}
    return write_gltf(tmp_path / "t.gltf", [[{**primitive, "positions": positions + [2 * k, 0, 0]} for k in range(primitives)]],
                      materials=[{"name": "skin", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                      extra={"images": [{"uri": "missing.png"}], "textures": [{"source": 0}]})


def test_a_missing_texture_is_said_once_however_many_primitives_use_it(tmp_path, capsys):
    path = _textured(tmp_path, primitives=3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_mesh(path)
    assert [str(w.message) for w in caught] == ["t.gltf: material 'skin': its base colour texture could not be read; drawn untextured"]
    from wgpu_shading.cli.main import main

    assert main(["render", str(path), "-o", str(tmp_path / "out.png"), "--size", "16", "-q"]) == 0
    assert capsys.readouterr().err.count("could not be read") == 1


def test_a_missing_texture_is_not_said_before_the_files_own_error(tmp_path, capsys):
    path = _textured(tmp_path)
    # the second primitive's material is broken: the file is refused, the texture is moot
    path = _rewrite(path, lambda d: (d["materials"].append({"emissiveFactor": [1e39, 0, 0]}),
                                     d["meshes"][0]["primitives"][1].update(material=1)))
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    one_line_error(code, err, "t.gltf", "material.emission")
