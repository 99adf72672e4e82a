"""The WGSL preprocessor and the feature-specialized shaders: code and uniforms exist only
for the effects a scene uses, and every specialization compiles."""

from __future__ import annotations

import dataclasses
import itertools
import math
import random
import re

import pytest

from wgpu_shading.render.features import FeatureSet
from wgpu_shading.scene import FREQUENCIES, REFLECTIONS, SHADOW_FILTERS, TEXTURE_MODES
from wgpu_shading.scene.material import ALPHA_MODES
from wgpu_shading.render.shaders.preprocess import ShaderSourceError, preprocess
from wgpu_shading.render.shaders.shadergen import generate_wgsl

FILES = {
    "main.wgsl": '#include "part.wgsl"\n#include "part.wgsl"\nmain\n',
    "part.wgsl": "part\n",
    "cond.wgsl": "#if A and not B\nab\n#elif B\nb\n#else\nneither\n#endif\n#if COUNT > 1\nmany\n#endif\nend\n",
    "nested.wgsl": "#if A\nouter\n#if B\ninner\n#endif\n#else\nelse\n#endif\n",
    "typo.wgsl": "#if SPOTLIGHTS\nx\n#endif\n",
    "open.wgsl": "#if A\nx\n",
}


def run(name: str, **defines: int) -> list[str]:
    values = {"A": 0, "B": 0, "COUNT": 0, **defines}
    return preprocess(name, values, FILES.__getitem__).split()


def test_include_pastes_a_file_once():
    assert run("main.wgsl") == ["part", "main"]


@pytest.mark.parametrize(
    "defines, expected",
    [
        ({"A": 1}, ["ab", "end"]),
        ({"A": 1, "B": 1}, ["b", "end"]),
        ({}, ["neither", "end"]),
        ({"COUNT": 2}, ["neither", "many", "end"]),
    ],
)
def test_conditionals(defines, expected):
    assert run("cond.wgsl", **defines) == expected


def test_nested_conditionals():
    assert run("nested.wgsl", A=1, B=1) == ["outer", "inner"]
    assert run("nested.wgsl", A=1) == ["outer"]
    assert run("nested.wgsl", B=1) == ["else"]


def test_unknown_feature_names_are_errors_not_false():
    with pytest.raises(ShaderSourceError, match="unknown feature name 'SPOTLIGHTS'"):
        run("typo.wgsl")


def test_unclosed_if_is_an_error():
    with pytest.raises(ShaderSourceError, match="not closed"):
        run("open.wgsl", A=1)


# #for: what each of COUNT lights needs, written out once per light (WGSL has no arrays of
# interstage variables), with its own #if inside.
LOOP_FILES = {
    "loop.wgsl": "#for LIGHT < COUNT\n@location({{5 + 4 * LIGHT}}) share_{{LIGHT}}\n#if A\nsplit_{{LIGHT}}\n#endif\n#endfor\nend\n",
    "nested_loop.wgsl": "#for I < COUNT\n#for J < COUNT\n#endfor\n#endfor\n",
    "open_loop.wgsl": "#for I < COUNT\nx\n",
    "stray_endfor.wgsl": "#endfor\n",
    "typo_loop.wgsl": "#for I < LIGHTCOUNT\nx\n#endfor\n",
    "bad_expression.wgsl": "#for I < COUNT\n{{I / 2}}\n#endfor\n",
}


def run_loop(name: str, **defines: int) -> list[str]:
    return preprocess(name, {"A": 0, "COUNT": 0, **defines}, LOOP_FILES.__getitem__).split("\n")


def test_a_loop_is_written_out_once_per_count_with_its_conditionals():
    assert run_loop("loop.wgsl") == ["end"]
    assert run_loop("loop.wgsl", COUNT=2) == ["@location(5) share_0", "@location(9) share_1", "end"]
    assert run_loop("loop.wgsl", COUNT=2, A=1) == ["@location(5) share_0", "split_0", "@location(9) share_1", "split_1", "end"]


