"""The golden-image comparison itself (wgpu_shading.testing.golden): what passes, what fails, and
that a failure's message names what went wrong. Images are real renders of a small scene,
changed the way real defects and real noise change them."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading import Camera, PositionalLight, Scene, SceneObject, Shading, load_mesh, material
from wgpu_shading.testing.golden import (
    GoldenError,
    Tolerance,
    as_rgba8,
    check_image,
    compare,
    diff_image,
    failure_paths,
    read_image,
    write_image,
)

SIZE = 128


@pytest.fixture(scope="module")
def scene() -> Scene:
    return Scene(
        objects=(SceneObject(load_mesh("builtin:sphere?slices=48&stacks=24"), material("gold")),),
        lights=(PositionalLight(position=(3.0, 3.0, 4.0)),),
        camera=Camera(eye=(0.0, 0.0, 3.2), fov_y=45.0),
        shading=Shading(frequency="phong", reflection="phong"),
        size=(SIZE, SIZE),
    )


@pytest.fixture(scope="module")
def base(renderer, scene) -> np.ndarray:
    return renderer.render(scene)


def edges(image: np.ndarray) -> np.ndarray:
    """Pixels at the object's outline: covered, with an uncovered 4-neighbour."""
    covered = image[:, :, :3].any(axis=2)
    padded = np.pad(covered, 1)
    neighbours_uncovered = ~padded[:-2, 1:-1] | ~padded[2:, 1:-1] | ~padded[1:-1, :-2] | ~padded[1:-1, 2:]
    return covered & neighbours_uncovered


# --------------------------------------------------------------------------- what passes


def test_identical_images_pass(base):
    result = compare(base, base.copy())
    assert result.passed
    assert result.over_count == 0 and result.max_difference == 0 and result.percentile == 0
    assert result.message.startswith("match: 0 pixels (0 %)")


