"""The golden diff image's log scale: small differences stay visible, large ones do not
saturate, and the scale is stated in the report and in the PNG."""

from __future__ import annotations

import numpy as np
from PIL import Image

from wgpu_shading.testing.golden import Tolerance, check_image, diff_image


def _pair(differences):
    expected = np.zeros((1, len(differences), 4), np.uint8)
    expected[..., 3] = 255
    actual = expected.copy()
    actual[0, :, 1] = differences
    return actual, expected


def test_log_scale_keeps_every_difference_distinguishable():
    differences = [0, 1, 2, 8, 26, 64, 128, 255]
    actual, expected = _pair(differences)
    drawn = diff_image(actual, expected)[0, :, 1].tolist()
    assert drawn == [0, 32, 51, 101, 152, 192, 223, 255]
    assert drawn == sorted(set(drawn))  # strictly increasing: no two levels look alike
    # The linear ×10 scale is still available and saturates from 26/255 on.
    assert diff_image(actual, expected, amplification=10)[0, 4:, 1].tolist() == [255] * 4


def test_failure_states_the_scale_in_report_and_png(tmp_path):
    actual, expected = _pair([0, 40, 90, 200])
    reference = tmp_path / "ref.png"
    Image.fromarray(expected).save(reference)
    result = check_image(actual, reference)
    assert not result.passed
    assert "diff image: log scale: drawn = 255·log2(1 + d)/8" in result.report()
    diff = Image.open(tmp_path / "ref.diff.png")
    assert diff.text["Comment"].startswith("log scale")


def test_written_diff_carries_a_legend_that_reads_like_the_diff(tmp_path):
    expected = np.zeros((40, 200, 4), np.uint8)
    expected[..., 3] = 255
    actual = expected.copy()
    actual[10:20, 10:20, 0] = 8
    reference = tmp_path / "wide.png"
    Image.fromarray(expected).save(reference)
    assert not check_image(actual, reference, Tolerance(threshold=0, max_fraction=0.0)).passed
    written = np.asarray(Image.open(tmp_path / "wide.diff.png"))
    assert written.shape == (40 + 34, 200, 4)  # the diff's own pixels first, the legend below
    assert np.array_equal(written[:40], diff_image(actual, expected))
    ramp = written[40, :, 0].astype(int)
    column_of_8 = round(np.log2(9) / 8 * 199)  # the legend spaces differences evenly on the log scale
    assert abs(ramp[column_of_8] - written[15, 15, 0]) <= 2  # the legend's 8/255 looks like the diff's 8/255
    assert ramp[0] == 0 and ramp[-1] == 255 and np.all(np.diff(ramp) >= 0)