@pytest.mark.parametrize("name, message", [
    ("nested_loop.wgsl", "loop.wgsl:2: #for inside a #for"),
    ("open_loop.wgsl", "open_loop.wgsl:1: #for not closed"),
    ("stray_endfor.wgsl", "#endfor without #for"),
    ("typo_loop.wgsl", "unknown feature name 'LIGHTCOUNT'"),
    ("bad_expression.wgsl", "expected an integer expression of I"),
])
def test_malformed_loops_are_errors(name, message):
    with pytest.raises(ShaderSourceError, match=message):
        run_loop(name, COUNT=2)


def _code(features: FeatureSet) -> str:
    """The generated WGSL without comments (comments may mention absent features)."""
    return re.sub(r"//[^\n]*", "", generate_wgsl(features))


BASE = FeatureSet(frequency="phong", reflection="phong", positional_lights=1)


@pytest.mark.parametrize(
    "feature, words",
    [
        ({"spot_lights": 1}, ["SpotLight", "spot_lights", "cutoff_chord_squared"]),
        ({"directional_lights": 1}, ["DirectionalLight", "directional_lights"]),
        ({"attenuation": True}, ["attenuation"]),
        ({"emission": True}, ["emission"]),
        ({"texture_mode": "modulate"}, ["textureSample", "base_color_texture", "base_color_sampler", "uv"]),
        ({"two_sided": True}, ["front_facing"]),
        ({"reflection": "blinn-phong"}, ["blinn_exponent_scale", "half_vector"]),
        ({"positional_shadows": 1, "shadow_filter": "nearest"},
         ["shadow_maps", "ShadowUniforms", "shadow_position_0", "outward_normal", "light_visible", "textureLoad", "front_facing", "dpdx"]),
        ({"positional_shadows": 1, "shadow_filter": "pcf3"}, ["shadow_sampler", "textureSampleCompareLevel"]),
        ({"positional_shadows": 1, "shadow_filter": "nearest", "frequency": "gouraud"}, ["front_share_0", "light_switched_off"]),
    ],
)
def test_each_feature_brings_its_code_and_only_then(feature, words):
    without = _code(BASE)
    with_feature = _code(FeatureSet(**{**BASE.__dict__, **feature}))
    for word in words:
        assert word not in without, f"{word!r} is in a shader that does not use {feature}"
        assert word in with_feature, f"{word!r} is missing from a shader that uses {feature}"


def test_no_shadow_code_without_shadows():
    """Only what the scene calls for: every feature set of the covering set without shadow
    fields (a draw that receives none) has no word of the shadow chunks, not even a blank
    line from them (the same bytes as before shadows existed: checked once against the
    sources before shadows, 82 feature sets, identical)."""
    domains = {name: values for name, values in field_domains().items() if "shadow" not in name}
    for row in covering_rows(domains, 2):
        code = _code(FeatureSet(**row))  # (comments may mention what a shadow would do)
        assert "shadow" not in code.lower() and "light_visible" not in code, FeatureSet(**row).describe()
    # a shadow filter without a casting light is no shadow either
    assert generate_wgsl(FeatureSet(positional_lights=1, shadow_filter="pcf3")) == generate_wgsl(FeatureSet(positional_lights=1))


def test_no_specular_code_without_specular():
    code = _code(FeatureSet(frequency="phong", directional_lights=1, specular=False))
    for word in ("specular_factor", "reflect(", "pow(", "lit.specular"):
        assert word not in code
    assert "reflect(" in _code(FeatureSet(frequency="phong", directional_lights=1, specular=True))


def test_local_viewer_code_only_for_local_viewer():
    assert "-eye_position" in _code(BASE)
    infinite = _code(FeatureSet(**{**BASE.__dict__, "local_viewer": False}))
    assert "-eye_position" not in infinite and "vec3<f32>(0.0, 0.0, 1.0)" in infinite


def test_light_counts_become_constants():
    source = generate_wgsl(FeatureSet(directional_lights=2, positional_lights=3, spot_lights=1))
    assert "const DIRECTIONAL_LIGHT_COUNT: u32 = 2u;" in source
    assert "const POSITIONAL_LIGHT_COUNT: u32 = 3u;" in source
    assert "const SPOT_LIGHT_COUNT: u32 = 1u;" in source
    assert "LIGHT_COUNT" not in generate_wgsl(FeatureSet())


