"""The shadow part of the accuracy study (docs/accuracy.md#shadows): its grid, the rule
that `auto` follows (docs/shadows.md#auto), and the sweep itself once the GPU draws shadows."""

from __future__ import annotations

import pytest

from wgpu_shading.errors import AccuracyError, SceneError
from wgpu_shading.scene import ShadowSettings
from wgpu_shading.study.accuracy import (
    ShadowBudget,
    ShadowPoint,
    ShadowSetting,
    cheapest_shadow_setting,
    gpu_draws_shadows,
    run_shadow_study,
    shadow_grid,
    shadow_table,
)


def point(size, filter_, bias, ms, wrong_far=0, displacement=0.5, color=0.2, case="a"):
    return ShadowPoint(case, ShadowSetting(size, filter_, bias), wrong_far + 3, wrong_far, displacement, color, color, ms)


def test_the_grid_is_every_combination_and_validated():
    grid = shadow_grid((512, 1024), ("nearest", "pcf3"), (0.0, 1.0))
    assert len(grid) == 8 and ShadowSetting(1024, "pcf3", 1.0) in grid
    assert grid[0].settings() == ShadowSettings(512, "nearest", 0.0)
    with pytest.raises(SceneError, match="shadows.map_size"):
        shadow_grid((8,))


def test_auto_is_the_cheapest_setting_within_the_budget_on_every_case():
    points = [
        point(512, "nearest", 0.0, 1.0, wrong_far=40),  # acne: out
        point(512, "pcf3", 1.0, 2.0, displacement=1.4),  # boundary too far: out
        point(1024, "pcf3", 1.0, 3.0),
        point(1024, "pcf3", 1.0, 3.1, case="b"),
        point(2048, "bilinear", 1.0, 2.95),
        point(2048, "bilinear", 1.0, 9.0, case="b", color=1.5),  # fails on case b: out
        point(4096, "pcf5", 2.0, 8.0),
    ]
    assert cheapest_shadow_setting(points) == ShadowSetting(1024, "pcf3", 1.0)
    # A looser budget lets the fast ones in.
    assert cheapest_shadow_setting(points, ShadowBudget(wrong_far=50, displacement_p99=2.0)) == ShadowSetting(512, "nearest", 0.0)
    # Within 5 % of the fastest, the larger map wins, then the cheaper filter, then the smaller bias.
    tied = points + [point(2048, "nearest", 2.0, 3.1), point(2048, "nearest", 2.0, 3.1, case="b"),
                     point(2048, "nearest", 3.0, 3.1), point(2048, "nearest", 3.0, 3.1, case="b")]
    assert cheapest_shadow_setting(tied) == ShadowSetting(2048, "nearest", 2.0)
    assert cheapest_shadow_setting([point(512, "nearest", 0.0, 1.0, wrong_far=1)]) is None


def test_the_table_has_a_row_per_setting():
    table = shadow_table([point(1024, "pcf3", 1.0, 3.0), point(1024, "pcf3", 1.0, 5.0, case="b", wrong_far=2)])
    assert "| 1024 | pcf3 | 1 | 2 | 0.50 | 0.20 | 4.00 |" in table


@pytest.mark.skipif(gpu_draws_shadows(), reason="the renderer draws shadows: the sweep runs below")
def test_the_sweep_says_when_the_renderer_draws_no_shadows(renderer):
    with pytest.raises(AccuracyError, match="needs a renderer that draws shadows"):
        run_shadow_study(renderer, shadow_grid((512,), ("nearest",), (1.0,)))


@pytest.mark.skipif(not gpu_draws_shadows(), reason="the renderer draws no shadows yet (FeatureSet has no shadow field)")
def test_a_small_sweep_measures_every_point(renderer):
    grid = shadow_grid((256, 1024), ("nearest", "pcf3"), (1.0,))
    points = run_shadow_study(renderer, grid, cases=(("sphere_over_plane_30", 1.0, "perspective"),), size=(96, 96), frames=1)
    assert len(points) == 4 and all(p.frame_ms > 0 for p in points)


def test_auto_resolves_field_by_field():
    resolved = ShadowSettings(map_size=512).resolved()
    assert resolved.map_size == 512 and resolved.filter != "auto" and resolved.bias != "auto"
    assert ShadowSettings(512, "nearest", 0.0).resolved() == ShadowSettings(512, "nearest", 0.0)


def test_auto_is_the_studys_choice_for_the_stored_points():
    """scene/shadows.py's AUTO_* are what the rule picks from the study the docs show
    (docs/accuracy/shadows.json, written by `wgpu-shading bench accuracy --shadows`): a re-run
    that chooses otherwise fails here, naming the constants to set."""
    from pathlib import Path

    from wgpu_shading.scene import shadows
    from wgpu_shading.study.accuracy import load_shadow_points

    stored = Path(__file__).resolve().parent.parent / "docs" / "accuracy" / "shadows.json"
    chosen = cheapest_shadow_setting(load_shadow_points(stored))
    assert chosen is not None, "no setting of the stored study meets the budget"
    assert shadows.AUTO_IS_MEASURED
    assert (shadows.AUTO_MAP_SIZE, shadows.AUTO_FILTER, shadows.AUTO_BIAS) == (chosen.map_size, chosen.filter, chosen.bias), (
        f"set AUTO_MAP_SIZE, AUTO_FILTER, AUTO_BIAS = {chosen.map_size}, {chosen.filter!r}, {chosen.bias!r} in scene/shadows.py")


def test_a_point_reads_back_as_it_was_written(tmp_path):
    from wgpu_shading.study.accuracy import load_shadow_points, write_shadow_study

    points = [point(1024, "pcf3", 1.0, 3.0), point(512, "nearest", 3.0, 2.0, case="b")]
    write_shadow_study(points, tmp_path, plot=False, command="test")
    assert load_shadow_points(tmp_path / "shadows.json") == tuple(points)
    assert "auto = 512 texels, nearest, bias 3 texels" in (tmp_path / "shadows.md").read_text()


def test_bench_accuracy_shadows_writes_the_study_and_says_what_auto_is(tmp_path, capsys):
    from wgpu_shading.cli.main import main

    markdown = tmp_path / "accuracy.md"
    markdown.write_text("# Accuracy\n\n<!-- accuracy:shadows-auto -->\n<!-- /accuracy:shadows-auto -->\n")
    assert main(["bench", "accuracy", "--shadows", "--quick", "--no-plot", "--frames", "1", "--out", str(tmp_path / "out"),
                 "--markdown", str(markdown)]) == 0
    printed = capsys.readouterr().out
    assert "auto: (" in printed
    assert {p.name for p in (tmp_path / "out").iterdir()} == {"shadows.csv", "shadows.json", "shadows.md"}
    assert "auto = " in markdown.read_text() or "No setting" in markdown.read_text()
