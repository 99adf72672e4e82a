"""docs/valid-ranges.md is the one list of valid ranges; these tests keep it true.

- Every constant the table names holds the bounds written beside it.
- Every range with a probe below is tried against the code that checks it: accepted at each
  end it includes, refused at each end it leaves out and just beyond each end.
- Every `MAX_`/`MIN_` constant of the package is named in the table, unless NOT_USER_VALUES
  says why it is not a user's value.
- Every `a..b` range quoted in the command line's --help or in docs/scene-files.md is a
  range of the table (so a quote cannot drift from it)."""

from __future__ import annotations

import ast
import contextlib
import importlib
import io
import math
import re
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, SceneError, load_mesh
from wgpu_shading.errors import UsageError
from wgpu_shading.scene import (
    Camera,
    DirectionalLight,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    ShadowSettings,
    SpotLight,
    Texture,
    builtin,
)

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "valid-ranges.md"
REFUSED = (SceneError, MeshError, UsageError)

# MAX_/MIN_ constants that bound no value a user gives, and why.
NOT_USER_VALUES = {
    "MAX_PENDING_WRITES": "dataset/chunk.py: frames waiting for the PNG encoder, an internal queue",
    "MAX_ENCODER_THREADS": "dataset/chunk.py: the cap of the encoder threads made from the core count, not a user value",
    "MIN_DISTANCE_FRACTION": "live/navigation.py: how close a dolly may bring the eye, not an input",
    "MAX_DOLLY_EXPONENT": "live/navigation.py: the zoom of one scroll event, not an input",
    "MIN_SHININESS": "live/state.py: where the viewer's shininess keys stop, not a validity range",
    "MAX_SHININESS": "live/state.py: where the viewer's shininess keys stop, not a validity range",
    "MIN_LENGTH_SQUARED": "study/reference: the float64 reference's guard (docs/hard-cases.md)",
    "MIN_ATTENUATION_DENOMINATOR": "study/reference: the float64 reference's guard (docs/hard-cases.md)",
    "MAX_HITS_PER_RAY": "study/reference: the reference's ray cast counts a ray through more surfaces as shadowed",
    "MAX_DISPLACEMENT_P99": "study/shadows: the shadow check's acceptance threshold, not an input",
    "MAX_UNRELATED_FRACTION": "study/shadows: the shadow check's acceptance threshold, not an input",
    "MAX_JOINT_LIGHTS": "study/shadows: how many lights the shadow check tells apart at once, not an input",
    "MAX_SINGLE_VIEW_TAN": "render/passes/shadow_views.py: where a spot's map becomes a cube map, not an input",
    "MAX_RANGES": "scene/geometry/corner_ids.py: how many passes the crease analysis makes over its ids, not an input",
    "MIN_DECODED_TEXT": "assets/gltf/data_uris.py: which data: URIs are decoded before json.loads; the bytes are the same either way",
    "MIN_FILE_BYTES": "assets/mesh_cache.py: which mesh files the cache keeps; the Mesh is the same either way",
    "MIN_TRIANGLES": "render/gpu/order_cache.py: which vertex-cache orders the cache keeps; the order is the same either way",
}


class Row:
    """One line of the table: its key (the first `code` of the first column), its range and constants."""

    def __init__(self, cells: list[str]):
        self.key = re.search(r"`([^`]+)`", cells[0]).group(1)
        self.text = cells[1]
        self.range = re.search(r"`([^`]+)`", cells[1]).group(1)
        self.whole = "whole" in cells[1]
        self.constants = re.findall(r"`([A-Z][A-Z0-9_]+)`", cells[2])

    def bounds(self) -> tuple[float, float, bool, bool]:
        """(low, high, low included, high included); a one-sided range has ∓inf at its open side."""
        if match := re.fullmatch(r"([\[(])(.+), (.+)([\])])", self.range):
            return number(match[2]), number(match[3]), match[1] == "[", match[4] == "]"
        if match := re.fullmatch(r"≤ (.+)", self.range):
            return -math.inf, number(match[1]), False, True
        if match := re.fullmatch(r"≥ (.+)", self.range):
            return number(match[1]), math.inf, True, False
        raise AssertionError(f"docs/valid-ranges.md: cannot read the range {self.range!r} of {self.key}")

    def numbers(self) -> set[float]:
        if self.range.startswith("{"):
            return {number(item) for item in self.range.strip("{}").split(",")}
        return {bound for bound in self.bounds()[:2] if math.isfinite(bound)}


