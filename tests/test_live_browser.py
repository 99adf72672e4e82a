"""The notebook widget in a real browser: JupyterLab in headless Chromium (Debian's
`chromium` and `chromium-driver`), driven by Selenium. The cell `wgpu_shading.view(...)`
must show render's pixels in the page (the <img> jupyter_rfb draws into, decoded here), and
a key pressed on the widget must change the picture as in the window.

Opt-in by installation: it needs JupyterLab and Selenium in the environment and Chromium
with its driver on the machine (several hundred MB that `./run tests` does not install;
docs/viewer.md says why), and takes ~30 s. Without them it is skipped, saying what is missing."""

from __future__ import annotations

import base64
import io
import json
import os
import shlex
import shutil
import socket
import subprocess
import sys
import time
import urllib.request

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.cli import main

pytest.importorskip("rendercanvas.jupyter", reason="the [view] extra (rendercanvas, jupyter_rfb) is not installed")
pytest.importorskip("jupyterlab", reason="JupyterLab is not installed (pip install jupyterlab selenium)")
webdriver = pytest.importorskip("selenium.webdriver", reason="Selenium is not installed (pip install selenium)")
BROWSER, DRIVER = shutil.which("chromium"), shutil.which("chromedriver")
pytestmark = pytest.mark.skipif(
    BROWSER is None or DRIVER is None, reason="Chromium or its driver is not installed (apt: chromium chromium-driver)"
)

TOKEN = "wgpu-shading-smoke"
CELLS = (
    'import wgpu_shading\nw = wgpu_shading.view("builtin:torus", size=(160, 120))\nw',
    "import shlex\nprint(shlex.join(w.command()))",
)


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _notebook() -> dict:
    return {
        "cells": [{"cell_type": "code", "execution_count": None, "metadata": {}, "outputs": [], "source": cell} for cell in CELLS],
        "metadata": {"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}},
        "nbformat": 4, "nbformat_minor": 5,
    }


def _wait(condition, seconds: float, what: str):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            value = condition()
        except Exception:  # the page is still being built
            value = None
        if value:
            return value
        time.sleep(0.25)
    raise AssertionError(f"timed out after {seconds:.0f} s waiting for {what}")


def _shown(browser, img) -> np.ndarray:
    """The image the page shows, decoded from the very bytes the widget sent (a data: URL for
    the first frame, a blob: URL after it; the page reads the blob back for us)."""
    source = browser.execute_async_script(
        """const [img, done] = arguments;
        fetch(img.src).then(r => r.blob()).then(b => {
            const reader = new FileReader(); reader.onload = () => done(reader.result); reader.readAsDataURL(b);
        }).catch(e => done('error: ' + e));""",
        img,
    )
    assert source.startswith("data:image/png;base64,"), f"not a lossless frame: {source[:40]}"
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(source.split(",", 1)[1]))).convert("RGBA"))


def _rendered(tmp_path, *flags: str) -> np.ndarray:
    out = tmp_path / "render.png"
    assert main(["render", "builtin:torus", "--size", "160x120", *flags, "-o", str(out), "-q"]) == 0
    return np.asarray(Image.open(out).convert("RGBA"))