def test_lavapipe_like_noise_passes(base):
    """±2 units everywhere the object is, ±2 more at its edges, and a few edge pixels
    flipped entirely (a coverage change): what another Mesa or CPU can do."""
    rng = np.random.default_rng(7)
    noisy = base.astype(np.int16)
    covered = base[:, :, :3].any(axis=2)
    noisy[covered, :3] += rng.integers(-2, 3, size=(int(covered.sum()), 3), dtype=np.int16)
    outline = edges(base)
    noisy[outline, :3] += rng.integers(-2, 3, size=(int(outline.sum()), 3), dtype=np.int16)
    flipped = np.argwhere(outline)[:: max(1, int(outline.sum()) // 10)][:10]  # 10 pixels of 16384
    noisy[flipped[:, 0], flipped[:, 1], :3] = 0
    noisy = np.clip(noisy, 0, 255).astype(np.uint8)
    assert np.abs(noisy.astype(int) - base).max() > 2  # the test does change pixels
    result = compare(noisy, base)
    assert result.passed, result.message
    assert result.over_count <= 10


# --------------------------------------------------------------------------- what fails, and how it is named


def test_removed_highlight_fails_and_is_named(renderer, scene, base):
    obj = scene.objects[0]
    dull = replace(scene, objects=(replace(obj, material=replace(obj.material, specular=(0.0, 0.0, 0.0, 1.0))),))
    result = compare(renderer.render(dull), base)
    assert not result.passed
    assert result.max_difference > 50
    text = result.message
    assert "brightest spot (highlight?) is dimmed or gone" in text, text
    assert "darker" in text and "a local difference: all differing pixels lie within rows" in text, text


def test_one_pixel_shift_fails_and_is_named(base):
    result = compare(np.roll(base, 1, axis=1), base)
    assert not result.passed
    assert "moved 1 pixel right" in result.message, result.message
    result = compare(np.roll(base, -1, axis=0), base)
    assert "moved 1 pixel up" in result.message, result.message


def test_object_moved_by_one_pixel_fails_and_is_named(renderer, scene, base):
    """A real move of the object in the scene (one pixel's width at its distance), not an
    image roll: the shading changes a little too, the shift is still recognized."""
    pixel = 2.0 * 3.2 * np.tan(np.radians(22.5)) / SIZE
    obj = scene.objects[0]
    moved = replace(scene, objects=(replace(obj, translate=(pixel, 0.0, 0.0)),))
    result = compare(renderer.render(moved), base)
    assert not result.passed
    assert "a shift" in result.message and "1 pixel right" in result.message, result.message


def test_swapped_color_channels_fail_and_are_named(base):
    result = compare(base[:, :, [2, 1, 0, 3]], base)
    assert not result.passed
    assert "swapped color channels: red and blue are exchanged" in result.message, result.message


def test_changed_light_color_fails_and_names_the_channel(renderer, scene, base):
    light = scene.lights[0]
    yellowish = replace(scene, lights=(replace(light, diffuse=(1.0, 1.0, 0.6, 1.0), specular=(1.0, 1.0, 0.6, 1.0)),))
    result = compare(renderer.render(yellowish), base)
    assert not result.passed
    assert "in the blue channel" in result.message, result.message
    assert "darker" in result.message


def test_moved_light_fails(renderer, scene, base):
    light = scene.lights[0]
    moved = replace(scene, lights=(replace(light, position=(3.0, 3.6, 4.0)),))
    result = compare(renderer.render(moved), base)
    assert not result.passed
    assert result.failures and "differ by more than 8/255" in result.failures[0]


def test_failure_message_reports_counts_max_percentile_and_where(base):
    changed = base.copy()
    changed[10:20, 30:40, 0] = 255  # a 10×10 red square on the black background
    result = compare(changed, base)
    assert not result.passed
    assert result.over_count == 100 and result.max_difference == 255
    assert result.max_location == (10, 30) and result.max_channel == "red"
    text = result.message
    assert "100 pixels (0.61 %) of 16384 differ by more than 8/255 (allowed: 0.10 %)" in text
    assert "max 255/255 at (row 10, col 30, red)" in text
    assert "99.9th percentile 255/255" in text
    assert "in the red channel" in text and "lie within rows 10–19, cols 30–39 (0.6% of the image)" in text and "brighter" in text


def test_different_sizes_fail(base):
    result = compare(base[:64], base)
    assert not result.passed
    assert "sizes differ: actual 128×64, expected 128×128" in result.message


# --------------------------------------------------------------------------- the tolerance rules


def test_threshold_counts_differences_strictly_above_it():
    expected = np.zeros((10, 10, 4), np.uint8)
    at = expected.copy()
    at[..., 1] = 8
    assert compare(at, expected).over_count == 0
    above = expected.copy()
    above[0, 0, 1] = 9
    assert compare(above, expected).over_count == 1


def test_max_fraction_allows_exactly_that_many_pixels():
    expected = np.zeros((100, 100, 4), np.uint8)  # 10 000 pixels: 0.1 % is 10
    actual = expected.copy()
    actual.reshape(-1, 4)[:10, 0] = 200
    assert compare(actual, expected).passed
    actual.reshape(-1, 4)[10, 0] = 200
    result = compare(actual, expected)
    assert not result.passed and "11 pixels" in result.failures[0] and "at most 10" in result.failures[0]
    assert compare(actual, expected, Tolerance(max_fraction=0.002)).passed


def test_max_difference_caps_every_pixel():
    expected = np.zeros((100, 100, 4), np.uint8)
    actual = expected.copy()
    actual[0, 0, 2] = 40  # one pixel: within the fraction rule
    assert compare(actual, expected).passed
    result = compare(actual, expected, Tolerance(max_difference=30))
    assert not result.passed and "max difference 40/255 exceeds the cap of 30/255" in result.message


def test_alpha_is_compared():
    expected = np.full((50, 50, 4), 255, np.uint8)
    actual = expected.copy()
    actual[..., 3] = 242  # jade's alpha 0.95 instead of 1
    result = compare(actual, expected)
    assert not result.passed and result.max_channel == "alpha" and "only alpha differs" in result.message


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"threshold": -1}, "threshold"),
        ({"threshold": 2.5}, "threshold"),
        ({"max_fraction": 1.5}, "max_fraction"),
        ({"max_difference": 300}, "max_difference"),
        ({"flip_mean": -0.1}, "flip_mean"),
    ],
)
def test_bad_tolerances_are_rejected(kwargs, message):
    with pytest.raises(GoldenError, match=message):
        Tolerance(**kwargs)