def number(text: str) -> float:
    """1e6, 16384, 2^25, 2 GiB, 16 MiB: the notations the table uses."""
    text = text.strip()
    if match := re.fullmatch(r"(\d+)\^(\d+)", text):
        return float(int(match[1]) ** int(match[2]))
    if match := re.fullmatch(r"(\d+) (KiB|MiB|GiB)", text):
        return float(int(match[1]) << {"KiB": 10, "MiB": 20, "GiB": 30}[match[2]])
    return float(text)


def _rows() -> list[Row]:
    lines = [line for line in PAGE.read_text(encoding="utf-8").splitlines() if line.startswith("| `")]
    return [Row([cell.strip() for cell in line.strip().strip("|").split("|")]) for line in lines]


ROWS = {row.key: row for row in _rows()}


def _constant_modules() -> dict[str, str]:
    """Every top-level MAX_*/MIN_* name of the package → the module that assigns it."""
    found = {}
    for path in sorted((ROOT / "wgpu_shading").rglob("*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(node, ast.AnnAssign) else []
            for target in targets:
                for name in target.elts if isinstance(target, ast.Tuple) else [target]:
                    if isinstance(name, ast.Name) and re.fullmatch(r"(MAX|MIN)_[A-Z0-9_]+", name.id):
                        module = ".".join(path.relative_to(ROOT).with_suffix("").parts)
                        found.setdefault(name.id, module)
    return found


CONSTANTS = _constant_modules()


def test_the_table_is_read():
    assert len(ROWS) >= 40 and ROWS["camera.fov_y"].bounds() == (1e-6, 180.0, True, False)
    assert ROWS["mesh"].numbers() == {2.0**25} and ROWS["output.samples"].numbers() == {1.0, 4.0}


@pytest.mark.parametrize("row", [row for row in ROWS.values() if row.constants], ids=lambda row: row.key)
def test_named_constants_hold_the_bounds_written(row):
    for name in row.constants:
        if name == "SAMPLE_COUNTS":
            value = importlib.import_module("wgpu_shading.scene.objects").SAMPLE_COUNTS
        else:
            assert name in CONSTANTS, f"docs/valid-ranges.md names {name}, which the package no longer defines"
            value = getattr(importlib.import_module(CONSTANTS[name]), name)
        values = set(map(float, value)) if isinstance(value, tuple) else {float(value)}
        assert values <= row.numbers(), f"{row.key}: {name} = {value!r}, the table says {row.range}"


def test_every_limit_constant_is_in_the_table():
    named = {name for row in ROWS.values() for name in row.constants}
    missing = sorted(set(CONSTANTS) - named - set(NOT_USER_VALUES))
    assert not missing, "add these limits to docs/valid-ranges.md (or to NOT_USER_VALUES with a reason): " + ", ".join(
        f"{name} ({CONSTANTS[name]})" for name in missing)
    assert not set(NOT_USER_VALUES) - set(CONSTANTS), "NOT_USER_VALUES names constants that no longer exist"


_CUBE = builtin("builtin:cube")

# key → a call that raises SceneError/MeshError/UsageError when its argument is out of range.
PROBES = {
    "color": lambda x: PositionalLight(diffuse=(x, 0.0, 0.0, 1.0)),
    "alpha": lambda x: Material(diffuse=(1.0, 1.0, 1.0, x)),
    "output.background": lambda x: Scene(background=(x, 0.0, 0.0, 1.0)),
    "position": lambda x: PositionalLight(position=(x, 0.0, 0.0)),
    "direction": lambda x: DirectionalLight(direction=(x, 0.0, 0.0)),
    "material.shininess": lambda x: Material(shininess=x),
    "material.alpha_cutoff": lambda x: Material(alpha_cutoff=x),
    "material.normal_scale": lambda x: (Material(normal_scale=x), Material(bump_scale=x)),
    "material.occlusion_strength": lambda x: Material(occlusion_strength=x),
    "light.exponent": lambda x: SpotLight(exponent=x),
    "light.cutoff": lambda x: SpotLight(cutoff=x),
    "light.attenuation": lambda x: PositionalLight(attenuation=(1.0, x, 0.0)),
    "light.range": lambda x: PositionalLight(range=x),
    "shading.blinn_exponent_scale": lambda x: Shading(blinn_exponent_scale=x),
    "shading.point_size": lambda x: (Shading(point_size=x), Shading(line_width=x), Shading(edge_width=x)),
    "shading.edge_color": lambda x: Shading(edge_color=(x, 0.0, 0.0, 1.0)),
    "texture.uv_set": lambda x: Texture(np.zeros((1, 1, 3), np.uint8), uv_set=int(x)),
    "camera.fov_y": lambda x: Camera(fov_y=x),
    "camera.ortho_height": lambda x: Camera(projection="orthographic", ortho_height=x),
    "camera.near": lambda x: Camera(near=x, far=1.0),
    "camera.far / camera.near": lambda x: Camera(near=1.0, far=x),
    "object.scale": lambda x: SceneObject(_CUBE, scale=(x, 1.0, 1.0)),
    "output.size": lambda x: Scene(size=(int(x), 1)),
    "output.samples": lambda x: Scene(samples=int(x)),
    "lights": lambda x: Scene(lights=(PositionalLight(),) * int(x)),
    "objects": lambda x: Scene(objects=(SceneObject(_CUBE),) * int(x)),
    "shadows.map_size": lambda x: ShadowSettings(map_size=int(x)),
    "shadows.bias": lambda x: ShadowSettings(bias=x),
    "crease_angle": lambda x: load_mesh(ROOT / "tests" / "data" / "real" / "smoothing_off.obj", crease_angle=x),
    "builtin": lambda x: builtin(f"builtin:sphere?radius={x!r}&slices=6&stacks=3"),
    "texture": lambda x: Texture(np.zeros((1, int(x), 3), np.uint8)),
    "batch --views": lambda x: __import__("wgpu_shading.dataset.views", fromlist=["turntable_views"]).turntable_views(int(x)),
}


def _accepted(probe, value: float) -> bool:
    try:
        probe(value)
    except REFUSED:
        return False
    return True


def _beyond(bound: float, outward: float, whole: bool) -> float:
    """A value just past `bound` in the direction `outward` (+1 above, −1 below)."""
    if whole:
        return bound + outward
    return bound + outward * (abs(bound) * 1e-6 if bound else 1e-9)


@pytest.mark.parametrize("key", sorted(PROBES))
def test_the_code_accepts_and_refuses_what_the_table_says(key):
    assert key in ROWS, f"docs/valid-ranges.md has no row {key!r} any more"
    row, probe = ROWS[key], PROBES[key]
    if row.range.startswith("{"):
        members = row.numbers()
        for member in members:
            assert _accepted(probe, member), f"{key}: {member:g} is in {row.range} but refused"
            for neighbour in (member - 1, member + 1):
                if neighbour not in members:
                    assert not _accepted(probe, neighbour), f"{key}: {neighbour:g} is not in {row.range} but accepted"
        return
    low, high, low_in, high_in = row.bounds()
    for bound, included, outward in ((low, low_in, -1.0), (high, high_in, +1.0)):
        if not math.isfinite(bound):
            continue
        assert _accepted(probe, bound) == included, f"{key}: {bound:g} should be {'accepted' if included else 'refused'} ({row.range})"
        assert not _accepted(probe, _beyond(bound, outward, row.whole)), f"{key}: just beyond {bound:g} accepted ({row.range})"
        inside = _beyond(bound, -outward, row.whole)
        assert _accepted(probe, inside), f"{key}: {inside:g}, just inside {row.range}, refused"


# `a..b` in the texts checked below that is not a valid range, and what it is instead.
NOT_VALID_RANGES = {(1.0, 65535.0): "the 16-bit depth PNG's values (docs/conventions.md), an encoding"}


def _quoted_ranges(text: str) -> set[tuple[float, float]]:
    return {(number(a), number(b)) for a, b in re.findall(r"(?<![\w.])(-?\d[\d.e+-]*)\.\.<?(-?\d[\d.e+-]*)", text)}


def _help_texts() -> str:
    """`wgpu-shading --help` and every command's --help, as a user reads them."""
    from wgpu_shading.cli.main import build_parser

    texts = [build_parser().format_help()]
    for command in re.findall(r"^    (\w[\w-]*)", texts[0], flags=re.MULTILINE):  # the COMMAND list
        output = io.StringIO()
        with contextlib.redirect_stdout(output), pytest.raises(SystemExit):
            build_parser().parse_args([command, "--help"])
        texts.append(output.getvalue())
    assert len(texts) > 5, texts[0]
    return "\n".join(texts)


def test_ranges_quoted_elsewhere_are_the_tables():
    table = {tuple(sorted(row.numbers()))[:2] for row in ROWS.values() if len(row.numbers()) == 2}
    quoted = _quoted_ranges(_help_texts()) | _quoted_ranges((ROOT / "docs" / "scene-files.md").read_text(encoding="utf-8"))
    assert quoted, "no range quoted: the check would be vacuous"
    quoted -= set(NOT_VALID_RANGES)
    assert not quoted - table, f"ranges quoted in --help or docs/scene-files.md that docs/valid-ranges.md does not give: {sorted(quoted - table)}"
