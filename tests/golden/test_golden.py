"""The project's golden images: every classic scene (docs/conventions.md#the-classic-scenes) in the shading modes it shows,
every light kind, attenuation, table materials, every texture mode, two-sided lighting
and the infinite viewer (cases.toml, scenes/). References in references/, rendered on
lavapipe (references/ENVIRONMENT.txt says which Mesa). Update after an intended change:

    ./run tests tests/golden --update-golden      # then review the changed PNGs (git diff)
"""

from __future__ import annotations

import pytest

from golden_cases import ENVIRONMENT, SCENES, cases, environment_text

CASES = cases()


@pytest.mark.parametrize("case", CASES, ids=[case.name for case in CASES])
def test_golden(case, assert_golden, renderer):
    try:
        result = assert_golden(case.load(), case.reference)
    except pytest.fail.Exception as failure:
        # Name the Mesa of the references next to this run's, the first suspect of a mismatch.
        recorded = ENVIRONMENT.read_text() if ENVIRONMENT.exists() else "(no ENVIRONMENT.txt)"
        driver = next((line for line in recorded.splitlines() if line.startswith("driver:")), "driver: ?")
        now = renderer.device.adapter.info.get("description", "?")
        raise pytest.fail.Exception(f"{failure.msg}\nreferences {driver}; this run: {now}", pytrace=False) from None
    if result.status in ("created", "updated"):
        ENVIRONMENT.parent.mkdir(parents=True, exist_ok=True)
        ENVIRONMENT.write_text(environment_text(renderer.device))


def test_every_scene_and_reference_is_a_case():
    names = {case.name for case in CASES}
    references = {path.stem for path in CASES[0].reference.parent.glob("*.png")}
    assert not references - names, f"references without a case: {sorted(references - names)}"
    assert {path.stem for path in SCENES.glob("*.toml")} <= names
    assert all(case.scene.is_file() for case in CASES), [str(c.scene) for c in CASES if not c.scene.is_file()]


def test_references_record_the_mesa_that_made_them():
    text = ENVIRONMENT.read_text()
    assert "driver: Mesa " in text and "adapter: llvmpipe" in text, text