def test_inputs_rgb_gray_and_float_are_accepted():
    rgba = np.zeros((4, 4, 4), np.uint8)
    rgba[..., 3] = 255
    assert compare(rgba[..., :3], rgba).passed
    assert compare(np.zeros((4, 4)), rgba).passed  # float gray 0 → opaque black
    assert as_rgba8(np.full((2, 2, 3), 0.5))[0, 0].tolist() == [128, 128, 128, 255]
    with pytest.raises(GoldenError, match="expected an"):
        compare(np.zeros((4, 4, 2), np.uint8), rgba)
    with pytest.raises(GoldenError, match="NaN"):
        compare(np.full((4, 4, 3), np.nan), rgba)


# --------------------------------------------------------------------------- images and files


def test_diff_image_amplifies_per_channel():
    expected = np.zeros((2, 2, 4), np.uint8)
    expected[..., 3] = 255
    actual = expected.copy()
    actual[0, 0, 0] = 3  # red +3
    actual[1, 1, 3] = 250  # alpha −5: shows in all three channels
    diff = diff_image(actual, expected, amplification=10)
    assert diff[0, 0].tolist() == [30, 0, 0, 255]
    assert diff[1, 1].tolist() == [50, 50, 50, 255]
    assert diff[0, 1].tolist() == [0, 0, 0, 255]


def test_check_image_creates_passes_fails_and_updates(tmp_path, base):
    reference = tmp_path / "refs" / "sphere.png"
    with pytest.raises(GoldenError, match="does not exist"):
        check_image(base, reference)
    assert check_image(base, reference, update=True).status == "created"
    assert np.array_equal(read_image(reference), base)

    stamp = reference.stat().st_mtime_ns
    noisy = base.copy()
    noisy[60, 60, 0] ^= 1
    assert check_image(noisy, reference, update=True).status == "passed"  # within tolerance: untouched
    assert reference.stat().st_mtime_ns == stamp

    shifted = np.roll(base, 1, axis=1)
    result = check_image(shifted, reference)
    assert result.status == "failed" and not result.passed
    paths = failure_paths(reference)
    assert set(result.written) == set(paths.values())
    assert np.array_equal(read_image(paths["actual"]), shifted)
    assert np.array_equal(read_image(paths["expected"]), base)
    assert read_image(paths["diff"]).shape == base.shape
    assert "FAIL" in result.report() and "moved 1 pixel right" in result.report() and "sphere.diff.png" in result.report()

    assert check_image(base, reference).status == "passed"
    assert not any(path.exists() for path in paths.values())  # a pass removes the stale failure images

    out = tmp_path / "out"
    result = check_image(shifted, reference, output_dir=out)
    assert all(path.parent == out for path in result.written)
    assert check_image(shifted, reference, update=True).status == "updated"
    assert np.array_equal(read_image(reference), shifted)


def test_read_image_rejects_what_it_cannot_compare(tmp_path):
    bad = tmp_path / "bad.png"
    bad.write_text("not a png")
    with pytest.raises(GoldenError, match="this file holds data that is not PNG"):
        read_image(bad)
    import imageio.v3 as iio

    deep = tmp_path / "deep.png"
    iio.imwrite(deep, np.zeros((4, 4), np.uint16))
    with pytest.raises(GoldenError, match="8-bit"):
        read_image(deep)
    ok = write_image(tmp_path / "sub" / "ok.png", np.zeros((3, 5, 3), np.uint8))
    assert read_image(ok).shape == (3, 5, 4)


