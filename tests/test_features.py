"""Every lighting feature moves pixels in the expected direction, and by the amount the
float64 evaluation of docs/conventions.md#the-lighting-equation predicts (wgpu_shading.study.reference), at the sampled pixels.

The stage: a square facing the camera, lit from in front. Each test renders on the GPU
(float32 target), checks the whole image against the same-mesh float64 reference
(`support.compare`), then checks the feature's own effect at chosen pixels."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from support import EDGE_BAND, compare, smooth_texture
from wgpu_shading.study import reference as ref
from wgpu_shading.scene import plane, uv_sphere
from wgpu_shading.scene import (
    Camera,
    DirectionalLight,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    SpotLight,
)

SIZE = (80, 80)
WALL = plane(size=3.0, subdivisions=8)  # fills the whole frame
MATTE = Material(ambient=(0.2, 0.2, 0.2, 1), diffuse=(0.6, 0.6, 0.6, 1), specular=(0.3, 0.3, 0.3, 1), shininess=20.0)


def stage(*lights, material: Material = MATTE, **shading) -> Scene:
    return Scene(
        objects=(SceneObject(WALL, material),),
        lights=lights,
        camera=Camera(eye=(0.0, 0.0, 2.4), fov_y=50.0, near=0.5, far=10.0),
        shading=Shading(**shading),
        ambient=(0.1, 0.1, 0.1, 1.0),
        size=SIZE,
    )


def render(renderer, scene: Scene, what: str) -> np.ndarray:
    """GPU color (float32), after asserting it matches the float64 reference."""
    frame = renderer.render_frame(scene, float32=True, depth=True)
    compare(frame, ref.render_reference(scene), EDGE_BAND, what)
    return frame.color[:, :, :3].astype(np.float64)


CENTRE = (40, 40)


def test_attenuation_darkens_by_the_predicted_factor(renderer):
    light = PositionalLight(position=(0.0, 0.0, 1.0), ambient=(0, 0, 0, 1), diffuse=(0.8, 0.8, 0.8, 1), specular=(0, 0, 0, 1))
    plain = render(renderer, stage(light), "no attenuation")
    coefficients = (1.0, 0.5, 0.25)
    attenuated = render(renderer, stage(replace(light, attenuation=coefficients)), "attenuation")
    ambient_only = render(renderer, stage(), "no lights")
    assert (attenuated <= plain + 1e-6).all() and (attenuated[CENTRE] < plain[CENTRE] - 0.1).all()
    # At the centre the light is 1 unit straight above: factor 1 / (1 + 0.5 + 0.25).
    light_part_plain = plain[CENTRE] - ambient_only[CENTRE]
    light_part_attenuated = attenuated[CENTRE] - ambient_only[CENTRE]
    np.testing.assert_allclose(light_part_attenuated, light_part_plain / 1.75, atol=2e-3)
    # Farther pixels lose more: the ratio falls away from the centre.
    corner = (8, 8)
    ratio_corner = (attenuated[corner] - ambient_only[corner])[0] / (plain[corner] - ambient_only[corner])[0]
    assert ratio_corner < 1 / 1.75


def _spot(**changes) -> SpotLight:
    values = dict(position=(0.0, 0.0, 1.0), direction=(0.0, 0.0, -1.0), cutoff=30.0, exponent=0.0,
                  ambient=(0, 0, 0, 1), diffuse=(0.8, 0.8, 0.8, 1), specular=(0, 0, 0, 1))
    values.update(changes)
    return SpotLight(**values)


def test_spot_cone_edge_is_where_the_cutoff_puts_it(renderer):
    lit = render(renderer, stage(_spot()), "spot cone")
    ambient_only = render(renderer, stage(), "no lights")
    inside = (lit - ambient_only).max(axis=2) > 1e-4
    # The cone meets the plane 1 unit below the light in a circle of radius tan(30°).
    world = ref.pixel_rays(stage().camera, SIZE)  # eye-space rays through pixel centres, z = -1
    hit = world[:, :, :2] * 2.4  # the plane is 2.4 units in front of the eye
    radius = np.hypot(hit[:, :, 0], hit[:, :, 1])
    cone = np.tan(np.radians(30.0))
    pixel = 2.4 * np.tan(np.radians(25.0)) / 40.0  # world size of one pixel on the plane
    assert inside[radius < cone - pixel].all(), "dark pixels inside the cone"
    assert not inside[radius > cone + pixel].any(), "lit pixels outside the cone"


def test_spot_exponent_narrows_the_beam(renderer):
    none = render(renderer, stage(), "no lights")
    wide = render(renderer, stage(_spot(exponent=0.0)), "spot exponent 0") - none
    narrow = render(renderer, stage(_spot(exponent=40.0)), "spot exponent 40") - none
    rays = ref.pixel_rays(stage().camera, SIZE)
    for pixel in [CENTRE, (40, 48), (40, 56), (30, 50)]:
        x, y = rays[pixel][:2] * 2.4  # where the pixel's ray meets the plane
        cosine = 1.0 / np.sqrt(1.0 + x * x + y * y)  # angle off the spot's axis, light 1 unit above
        # Everything but the spot factor is the same in both: the ratio is cos^40 - cos^0.
        np.testing.assert_allclose(narrow[pixel], wide[pixel] * cosine**40, atol=2e-3)
    assert narrow[40, 56][0] < 0.5 * wide[40, 56][0]


def test_lights_add_up(renderer):
    a = DirectionalLight(direction=(-0.3, -0.2, -1.0), ambient=(0.05, 0, 0, 1), diffuse=(0.3, 0.1, 0.1, 1), specular=(0.2, 0.2, 0.2, 1))
    b = PositionalLight(position=(0.5, -0.5, 1.5), ambient=(0, 0.05, 0, 1), diffuse=(0.1, 0.3, 0.2, 1), specular=(0.2, 0.2, 0.2, 1))
    c = _spot(diffuse=(0.1, 0.1, 0.3, 1), cutoff=40.0)
    none = render(renderer, stage(), "no lights")
    parts = [render(renderer, stage(light), f"one light: {light.kind}") - none for light in (a, b, c)]
    together = render(renderer, stage(a, b, c), "three lights") - none
    assert (together < 1.0 - 1e-3).all()  # the sum stays below the clamp
    np.testing.assert_allclose(together, sum(parts), atol=2e-3)


def test_emission_adds_its_color(renderer):
    light = DirectionalLight(direction=(0, 0, -1), diffuse=(0.5, 0.5, 0.5, 1), specular=(0, 0, 0, 1))
    plain = render(renderer, stage(light), "no emission")
    glowing = render(renderer, stage(light, material=replace(MATTE, emission=(0.2, 0.1, 0.0, 1))), "emission")
    np.testing.assert_allclose(glowing - plain, np.broadcast_to([0.2, 0.1, 0.0], plain.shape), atol=2e-3)


@pytest.mark.parametrize("reflection", ["phong", "blinn-phong"])
def test_specular_appears_where_the_reflection_model_puts_it(renderer, reflection):
    light = PositionalLight(position=(0.6, 0.6, 2.0), specular=(1, 1, 1, 1), diffuse=(0.3, 0.3, 0.3, 1))
    shiny = replace(MATTE, specular=(0.8, 0.8, 0.8, 1), shininess=60.0)
    with_highlight = render(renderer, stage(light, material=shiny, reflection=reflection), f"{reflection} highlight")
    without = render(renderer, stage(light, material=replace(shiny, specular=(0, 0, 0, 1)), reflection=reflection), "no specular")
    highlight = with_highlight - without
    peak = np.unravel_index(np.argmax(highlight.sum(axis=2)), highlight.shape[:2])
    # The highlight's peak is between the light's and the eye's footprints on the plane:
    # for Phong exactly where R·V = 1, for Blinn-Phong where N·H = 1 (the same point here).
    assert 0.1 < highlight[peak].max() <= 0.8 + 1e-3
    assert peak[0] < 40 and peak[1] > 40  # upper right of centre, towards the light


SPHERE = uv_sphere(1.0, 48, 24)
COLORED = Material(ambient=(0.3, 0.3, 0.3, 1), diffuse=(0.8, 0.8, 0.8, 1), specular=(0.9, 0.9, 0.9, 1), shininess=40.0)


def textured(mode: str) -> Scene:
    texture = smooth_texture()
    return Scene(
        objects=(SceneObject(SPHERE, replace(COLORED, texture=texture, texture_mode=mode), scale=(1.0, 1.0, 1.0)),),
        lights=(PositionalLight(position=(2.0, 2.0, 4.0)),),
        camera=Camera(eye=(0.0, 0.0, 3.0), fov_y=40.0, near=0.5, far=10.0),
        ambient=(0.2, 0.2, 0.2, 1.0),
        size=(72, 72),
    )


def test_texture_modes_combine_as_specified(renderer):
    images = {mode: render(renderer, textured(mode), f"texture {mode}") for mode in ("modulate", "modulate_all", "blend")}
    plain = render(renderer, replace(textured("modulate"), objects=(SceneObject(SPHERE, COLORED),)), "untextured")
    peak = np.unravel_index(np.argmax(plain.sum(axis=2)), plain.shape[:2])
    dim = (60, 16)  # lower left, away from the light
    # modulate: the highlight stays the light's color (white): its channels stay equal at the peak,
    # while modulate_all tints the highlight with the texture (channels spread apart).
    spread = {mode: float(np.ptp(images[mode][peak])) for mode in images}
    assert spread["modulate_all"] > spread["modulate"] + 0.02
    # Both modulating modes darken with the texture (texels < 1); blend pulls towards 0.5·texture
    # (brightening dark regions, darkening bright ones).
    assert (images["modulate"][dim] < plain[dim]).all() and (images["modulate_all"][dim] < plain[dim]).all()
    assert (images["blend"][dim] > images["modulate"][dim]).all()
