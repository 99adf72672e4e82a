"""The scene's shadow fields (docs/shadows.md#settings): defaults, validation naming the
key, and the helpers that say what casts."""

from __future__ import annotations

import pytest

from wgpu_shading.errors import SceneError
from wgpu_shading.scene import (
    SHADOW_FILTERS,
    DirectionalLight,
    PositionalLight,
    Scene,
    SceneObject,
    ShadowSettings,
    SpotLight,
    cube,
    every_light_casts,
    has_shadows,
    shadowing_lights,
)


def test_defaults_cast_nothing_until_a_light_asks():
    assert not any(kind().shadows for kind in (DirectionalLight, PositionalLight, SpotLight))
    obj = SceneObject(cube())
    assert obj.cast_shadows and obj.receive_shadows
    assert ShadowSettings() == ShadowSettings("auto", "auto", "auto")
    scene = Scene(objects=(obj,), lights=(DirectionalLight(), PositionalLight(shadows=True)))
    assert scene.shadows == ShadowSettings()
    assert shadowing_lights(scene) == (1,) and has_shadows(scene)


def test_no_shadows_without_a_caster_a_receiver_or_a_casting_light():
    light = DirectionalLight(shadows=True)
    assert not has_shadows(Scene(objects=(SceneObject(cube()),), lights=(DirectionalLight(),)))
    assert not has_shadows(Scene(objects=(SceneObject(cube(), cast_shadows=False),), lights=(light,)))
    assert not has_shadows(Scene(objects=(SceneObject(cube(), receive_shadows=False),), lights=(light,)))
    assert not has_shadows(Scene(lights=(light,)))


def test_every_light_casts_is_what_the_shadows_flag_means():
    scene = Scene(lights=(DirectionalLight(), PositionalLight(), SpotLight(shadows=True)))
    changed = every_light_casts(scene)
    assert shadowing_lights(changed) == (0, 1, 2)
    assert [type(light) for light in changed.lights] == [type(light) for light in scene.lights]


@pytest.mark.parametrize(
    "build, message",
    [
        (lambda: DirectionalLight(shadows="yes"), "light.shadows: expected true or false, got 'yes'"),
        (lambda: SpotLight(shadows=1), "light.shadows: expected true or false, got 1"),
        (lambda: SceneObject(cube(), cast_shadows=None), "object.cast_shadows: expected true or false"),
        (lambda: SceneObject(cube(), receive_shadows="false"), "object.receive_shadows: expected true or false"),
        (lambda: ShadowSettings(map_size=8), r"shadows.map_size: expected \"auto\" or 16..8192 texels, got 8"),
        (lambda: ShadowSettings(map_size=100000), "shadows.map_size"),
        (lambda: ShadowSettings(map_size=512.5), "shadows.map_size: expected \"auto\" or a whole number"),
        (lambda: ShadowSettings(map_size="big"), "shadows.map_size"),
        (lambda: ShadowSettings(filter="pcf7"), "shadows.filter: expected one of 'auto', 'nearest'"),
        (lambda: ShadowSettings(bias=-1.0), r"shadows.bias: expected a number in \[0, 64\]"),
        (lambda: ShadowSettings(bias=float("nan")), "shadows.bias"),
        (lambda: Scene(shadows={"map_size": 512}), "shadows: expected ShadowSettings"),
    ],
)
def test_bad_values_name_the_key(build, message):
    with pytest.raises(SceneError, match=message):
        build()


def test_settings_normalize():
    settings = ShadowSettings(map_size=1024.0, filter="pcf3", bias=2)
    assert settings.map_size == 1024 and isinstance(settings.map_size, int)
    assert settings.bias == 2.0 and settings.filter in SHADOW_FILTERS
