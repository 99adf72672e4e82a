"""The material table (docs/scene-files.md#materials)."""

from __future__ import annotations

import pytest

from wgpu_shading import MATERIALS, SceneError, material


def test_table_has_the_classic_entries_pewter_and_polished_metals():
    classic = [
        "emerald", "jade", "obsidian", "pearl", "ruby", "turquoise", "brass", "bronze", "chrome", "copper", "gold",
        "silver", *(f"{c}_{k}" for k in ("plastic", "rubber") for c in ("black", "cyan", "green", "red", "white", "yellow")),
    ]
    assert len(classic) == 24
    for name in classic + ["pewter", "polished_gold", "polished_silver", "polished_bronze", "polished_copper"]:
        assert name in MATERIALS


def test_values_and_shininess_in_opengl_units():
    gold = material("gold")
    assert gold.ambient == (0.24725, 0.1995, 0.0745, 1.0)
    assert gold.diffuse == (0.75164, 0.60648, 0.22648, 1.0)
    assert gold.specular == (0.628281, 0.555802, 0.366065, 1.0)
    assert gold.shininess == pytest.approx(51.2)
    assert material("pewter").shininess == pytest.approx(9.85)
    assert material("black rubber").shininess == pytest.approx(10.0)
    assert material("brass").shininess == pytest.approx(27.897436, rel=1e-6)


@pytest.mark.parametrize("name, alpha", [("jade", 0.95), ("pearl", 0.922), ("emerald", 0.55), ("ruby", 0.55), ("obsidian", 0.82), ("turquoise", 0.8), ("gold", 1.0)])
def test_alphas(name, alpha):
    m = material(name)
    assert m.ambient[3] == m.diffuse[3] == m.specular[3] == alpha


def test_names_are_forgiving_about_spaces_case_and_dashes():
    assert material("Black Plastic") is material("black-plastic") is MATERIALS["black_plastic"]


def test_unknown_name_suggests():
    with pytest.raises(SceneError, match="unknown material 'silvr'; did you mean 'silver'"):
        material("silvr")
