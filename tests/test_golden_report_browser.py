"""The golden report (`pytest --golden-report DIR`, `check --report FILE.html`) in a real
browser: headless Chromium (Debian's `chromium` and `chromium-driver`, which `./run tests`
installs) driven by Selenium (the `test` extra). The page must load from file:// without a
console error, every image must decode, the slider and the blink must change what is shown
(read back from screenshots of the page), zoom must enlarge to whole pixels and the pixel
read-out must name the values under the pointer.

Skipped, with the reason, only where the browser cannot be started."""

from __future__ import annotations

import io
import shutil
import textwrap
import time

import numpy as np
import pytest
from PIL import Image

webdriver = pytest.importorskip("selenium.webdriver", reason="Selenium is not installed (the `test` extra: pip install -e '.[test]')")

RED, BLUE = (200, 0, 0), (0, 0, 200)
# The expected image is red, the actual one blue (a 3 × 5 block in the corner is green in
# both, so the read-out can be checked on a pixel that does not differ).
REPORT_TEST = textwrap.dedent(
    """
    import os
    import numpy as np

    def image(color):
        img = np.zeros((48, 64, 4), np.uint8)
        img[..., :3] = color
        img[..., 3] = 255
        img[:3, :5] = (0, 255, 0, 255)
        return img

    def test_color(assert_golden):
        assert_golden(image((0, 0, 200) if os.environ.get("GOLDEN_BLUE") else (200, 0, 0)), "refs/color.png")

    def test_steady(assert_golden):
        assert_golden(image((9, 9, 9)), "refs/steady.png")
    """
)
CHROMIUM_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run", "--window-size=1280,1600",
)  # fmt: skip


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    binary, driver = shutil.which("chromium"), shutil.which("chromedriver")
    if binary is None or driver is None:
        pytest.skip("Chromium or its driver is not installed (apt: chromium chromium-driver; ./run tests installs them)")
    from selenium.common.exceptions import WebDriverException

    options = webdriver.ChromeOptions()
    options.binary_location = binary
    for flag in (*CHROMIUM_FLAGS, f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    try:
        chrome = webdriver.Chrome(service=webdriver.ChromeService(executable_path=driver), options=options)
    except WebDriverException as error:
        pytest.skip(f"headless Chromium could not be started: {str(error.msg).splitlines()[0] if error.msg else error}")
    try:
        yield chrome
    finally:
        chrome.quit()


@pytest.fixture(scope="module")
def report_page(tmp_path_factory):
    """A report made as a user makes one: pytest with the plugin, a reference, then a change."""
    import os
    import subprocess
    import sys

    folder = tmp_path_factory.mktemp("user-project")
    (folder / "test_user.py").write_text(REPORT_TEST)
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:hypothesispytest"]
    env = {k: v for k, v in os.environ.items() if k != "GOLDEN_BLUE"}
    subprocess.run([*command, "--update-golden"], cwd=folder, env=env, check=True, capture_output=True)
    run = subprocess.run([*command, "--golden-report=report"], cwd=folder, env={**env, "GOLDEN_BLUE": "1"}, capture_output=True, text=True)
    assert run.returncode == 1, run.stdout
    return folder / "report" / "golden-report.html"


def _open(browser, page) -> None:
    browser.get(page.as_uri())
    browser.get_log("browser")  # (an earlier page's messages)
    browser.refresh()
    deadline = time.monotonic() + 20
    while not browser.execute_script(
        "return document.readyState === 'complete' && Array.from(document.images).every(i => i.complete)"
    ):
        assert time.monotonic() < deadline, "the page's images never finished loading"
        time.sleep(0.1)


def _errors(browser) -> list[str]:
    return [entry["message"] for entry in browser.get_log("browser") if entry["level"] in ("SEVERE", "WARNING")]


def _shown(element) -> np.ndarray:
    """What the browser draws for `element`, as an RGB array (a screenshot of it)."""
    return np.asarray(Image.open(io.BytesIO(element.screenshot_as_png)).convert("RGB")).astype(int)


def _near(pixel, color, tolerance=12) -> bool:
    return bool(np.all(np.abs(np.asarray(pixel) - np.asarray(color)) <= tolerance))


def test_the_report_loads_without_errors_and_its_images_decode(browser, report_page):
    _open(browser, report_page)
    assert _errors(browser) == []
    sizes = browser.execute_script("return Array.from(document.images).map(i => [i.getAttribute('data-role'), i.naturalWidth, i.naturalHeight])")
    roles = sorted(role for role, *_ in sizes)
    assert roles == ["actual", "diff", "expected", "over", "under"], sizes
    assert all(width > 0 and height > 0 for _, width, height in sizes), sizes
    assert browser.execute_script("return document.querySelectorAll('article.failure').length") == 1
    assert "test_user.py::test_steady" in browser.find_element("css selector", "table.passes").text
    assert browser.find_element("css selector", "code.command").text == "pytest --update-golden test_user.py::test_color"


def test_zoom_shows_whole_pixels_and_the_readout_names_the_pixel(browser, report_page):
    _open(browser, report_page)
    browser.execute_script("const s = document.querySelector('select.zoom'); s.value = '8'; s.dispatchEvent(new Event('change'))")
    expected = browser.find_element("css selector", "figure.expected img")
    assert browser.execute_script("return arguments[0].getBoundingClientRect().width", expected) == 64 * 8
    assert browser.execute_script("return getComputedStyle(arguments[0]).imageRendering", expected) == "pixelated"
    shown = _shown(expected)
    # The green block is 5 × 3 source pixels: 40 × 24 screen pixels at 8×, edges sharp (no smoothing).
    assert _near(shown[23, 39], (0, 255, 0), 0) and _near(shown[24, 40], RED, 0) and _near(shown[23, 40], RED, 0)

    def readout(row, col):
        browser.execute_script(
            """const [img, x, y] = arguments; const r = img.getBoundingClientRect();
            img.dispatchEvent(new MouseEvent('mousemove', {clientX: r.left + x, clientY: r.top + y, bubbles: true}));""",
            expected, col * 8 + 4, row * 8 + 4,
        )
        return browser.find_element("css selector", ".pixel").text

    assert readout(1, 2) == "row 1, col 2: expected 0 255 0 255 · actual 0 255 0 255 · difference 0 0 0 0 (RGBA, /255)"
    assert readout(20, 30) == "row 20, col 30: expected 200 0 0 255 · actual 0 0 200 255 · difference -200 0 +200 0 (RGBA, /255)"
    assert _errors(browser) == []


def test_the_slider_shows_actual_left_of_it_and_expected_right(browser, report_page):
    _open(browser, report_page)
    stack = browser.find_element("css selector", ".stack")

    def slide(position: int) -> np.ndarray:
        browser.execute_script(
            "const r = document.querySelector('input.split'); r.value = arguments[0]; r.dispatchEvent(new Event('input'))", position
        )
        return _shown(stack)

    middle_row = stack.size["height"] // 2
    everything_expected, everything_actual = slide(0), slide(100)
    assert _near(everything_expected[middle_row, 5], RED) and _near(everything_expected[middle_row, -5], RED)
    assert _near(everything_actual[middle_row, 5], BLUE) and _near(everything_actual[middle_row, -5], BLUE)
    half = slide(50)
    assert _near(half[middle_row, 5], BLUE) and _near(half[middle_row, -5], RED)
    # A real drag on the slider (mouse events, not a set value) moves it too.
    from selenium.webdriver.common.action_chains import ActionChains

    handle = browser.find_element("css selector", "input.split")
    ActionChains(browser).move_to_element(handle).click_and_hold().move_by_offset(-(handle.size["width"] // 2) + 1, 0).release().perform()
    assert int(handle.get_attribute("value")) == 0 and _near(_shown(stack)[middle_row, -5], RED)
    assert _errors(browser) == []


def test_blink_alternates_expected_and_actual(browser, report_page):
    _open(browser, report_page)
    stack = browser.find_element("css selector", ".stack")
    browser.find_element("css selector", ".compare input[value=blink]").click()
    seen, labels = set(), set()
    deadline = time.monotonic() + 5
    while len(seen) < 2 and time.monotonic() < deadline:
        pixel = _shown(stack)[stack.size["height"] // 2, stack.size["width"] // 2]
        seen |= {name for name, color in (("red", RED), ("blue", BLUE)) if _near(pixel, color)}
        labels.add(browser.find_element("css selector", ".compare .showing").text)
        time.sleep(0.15)
    assert seen == {"red", "blue"} and labels == {"showing: expected", "showing: actual"}
    # Back to the slider: the blinking stops.
    browser.find_element("css selector", ".compare input[value=slider]").click()
    first = _shown(stack)
    time.sleep(1.0)
    assert np.array_equal(first, _shown(stack))
    assert _errors(browser) == []


def test_the_check_command_report_loads_too(browser, tmp_path, monkeypatch):
    from wgpu_shading.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["check", "example:gold_torus_phong.toml", "--ref", "t.png", "--size", "48", "--update", "-q"]) == 0
    assert main(["check", "example:gold_torus_phong.toml", "--ref", "t.png", "--size", "48", "--material", "jade", "--report", "r.html"]) == 1
    _open(browser, tmp_path / "r.html")
    assert _errors(browser) == []
    assert browser.execute_script("return Array.from(document.images).every(i => i.naturalWidth > 0)")
    assert "--update" in browser.find_element("css selector", "code.command").text
