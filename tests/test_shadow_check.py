"""The shadow check that GPU images are held to (docs/shadows.md#testing-shadows), on
images whose errors are made on purpose from the float64 reference: it passes what the
guarantees allow and fails, in words and with a picture, what they do not."""

from __future__ import annotations

import numpy as np
import pytest

from wgpu_shading.study.reference import RasterizedScene
from wgpu_shading.study.shadows import ShadowError, ShadowReference, check_shadows, measure_shadows, shadow_case

pytest.importorskip("embreex")


@pytest.fixture(scope="module")
def two_lights():
    case = shadow_case("two_lights", (96, 96))
    rasterized = RasterizedScene(case.scene)
    shadowless = rasterized.shade(visibility=np.ones_like(rasterized.visibility)).astype(np.float32)
    return ShadowReference(case.scene), rasterized, shadowless


def shifted(visibility: np.ndarray, pixels: int) -> np.ndarray:
    """The shadows moved `pixels` to the right (the left columns keep theirs)."""
    moved = visibility.copy()
    moved[:, :, pixels:] = visibility[:, :, :-pixels]
    return moved


def test_the_exact_image_passes(two_lights):
    reference, rasterized, shadowless = two_lights
    report = check_shadows(reference, rasterized.shade().astype(np.float32), shadowless)
    assert report.passed and all(r.wrong == 0 and r.displacement_p99 == 0 for r in report.lights)
    assert report.lit_error < 0.01 and report.shadowed_error < 0.01


def test_a_boundary_one_pixel_off_passes_two_pixels_off_does_not(two_lights):
    reference, rasterized, shadowless = two_lights
    one = measure_shadows(reference, rasterized.shade(visibility=shifted(rasterized.visibility, 1)), shadowless)
    assert one.passed, one.failures
    assert all(r.wrong > 0 and r.wrong_far == 0 and r.displacement_p99 == 1.0 for r in one.lights)
    two = measure_shadows(reference, rasterized.shade(visibility=shifted(rasterized.visibility, 2)), shadowless)
    assert any("boundary is 2.00 px from the exact one" in f for f in two.failures)
    three = measure_shadows(reference, rasterized.shade(visibility=shifted(rasterized.visibility, 3)), shadowless)
    assert any("farther than 2 px from the exact shadow boundary have the wrong state" in f for f in three.failures)


def test_acne_fails_with_the_worst_pixel_and_a_picture(two_lights, tmp_path):
    reference, rasterized, shadowless = two_lights
    acne = rasterized.visibility.copy()
    lit = np.argwhere(reference.matters(0) & ~reference.shadowed(0) & ~reference.shadowed(1))
    speck = lit[len(lit) // 2]
    acne[0, speck[0], speck[1]] = 0.0  # one dark speck, far inside the lit ground
    with pytest.raises(ShadowError) as failure:
        check_shadows(reference, rasterized.shade(visibility=acne), shadowless, name="acne", picture_dir=tmp_path)
    message = str(failure.value)
    assert "light 0: 1 pixels farther than 2 px" in message and f"({speck[0]}, {speck[1]})" in message
    picture = tmp_path / "acne.shadows.png"
    assert picture.is_file() and str(picture) in message


def test_a_lit_colour_off_by_more_than_one_unit_fails(two_lights):
    reference, rasterized, shadowless = two_lights
    image = rasterized.shade().copy()
    lit = reference.covered & (reference.visibility > 0.5).all(axis=0)
    image[lit, 1] += 1.5 / 255.0  # a faint shadow everywhere: the light 'leaks' as a tint
    report = measure_shadows(reference, image, shadowless)
    assert any("where the exact state is lit" in f for f in report.failures) and report.lit_error == pytest.approx(1.5, abs=0.01)


def test_a_gpu_visibility_is_used_when_given(two_lights):
    reference, rasterized, shadowless = two_lights
    wrong = shifted(rasterized.visibility, 3)
    report = measure_shadows(reference, rasterized.shade().astype(np.float32), shadowless, visibility=wrong)
    assert any("wrong state" in f for f in report.failures)


def test_a_shadowless_image_of_another_scene_is_refused(two_lights):
    reference, rasterized, shadowless = two_lights
    report = measure_shadows(reference, rasterized.shade(), np.zeros_like(shadowless))
    assert any("differ from the reference even without shadows" in f for f in report.failures)
    with pytest.raises(ValueError, match="expected an \\(H, W, 3 or 4\\) image of 96×96"):
        measure_shadows(reference, np.zeros((10, 10, 4)), shadowless)
