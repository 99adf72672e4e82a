"""docs/images/golden_report.png: the golden report as a browser shows it.

Makes the failure of docs/golden-tests.md (`check --reflection blinn-phong
--blinn-exponent-scale 1` against a Phong reference of the gold torus) with `--report`,
opens the page in headless Chromium (Selenium, the `test` extra; apt: chromium
chromium-driver), puts the slider at 40 % and the pointer on a highlight pixel, and saves a
screenshot of the failure. Run:

    .venv/bin/python docs/make_report_screenshot.py
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from selenium import webdriver
from wgpu_shading.cli import main as wgpu_shading

OUTPUT = Path(__file__).resolve().parent / "images" / "golden_report.png"
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--window-size=1100,1400")  # fmt: skip


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        os.chdir(folder)  # the page shows the command with the short names a user types
        check = ["check", "example:gold_torus_phong.toml", "--ref", "torus.png", "--size", "192"]
        assert wgpu_shading([*check, "--update", "-q"]) == 0
        changed = ["--reflection", "blinn-phong", "--blinn-exponent-scale", "1", "--report", "report.html"]
        assert wgpu_shading([*check, *changed]) == 1
        options = webdriver.ChromeOptions()
        options.binary_location = shutil.which("chromium")
        for flag in (*FLAGS, f"--user-data-dir={folder / 'profile'}"):
            options.add_argument(flag)
        browser = webdriver.Chrome(service=webdriver.ChromeService(executable_path=shutil.which("chromedriver")), options=options)
        try:
            browser.get((folder / "report.html").as_uri())
            browser.execute_script(
                """const r = document.querySelector('input.split'); r.value = 40; r.dispatchEvent(new Event('input'));
                const img = document.querySelector('figure.actual img'); const box = img.getBoundingClientRect();
                img.dispatchEvent(new MouseEvent('mousemove', {clientX: box.left + 84.5, clientY: box.top + 76.5, bubbles: true}));"""
            )
            browser.find_element("css selector", "article.failure").screenshot(str(OUTPUT))
        finally:
            browser.quit()
    print(f"wrote {OUTPUT}")


if __name__ == "__main__":
    main()
