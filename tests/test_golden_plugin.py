"""The pytest plugin (assert_golden, --update-golden, --golden-output) as a user's project
sees it: pytester runs a small test file with the plugin that the installed package
registers, and the `check` command of the CLI."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import imageio.v3 as iio
import pytest

from wgpu_shading.cli import main

pytest_plugins = ["pytester"]

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

USER_TEST = textwrap.dedent(
    """
    import numpy as np

    def image(value):
        img = np.zeros((40, 60, 4), np.uint8)
        img[..., 3] = 255
        img[10:30, 20:40, 0] = value
        return img

    def test_array(assert_golden):
        import os
        assert_golden(image(int(os.environ.get("GOLDEN_VALUE", "200"))), "refs/square.png")
    """
)


def run(pytester, *args: str):
    """pytest in this process on the pytester folder, without the hypothesis plugin
    (it re-imports hypothesis in every inner run: seconds each)."""
    return pytester.runpytest("-p", "no:hypothesispytest", "-p", "no:cacheprovider", *args)


def _value(monkeypatch, value: int) -> None:
    monkeypatch.setenv("GOLDEN_VALUE", str(value))


def test_plugin_is_registered_by_the_package(pytester):
    result = run(pytester, "--help")
    result.stdout.fnmatch_lines(["*--update-golden*", "*--golden-output=DIR*"])


def test_plugin_import_does_not_load_the_gpu_side():
    """pytest imports the plugin in every run of every project that has the package."""
    code = "import sys, wgpu_shading.testing.pytest_plugin; print(sorted(m for m in ('wgpu', 'wgpu_shading.render.renderer', 'wgpu_shading.testing.golden') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_missing_reference_fails_and_says_how_to_create_it(pytester, monkeypatch):
    _value(monkeypatch, 200)
    pytester.makepyfile(test_user=USER_TEST)
    out = pytester.path / "out"
    result = run(pytester, f"--golden-output={out}")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*golden reference*refs/square.png does not exist*", "*pytest --update-golden*"])
    assert list(out.rglob("square.actual.png"))


def test_update_then_pass_then_fail_with_diff_images_then_update(pytester, monkeypatch):
    pytester.makepyfile(test_user=USER_TEST)
    reference = pytester.path / "refs" / "square.png"
    out = pytester.path / "out"

    _value(monkeypatch, 200)
    result = run(pytester, "--update-golden")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["*golden references written*", f"created {reference}"])
    assert iio.imread(reference)[20, 30].tolist() == [200, 0, 0, 255]

    run(pytester).assert_outcomes(passed=1)
    _value(monkeypatch, 204)  # 4/255: within the default threshold
    run(pytester).assert_outcomes(passed=1)

    _value(monkeypatch, 120)  # the square changes by 80/255
    result = run(pytester, f"--golden-output={out}")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(
        [
            f"*golden image mismatch: {reference}",
            "MISMATCH: 400 pixels (16.67 %) of 2400 differ by more than 8/255 (allowed: 0.10 %); max 80/255 at (row 10, col 20, red); 99.9th percentile 80/255",
            "looks like: the largest differences are in the red channel*",
            "*darker*",
            "tolerance: threshold 8/255, max fraction 0.10 %",
            "images: *square.actual.png, *square.expected.png, *square.diff.png",
            "*--update-golden*",
        ]
    )
    diff = next(out.rglob("square.diff.png"))
    assert iio.imread(diff)[20, 30].tolist() == [202, 0, 0, 255]  # 80/255 on the log scale: 255·log2(81)/8
    assert iio.imread(reference)[20, 30, 0] == 200  # a failure never touches the reference

    result = run(pytester, "--update-golden")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines([f"updated {reference}"])
    assert iio.imread(reference)[20, 30, 0] == 120


def test_ini_options_set_the_default_tolerance(pytester, monkeypatch):
    pytester.makepyfile(test_user=USER_TEST)
    _value(monkeypatch, 200)
    run(pytester, "--update-golden").assert_outcomes(passed=1)
    _value(monkeypatch, 180)
    run(pytester).assert_outcomes(failed=1)
    pytester.makeini("[pytest]\ngolden_threshold = 25\n")
    run(pytester).assert_outcomes(passed=1)


def test_scene_file_and_tolerance_argument(pytester, renderer):
    # `renderer` imports the GPU side and creates the device in this process first, so the
    # inner runs reuse them (pytester forgets modules first imported by an inner run).
    pytester.makefile(
        ".toml",
        scene=textwrap.dedent(
            """
            [output]
            size = [48, 48]
            [camera]
            eye = [0.0, 0.0, 3.0]
            [[lights]]
            type = "positional"
            position = [2.0, 2.0, 3.0]
            [[objects]]
            mesh = "builtin:sphere?slices=16&stacks=8"
            material = "jade"
            """
        ),
    )
    pytester.makepyfile(
        test_scene=textwrap.dedent(
            """
            from wgpu_shading.testing.golden import Tolerance

            def test_scene(assert_golden):
                result = assert_golden("scene.toml", "refs/scene.png", tolerance=Tolerance(threshold=2))
                assert result.status in ("passed", "created")

            def test_scene_resized(assert_golden):
                assert_golden("scene.toml", "refs/scene32.png", size=(32, 24))
            """
        )
    )
    run(pytester, "--update-golden").assert_outcomes(passed=2)
    assert iio.imread(pytester.path / "refs" / "scene32.png").shape == (24, 32, 4)
    jade = iio.imread(pytester.path / "refs" / "scene.png")[24, 24]
    assert jade[3] == 255  # jade's alpha 0.95 makes nothing translucent (docs/conventions.md#the-lighting-equation): covered pixels are opaque
    run(pytester).assert_outcomes(passed=2)


# --------------------------------------------------------------------------- the check command


@pytest.fixture
def torus(tmp_path):
    return str(EXAMPLES / "gold_torus_phong.toml")


def test_check_command(tmp_path, torus, capsys):
    reference = tmp_path / "torus.png"
    assert main(["check", torus, "--ref", str(reference), "--size", "64"]) == 2
    assert "does not exist; run again with --update" in capsys.readouterr().err

    assert main(["check", torus, "--ref", str(reference), "--size", "64", "--update"]) == 0
    assert f"created reference {reference}" in capsys.readouterr().out

    assert main(["check", torus, "--ref", str(reference), "--size", "64"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"PASS {reference}: 0 pixels (0 %) of 4096 differ by more than 8/255") and "99.9th percentile 0/255" in out

    assert main(["check", torus, "--ref", str(reference), "--size", "64", "--material", "jade"]) == 1
    out = capsys.readouterr().out
    assert out.startswith(f"FAIL {reference}: ") and "looks like:" in out and "wrote" in out
    for kind in ("actual", "expected", "diff"):
        assert (tmp_path / f"torus.{kind}.png").is_file()

    outdir = tmp_path / "failures"
    outdir.mkdir()
    assert main(["check", torus, "--ref", str(reference), "--size", "48", "--output-dir", str(outdir)]) == 1
    assert "sizes differ: actual 48×48, expected 64×64" in capsys.readouterr().out
    assert (outdir / "torus.actual.png").is_file()

    # Tolerance options: Gouraud instead of Phong differs only around the highlights.
    assert main(["check", torus, "--ref", str(reference), "--size", "64", "--frequency", "gouraud"]) == 1
    capsys.readouterr()
    assert main(["check", torus, "--ref", str(reference), "--size", "64", "--frequency", "gouraud", "--threshold", "60", "-q"]) == 0
    assert capsys.readouterr().out == ""


@pytest.mark.parametrize(
    "args, message",
    [(["--threshold", "300"], "expected an integer 0..255"), (["--max-fraction", "2"], "expected a fraction between 0 and 1")],
)
def test_check_command_rejects_bad_tolerances(torus, capsys, args, message):
    assert main(["check", torus, "--ref", "ref.png", *args]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize(
    "args, message",
    [
        (["--ref", "x.jpg"], "the reference must be a .png file"),
        (["--ref", "ref.png", "--output-dir", "/nonexistent/dir"], "is not an existing folder"),
        (["--ref", "/nonexistent/dir/ref.png", "--update"], "folder '/nonexistent/dir' does not exist"),
    ],
)
def test_check_command_usage_errors_are_one_line(torus, capsys, args, message):
    assert main(["check", torus, "--size", "32", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("wgpu-shading: error: ") and message in err and err.count("\n") == 1


BAD_INPUT_TEST = textwrap.dedent(
    """
    import numpy as np

    def test_bad_scene(assert_golden):
        assert_golden("bad.toml", "refs/bad.png")

    def test_corrupt_reference(assert_golden):
        assert_golden(np.zeros((4, 4, 4), np.uint8), "refs/corrupt.png")
    """
)


def test_bad_scenes_and_references_are_test_failures_with_the_message_not_tracebacks(pytester):
    pytester.makepyfile(test_bad=BAD_INPUT_TEST)
    pytester.path.joinpath("bad.toml").write_text('[[lights]]\ntype = ["spot"]\n')
    (pytester.path / "refs").mkdir()
    (pytester.path / "refs" / "corrupt.png").write_bytes(b"\xff\xd8\xff\xe0 jpeg data")
    result = run(pytester)
    result.assert_outcomes(failed=2)
    output = result.stdout.str()
    assert "[[lights]] #1.type: expected one of 'directional', 'positional', 'spot', got ['spot']" in output
    assert "references are 8-bit PNGs; this file holds JPEG data" in output
    assert "Traceback" not in output and "raise SceneError" not in output and "GoldenError(" not in output
    # --update-golden replaces the unusable reference
    result = run(pytester, "--update-golden", "-k", "corrupt")
    result.assert_outcomes(passed=1)
    assert (pytester.path / "refs" / "corrupt.png").read_bytes().startswith(b"\x89PNG")


def test_the_failure_summary_comes_back_from_xdist_workers(pytester, monkeypatch):
    """Under `pytest -n 2` the tests run in worker processes; their golden failures and
    written references still reach the end-of-run sections the controller prints."""
    pytest.importorskip("xdist")
    pytester.makepyfile(test_user=USER_TEST)
    args = ("-p", "no:hypothesispytest", "-p", "no:cacheprovider", "-n", "2")
    _value(monkeypatch, 200)
    result = pytester.runpytest_subprocess(*args, "--update-golden")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["*golden references written*", "created *square.png"])
    _value(monkeypatch, 120)
    result = pytester.runpytest_subprocess(*args, f"--golden-output={pytester.path / 'out'}")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*golden-image failures*", "test_user.py::test_array: *out*", "*--update-golden*"])


# --------------------------------------------------------------------------- the HTML report

REPORT_TEST = USER_TEST + textwrap.dedent(
    """
    def test_steady(assert_golden):
        assert_golden(image(200), "refs/steady.png")
    """
)


def _data_uris(page: str) -> list[bytes]:
    import base64
    import re

    return [base64.b64decode(m) for m in re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', page)]


def test_golden_report_under_xdist_lists_failures_first_with_images_metrics_and_the_accept_command(pytester, monkeypatch):
    """`pytest -n 2 --golden-report DIR`: the workers' checks reach the controller, which writes
    one page; its images are the very PNGs of the failure, embedded; failures come before passes."""
    pytest.importorskip("xdist")
    pytester.makepyfile(test_user=REPORT_TEST)
    args = ("-p", "no:hypothesispytest", "-p", "no:cacheprovider", "-n", "2")
    _value(monkeypatch, 200)
    pytester.runpytest_subprocess(*args, "--update-golden").assert_outcomes(passed=2)
    _value(monkeypatch, 120)
    result = pytester.runpytest_subprocess(*args, "--golden-report=report")
    result.assert_outcomes(failed=1, passed=1)
    page_path = pytester.path / "report" / "golden-report.html"
    result.stdout.fnmatch_lines([f"*golden report: {page_path}*"])
    page = page_path.read_text(encoding="utf-8")
    assert "1 failed, 1 passed" in page
    failure, passes = page.index('<article class="failure"'), page.index('<section id="passes"')
    assert failure < passes and page.index("test_user.py::test_steady") > passes
    assert "pytest --update-golden test_user.py::test_array" in page[failure:passes]
    assert "400 of 2400 (16.67 %)" in page and "at most 2 (0.10 %)" in page  # the metric against the tolerance
    assert "looks like: the largest differences are in the red channel" in page
    folder = next((pytester.path / "report").glob("*test_array*"))  # the images beside the page, one folder per test
    embedded = _data_uris(page)
    for kind in ("expected", "actual", "diff"):
        assert (folder / f"square.{kind}.png").read_bytes() in embedded
    assert "http://" not in page and "https://" not in page and " src=\"file:" not in page  # nothing fetched
    assert not list((pytester.path / "report").rglob("*wgpu-shading-tmp*"))  # written atomically

    # The accept command, typed as printed, makes the test pass; the next report has no failure.
    accept = next(line for line in page.splitlines() if "pytest --update-golden" in line)
    assert pytester.runpytest_subprocess(*args, "--update-golden", "test_user.py::test_array").ret == 0
    pytester.runpytest_subprocess(*args, "--golden-report=report").assert_outcomes(passed=2)
    page = page_path.read_text(encoding="utf-8")
    assert "0 failed, 2 passed" in page and '<article class="failure"' not in page, accept


def test_golden_report_names_a_missing_reference(pytester):
    pytester.makepyfile(test_user=REPORT_TEST)
    result = run(pytester, "--golden-report=report", "-k", "steady")
    result.assert_outcomes(failed=1)
    page = (pytester.path / "report" / "golden-report.html").read_text(encoding="utf-8")
    assert "MISSING" in page and "steady.png does not exist" in page and "pytest --update-golden test_user.py::test_steady" in page
    assert len(_data_uris(page)) == 1  # the actual image only


def test_check_command_writes_a_report(tmp_path, torus, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["check", torus, "--ref", "torus.png", "--size", "64", "--update"]) == 0
    assert main(["check", torus, "--ref", "torus.png", "--size", "64", "--report", "pass.html", "-q"]) == 0
    page = (tmp_path / "pass.html").read_text(encoding="utf-8")
    assert "0 failed, 1 passed" in page and "0 pixels (0 %) of 4096 differ" in page
    argv = ["check", torus, "--ref", "torus.png", "--size", "64", "--material", "jade", "--report", "fail.html"]
    assert main(argv) == 1
    assert "report: fail.html" in capsys.readouterr().out
    page = (tmp_path / "fail.html").read_text(encoding="utf-8")
    assert "1 failed, 0 passed" in page and "looks like:" in page
    import html
    import shlex

    accept = shlex.join(["wgpu-shading", *argv, "--update"])
    assert html.escape(accept) in page
    assert (tmp_path / "torus.diff.png").read_bytes() in _data_uris(page)
    # The accept command does accept it.
    assert main(shlex.split(accept)[1:]) == 0 and main(argv[:-2]) == 0


@pytest.mark.parametrize(
    "name, message", [("report.txt", "the report is an HTML page; name it .html"), ("nowhere/report.html", "does not exist")]
)
def test_check_report_path_is_checked_before_rendering(torus, capsys, name, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["check", torus, "--ref", "ref.png", "--report", name]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


HOSTILE_NAMES_TEST = textwrap.dedent(
    """
    import os
    import numpy as np
    import pytest

    def image(value):
        img = np.zeros((20, 30, 4), np.uint8)
        img[..., 3] = 255
        img[5:15, 10:20, 0] = value
        return img

    @pytest.mark.parametrize("name", ["<script>alert(1)</script>", "x<y", "x>y", "q\\"u'o&amp;te"])
    def test_named(assert_golden, name):
        # every case its own colour, all compared with one reference name
        value = int(os.environ.get("GOLDEN_VALUE", "200")) + 10 * ["<script>alert(1)</script>", "x<y", "x>y", "q\\"u'o&amp;te"].index(name)
        assert_golden(image(value), f"refs/{len(name)}/same.png")
    """
)


def test_golden_report_of_tests_named_with_html_and_colliding_folder_names(pytester, monkeypatch):
    # Test ids with markup and quotes are text on the page, never markup; ids that read the
    # same once made into folder names (x<y, x>y: both test_named_x_y) keep their own images:
    # before, the second overwrote the first's and the report showed one picture twice.
    import html

    pytester.makepyfile(test_user=HOSTILE_NAMES_TEST)
    _value(monkeypatch, 100)
    run(pytester, "--update-golden").assert_outcomes(passed=4)
    _value(monkeypatch, 140)
    run(pytester, "--golden-report=report").assert_outcomes(failed=4)
    page = (pytester.path / "report" / "golden-report.html").read_text(encoding="utf-8")
    assert "<script>alert" not in page and page.count("<script>") == 1  # the page's own script only
    for name in ("<script>alert(1)</script>", "x<y", "x>y", "q\"u'o&amp;te"):
        assert html.escape(f"test_user.py::test_named[{name}]", quote=True) in page
    actual = [iio.imread(path)[10, 15, 0] for path in sorted((pytester.path / "report").rglob("same.actual.png"))]
    assert sorted(actual) == [140, 150, 160, 170]  # four tests, four folders, four pictures
    cards = page.split('<article class="failure"')[1:]
    assert len(cards) == 4 and len({_data_uris(card)[1] for card in cards}) == 4  # each card its own actual image