# --------------------------------------------------------------------------- FLIP


def test_flip_metric(renderer, scene, base):
    pytest.importorskip("flip_evaluator")
    from wgpu_shading.testing.golden import flip_mean

    assert flip_mean(base, base) == pytest.approx(0.0, abs=1e-6)
    obj = scene.objects[0]
    dull = renderer.render(replace(scene, objects=(replace(obj, material=replace(obj.material, specular=(0, 0, 0, 1))),)))
    error = flip_mean(dull, base)
    assert error > 0.001
    assert compare(dull, base, Tolerance(max_fraction=1.0, flip_mean=error * 2)).passed
    result = compare(dull, base, Tolerance(max_fraction=1.0, flip_mean=error / 2))
    assert not result.passed and "mean FLIP error" in result.message


def test_flip_without_the_optional_package_says_how_to_install_it(monkeypatch, base):
    import sys

    monkeypatch.setitem(sys.modules, "flip_evaluator", None)  # import fails as if not installed
    with pytest.raises(GoldenError, match=r"\[flip\] extra into this environment: .* -m pip install 'flip-evaluator"):
        compare(base, base, Tolerance(flip_mean=0.01))


# --------------------------------------------------------------------------- hostile references


def _jpeg_bytes() -> bytes:
    import io

    from PIL import Image

    buffer = io.BytesIO()
    Image.new("RGB", (4, 4), (10, 20, 30)).save(buffer, format="JPEG")
    return buffer.getvalue()


def _sixteen_bit_png(path):
    import imageio.v3 as iio

    iio.imwrite(path, np.full((4, 4), 40000, np.uint16))
    return path


@pytest.mark.parametrize(
    "kind, make, message",
    [
        ("jpeg", lambda p: p.write_bytes(_jpeg_bytes()), "this file holds JPEG data"),
        ("16-bit", _sixteen_bit_png, "this one has uint16 pixels"),
        ("damaged", lambda p: p.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\x00" * 40), "a damaged PNG"),
    ],
)
def test_unusable_references_are_refused_then_replaced_with_update(tmp_path, kind, make, message):
    reference = tmp_path / "ref.png"
    make(reference)
    image = np.full((4, 4, 4), 200, np.uint8)
    with pytest.raises(GoldenError, match=message + r".*rewrite it with --update"):
        check_image(image, reference)
    result = check_image(image, reference, update=True)
    assert result.status == "updated" and "could not be used" in result.report()
    assert reference.read_bytes().startswith(b"\x89PNG")
    assert np.array_equal(read_image(reference), image)
    assert check_image(image, reference).status == "passed"


def test_a_jpg_reference_name_never_gets_png_bytes(tmp_path):
    reference = tmp_path / "ref.jpg"
    with pytest.raises(GoldenError, match="references are 8-bit PNG files; name it .png"):
        check_image(np.zeros((4, 4, 4), np.uint8), reference, update=True)
    assert not reference.exists()


def test_an_rgb_reference_compares_colour_only_against_a_translucent_image(tmp_path):
    reference = write_image(tmp_path / "rgb.png", np.full((6, 6, 3), 90, np.uint8))
    import imageio.v3 as iio

    iio.imwrite(reference, np.full((6, 6, 3), 90, np.uint8))  # a file without alpha
    translucent = np.full((6, 6, 4), 90, np.uint8)
    translucent[:, :, 3] = 128
    assert check_image(translucent, reference).status == "passed"
    different = translucent.copy()
    different[:, :, 0] = 200
    assert check_image(different, reference).status == "failed"
    rgba_reference = write_image(tmp_path / "rgba.png", np.full((6, 6, 4), 90, np.uint8))
    assert check_image(translucent, rgba_reference).status == "failed"  # its alpha is 255