def test_generated_source_names_its_feature_set():
    assert generate_wgsl(BASE).startswith("// wgpu-shading generated shader: frequency=phong")


# The values each FeatureSet field is compiled with. A bool field needs no entry; any other
# field must have one here, or the test below fails naming it (so a new field is never
# silently left out, and fields are set by name, never by position).
DOMAINS: dict[str, tuple] = {
    "frequency": FREQUENCIES,
    "reflection": REFLECTIONS,
    "directional_lights": (0, 1, 3),
    "positional_lights": (0, 1, 3),
    "spot_lights": (0, 1, 2),
    "texture_mode": (None, *TEXTURE_MODES),
    "alpha_mode": ALPHA_MODES,
    "primitive": ("triangles", "points", "lines"),
    "under_edges": (0, 2),
    "uv_sets": ((), (("base_color", 1),), (("normal_map", 3), ("occlusion_map", 2), ("emissive_map", 1))),
    "directional_shadows": (0, 1),
    "spot_shadows": (0, 1),
    "positional_shadows": (0, 2),
    "shadow_filter": (None, *SHADOW_FILTERS),
}
STRENGTH = 3  # every combination of values of any 3 fields is compiled at least once


def field_domains() -> dict[str, tuple]:
    domains, missing = {}, []
    for field in dataclasses.fields(FeatureSet):
        if field.name in DOMAINS:
            domains[field.name] = tuple(DOMAINS[field.name])
        elif field.type in ("bool", bool):
            domains[field.name] = (False, True)
        else:
            missing.append(f"{field.name}: {field.type}")
    assert not missing, f"FeatureSet fields without a value domain (add them to DOMAINS): {missing}"
    assert set(DOMAINS) <= set(domains), f"DOMAINS names fields FeatureSet lacks: {set(DOMAINS) - set(domains)}"
    return domains


def covering_rows(domains: dict[str, tuple], strength: int, seed: int = 0) -> list[dict]:
    """A covering array: rows (field → value) such that every combination of values of any
    `strength` fields occurs in some row. Greedy: each row starts from a combination not yet
    covered and fills the other fields with the value that covers the most new ones."""
    names = list(domains)
    rng = random.Random(seed)
    uncovered = {
        tuple(zip(group, values))
        for group in itertools.combinations(names, strength)
        for values in itertools.product(*(range(len(domains[n])) for n in group))
    }
    rows = []
    while uncovered:
        row = dict(min(uncovered))
        for name in rng.sample(names, len(names)):
            if name in row:
                continue
            def gain(value: int) -> int:
                trial = {**row, name: value}
                return sum(
                    tuple((n, trial[n]) for n in group) in uncovered
                    for group in itertools.combinations(sorted(trial, key=names.index), strength)
                    if name in group
                )
            row[name] = max(range(len(domains[name])), key=lambda v: (gain(v), -v))
        uncovered -= {tuple((n, row[n]) for n in group) for group in itertools.combinations(names, strength)}
        rows.append({name: domains[name][row[name]] for name in names})
    return rows


def test_the_covering_set_covers_every_triple_of_fields():
    domains = field_domains()
    rows = covering_rows(domains, STRENGTH)
    for group in itertools.combinations(domains, STRENGTH):
        seen = {tuple(row[n] for n in group) for row in rows}
        assert len(seen) == math.prod(len(domains[n]) for n in group), group


def test_every_combination_compiles(renderer):
    """naga validates every specialization in a covering set over all FeatureSet fields
    (by name): every combination of values of any three fields compiles, which takes a few
    hundred shaders where the full product would take hundreds of thousands."""
    device = renderer.device
    rows = covering_rows(field_domains(), STRENGTH)
    for row in rows:
        features = FeatureSet(**row)
        try:
            device.create_shader_module(code=generate_wgsl(features))
        except Exception as error:  # noqa: BLE001 - name the feature set that failed
            raise AssertionError(f"{features.describe()} does not compile: {error}") from None
    assert len(rows) > 50