def test_widget_in_jupyterlab_shows_renders_pixels_and_takes_keys(tmp_path):
    (tmp_path / "smoke.ipynb").write_text(json.dumps(_notebook()))
    port = _free_port()
    home = tmp_path / "jupyter"
    env_dirs = {"JUPYTER_CONFIG_DIR": home / "config", "JUPYTER_RUNTIME_DIR": home / "runtime", "IPYTHONDIR": home / "ipython"}
    server = subprocess.Popen(
        [sys.executable, "-m", "jupyterlab", "--no-browser", "--allow-root", f"--port={port}", "--ip=127.0.0.1",
         f"--ServerApp.token={TOKEN}", f"--ServerApp.root_dir={tmp_path}",
         f"--LabApp.user_settings_dir={home / 'settings'}", f"--LabApp.workspaces_dir={home / 'workspaces'}",
         "--LabApp.expose_app_in_browser=True"],
        env={**os.environ, **{k: str(v) for k, v in env_dirs.items()}},
        stdout=subprocess.DEVNULL, stderr=(tmp_path / "server.log").open("w"),
    )
    browser = None
    try:
        _wait(lambda: urllib.request.urlopen(f"http://127.0.0.1:{port}/api/status?token={TOKEN}", timeout=2).status == 200,
              60, "JupyterLab to start")
        options = webdriver.ChromeOptions()
        options.binary_location = BROWSER
        for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1200,900"):
            options.add_argument(argument)
        browser = webdriver.Chrome(service=webdriver.ChromeService(executable_path=DRIVER), options=options)
        browser.get(f"http://127.0.0.1:{port}/lab/tree/smoke.ipynb?token={TOKEN}")
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.common.by import By

        # Cells are run through JupyterLab's own commands (the app is exposed to the page with
        # --LabApp.expose_app_in_browser): clicking into a cell's editor races the page's layout.
        _wait(lambda: browser.execute_script(
            "const w = window.jupyterapp && window.jupyterapp.shell.currentWidget;"
            "return !!(w && w.sessionContext && w.content && w.content.widgets.length === 2)"), 120, "the notebook")

        def run_cell(index: int) -> None:
            answer = browser.execute_async_script(
                """const [index, done] = arguments;
                const panel = window.jupyterapp.shell.currentWidget;
                panel.sessionContext.ready
                    .then(() => { panel.content.activeCellIndex = index; return window.jupyterapp.commands.execute('notebook:run-cell'); })
                    .then(() => done('ok'), (error) => done('error: ' + error));""",
                index,
            )
            assert answer == "ok", answer

        browser.set_script_timeout(120)
        img = None
        for _ in range(3):  # a run request sent while the kernel connects can be lost: send it again
            run_cell(0)
            try:
                img = _wait(lambda: browser.find_element(By.CSS_SELECTOR, "img.renderview-view[src^='data:image/png']"),
                            40, "the widget's first frame")
                break
            except AssertionError:
                continue
        assert img is not None, "the first cell never showed the widget"
        # (jupyter_rfb may show a 1×1 placeholder until the first frame arrives)
        shown = _wait(lambda: (frame := _shown(browser, img)).shape == (120, 160, 4) and [frame], 60, "a 160×120 frame")[0]
        assert np.array_equal(shown, _rendered(tmp_path)), "the browser shows other pixels than render writes"
        first = img.get_attribute("src")
        browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", img)
        # A drag on the picture (pointer down also gives the widget the keyboard), then F.
        ActionChains(browser).move_to_element(img).click_and_hold().move_by_offset(30, 10).release().perform()
        ActionChains(browser).send_keys("f").perform()
        title = lambda: browser.find_element(By.CSS_SELECTOR, ".renderview-top").text  # noqa: E731
        _wait(lambda: "flat shading" in title(), 60, f"the title to say flat shading after F (it says {title()!r})")
        # The last frame of an interaction is lossless: wait until it is the flat, turned view.
        _wait(lambda: img.get_attribute("src") != first, 60, "a new frame")
        # The second cell prints the render command of the view shown; it draws those pixels.
        run_cell(1)
        printed = _wait(lambda: next(e.text for e in browser.find_elements(By.CSS_SELECTOR, ".jp-OutputArea-output pre")
                                     if e.text.startswith("wgpu-shading render")), 60, "the printed command")
        argv = shlex.split(printed.strip())
        assert "--frequency=flat" in argv and any(a.startswith("--camera-position=") for a in argv), printed
        out = tmp_path / "printed.png"
        assert main([*argv[1:], "-o", str(out), "-q"]) == 0
        assert np.array_equal(_shown(browser, img), np.asarray(Image.open(out).convert("RGBA")))
    except AssertionError:
        if browser is not None:  # what the page looked like, for whoever reads the failure
            browser.save_screenshot(str(tmp_path / "page.png"))
            print(f"screenshot of the page: {tmp_path / 'page.png'}")
        raise
    finally:
        if browser is not None:
            browser.quit()
        server.terminate()
        try:
            server.wait(timeout=20)
        except subprocess.TimeoutExpired:
            server.kill()
