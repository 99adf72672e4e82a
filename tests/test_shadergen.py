"""The WGSL preprocessor and the feature-specialized shaders: code and uniforms exist only
for the effects a scene uses, and every specialization compiles."""

from __future__ import annotations

import itertools
import re

import pytest

from wgpu_shading.render.features import FeatureSet
from wgpu_shading.render.shadergen import ShaderSourceError, generate_wgsl, preprocess

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
    ],
)
def test_each_feature_brings_its_code_and_only_then(feature, words):
    without = _code(BASE)
    with_feature = _code(FeatureSet(**{**BASE.__dict__, **feature}))
    for word in words:
        assert word not in without, f"{word!r} is in a shader that does not use {feature}"
        assert word in with_feature, f"{word!r} is missing from a shader that uses {feature}"


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


def test_every_combination_compiles(renderer):
    """naga validates every specialization (one per combination of the switches)."""
    device = renderer.device
    count = 0
    for frequency, reflection, lights, attenuation, specular, emission, texture, two_sided, local in itertools.product(
        ("flat", "gouraud", "phong"),
        ("phong", "blinn-phong"),
        ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (2, 3, 2)),
        (False, True),
        (False, True),
        (False, True),
        (None, "modulate", "modulate_all", "blend"),
        (False, True),
        (False, True),
    ):
        if attenuation and lights[1] + lights[2] == 0:
            continue
        features = FeatureSet(frequency, reflection, *lights, attenuation, specular, emission, texture, two_sided, local)
        device.create_shader_module(code=generate_wgsl(features))
        count += 1
    assert count > 2000