# Named points: a chunk puts lines #at a point; the shader's #hook of that point receives
# them, in include order, wherever the #hook is.
POINT_FILES = {
    "entry.wgsl": '#include "a.wgsl"\nbegin\n#hook entry.middle  // what goes here\nend\n#include "b.wgsl"\n',
    "a.wgsl": "declare_a\n#at entry.middle\nfrom_a\n#end\n#at other_entry.point\nelsewhere\n#end\n",
    "b.wgsl": "#if B\n#at entry.middle\nfrom_b\n#hook b.inner\n#end\n#at b.inner\ninner\n#end\n#endif\n",
    "twice.wgsl": "#hook x.point\n#hook x.point\n",
    "unclosed.wgsl": "#at x.point\nline\n",
    "stray_end.wgsl": "#end\n",
    "include_inside.wgsl": '#at x.point\n#include "a.wgsl"\n#end\n',
    "crossing.wgsl": "#if A\n#at x.point\n#endif\n#end\n",
}


def run_points(name: str, **defines: int) -> list[str]:
    return preprocess(name, {"A": 0, "B": 0, **defines}, POINT_FILES.__getitem__).split()


def test_lines_put_at_a_point_go_to_its_hook_in_include_order():
    assert run_points("entry.wgsl") == ["declare_a", "begin", "from_a", "end"]
    # b.wgsl is included after the hook; its lines still go there, and hold a point of their own
    assert run_points("entry.wgsl", B=1) == ["declare_a", "begin", "from_a", "from_b", "inner", "end"]


@pytest.mark.parametrize("name, message", [
    ("twice.wgsl", "appears twice"),
    ("unclosed.wgsl", "not closed with #end"),
    ("stray_end.wgsl", "#end without #at"),
    ("include_inside.wgsl", "#include inside an #at block"),
    ("crossing.wgsl", "began before the #at block"),
])
def test_malformed_points_are_errors(name, message):
    with pytest.raises(ShaderSourceError, match=message):
        run_points(name, A=1)


def _sources() -> dict[str, str]:
    from importlib.resources import files

    root = files("wgpu_shading.wgsl")
    found = {}
    for folder in ("", "chunks", "chunks/lighting", "chunks/surface", "chunks/maps", "chunks/strokes", "chunks/shadows"):
        base = root.joinpath(*folder.split("/")) if folder else root
        for entry in base.iterdir():
            if entry.name.endswith(".wgsl"):
                found[f"{folder}/{entry.name}".lstrip("/")] = entry.read_text(encoding="utf-8")
    return found


def test_every_point_a_chunk_uses_is_declared_once():
    """A misspelt point would drop a chunk's code silently: every #at names a #hook."""
    sources = _sources()
    hooks = [m for text in sources.values() for m in re.findall(r"^#hook ([\w.]+)", text, re.M)]
    assert len(hooks) == len(set(hooks)), "a point is declared in two places"
    used = {point for text in sources.values() for line in re.findall(r"^#at (.+)$", text, re.M) for point in line.split()}
    assert used <= set(hooks), f"#at names no #hook declares: {sorted(used - set(hooks))}"


def test_an_effects_code_lives_in_its_chunk():
    """The entry shaders and the shared parts (lighting, output, the vertex-lit stage) test
    no effect: only the lit color's shape (SPECULAR) and the unlit replacement of shade().
    Every chunk is included by some entry shader."""
    sources = _sources()
    shared = {name: text for name, text in sources.items() if "/" not in name and name != "structs.wgsl"}
    tested = {word for text in shared.values() for line in re.findall(r"^#(?:if|elif) (.+)$", text, re.M)
              for word in re.findall(r"[A-Z_]+", line) if word not in ("and", "or", "not")}
    assert tested <= {"SPECULAR", "UNLIT"}, tested
    included = {path for text in shared.values() for path in re.findall(r'^#include "(chunks/[\w/]+\.wgsl)"', text, re.M)}
    assert included == {name for name in sources if name.startswith("chunks/")}
