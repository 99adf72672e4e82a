"""pytest plugin for golden-image tests, installed with wgpu-shading (entry point `pytest11`).

    def test_torus(assert_golden):
        assert_golden("scenes/torus.toml", "references/torus.png")        # a scene file
        assert_golden(my_scene, "references/mine.png", size=(128, 128))   # a Scene
        assert_golden(my_image_array, "references/array.png")             # any image

Paths are relative to the test file's folder. The fixture renders scenes with the
session-wide `golden_renderer` fixture (override it in a conftest.py to hand in your own
Renderer), compares with the reference PNG and fails with a message that says how many
pixels differ, by how much, where, and what the difference looks like; the actual,
expected and (log-scaled) diff images are written to --golden-output (default: a `golden`
folder in pytest's temporary directory) and named in the message.

Options:
    --update-golden         write missing references and rewrite those that differ
    --golden-output DIR     where to write the images of failures
    --golden-report DIR     write DIR/golden-report.html: every failure with its images, a
                            slider/blink comparison, the metrics, the diagnosis and the
                            command that accepts it; the checks that passed below it
ini options (pytest.ini / pyproject [tool.pytest.ini_options]):
    golden_threshold        default per-channel threshold (1/255 units), 8
    golden_max_fraction     default fraction of pixels allowed over it, 0.001

This module is imported in every pytest run of every project that installed
wgpu-shading, so it imports only pytest at load time; numpy, the comparison and the
renderer are imported when a test first uses the fixture.
"""

from __future__ import annotations

import hashlib
import os
import re
from pathlib import Path

import pytest

_STASH_WRITTEN = pytest.StashKey[list]()
_STASH_FAILED = pytest.StashKey[list]()
_STASH_ENTRIES = pytest.StashKey[list]()
REPORT_NAME = "golden-report.html"


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("wgpu-shading", "golden-image tests (wgpu-shading)")
    group.addoption(
        "--update-golden",
        action="store_true",
        default=False,
        help="assert_golden: write missing reference images and rewrite those that differ (matching ones are left alone)",
    )
    group.addoption(
        "--golden-output",
        metavar="DIR",
        default=None,
        help="assert_golden: folder for the actual/expected/diff images of failures (default: the --golden-report folder, else <pytest basetemp>/golden)",
    )
    group.addoption(
        "--golden-report",
        metavar="DIR",
        default=None,
        help=f"assert_golden: write DIR/{REPORT_NAME}, one page to open in a browser: failures with expected | actual | diff, "
        "slider and blink comparison, zoom, metrics, diagnosis and the command that accepts each; passes below",
    )
    parser.addini("golden_threshold", "assert_golden: per-channel threshold in units of 1/255 (default 8)", default=None)
    parser.addini("golden_max_fraction", "assert_golden: fraction of pixels allowed over the threshold (default 0.001)", default=None)


# What a test did to its references travels in the test's report (user_properties), not in
# this process's memory: under pytest-xdist (`pytest -n 2`) the tests run in worker processes
# and only their reports reach the controller that prints the end-of-run summary.
_PROPERTY = "wgpu_shading_golden"


def pytest_configure(config: pytest.Config) -> None:
    config.stash[_STASH_WRITTEN] = []
    config.stash[_STASH_FAILED] = []
    config.stash[_STASH_ENTRIES] = []
    config.pluginmanager.register(_GoldenReports(config), "wgpu-shading-golden-reports")


def _record(request: pytest.FixtureRequest, kind: str, line: str) -> None:
    request.node.user_properties.append((_PROPERTY, f"{kind}\t{line}"))


class _GoldenReports:
    """Collects the golden lines of each finished test, whether it ran in this process or in
    an xdist worker (its teardown report carries every property the test recorded)."""

    def __init__(self, config: pytest.Config):
        self.config = config

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.when != "teardown":
            return
        for name, value in report.user_properties:
            if name == _PROPERTY:
                kind, _, line = str(value).partition("\t")
                stash = {"written": _STASH_WRITTEN, "failed": _STASH_FAILED, "entry": _STASH_ENTRIES}[kind]
                self.config.stash[stash].append(line)


def _report_folder(config: pytest.Config) -> Path | None:
    option = config.getoption("--golden-report")
    if not option:
        return None
    folder = Path(option)
    return folder if folder.is_absolute() else Path(config.invocation_params.dir) / folder


def pytest_sessionfinish(session: pytest.Session, exitstatus) -> None:
    """The controller (or a run without xdist) writes the report; xdist workers only send
    their entries (they have `workerinput`)."""
    config = session.config
    folder = _report_folder(config)
    if folder is None or hasattr(config, "workerinput"):
        return
    from .report import ReportEntry, write_report
    from .tolerance import GoldenError

    # Sorted by test: under xdist they arrive in the order the workers finish.
    entries = sorted((ReportEntry.from_json(text) for text in config.stash.get(_STASH_ENTRIES, [])), key=lambda e: (e.name, e.reference))
    arguments = " ".join(config.invocation_params.args)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        write_report(folder / REPORT_NAME, entries, title="Golden-image report", context=f"pytest {arguments}".strip())
    except (OSError, GoldenError) as error:
        config.stash[_STASH_FAILED].append(f"the golden report could not be written: {error}")


def pytest_terminal_summary(terminalreporter, exitstatus, config: pytest.Config) -> None:
    written = config.stash.get(_STASH_WRITTEN, [])
    failed = config.stash.get(_STASH_FAILED, [])
    if written:
        terminalreporter.section("golden references written")
        for line in written:
            terminalreporter.write_line(line)
    if failed:
        terminalreporter.section("golden-image failures")
        for line in failed:
            terminalreporter.write_line(line)
        terminalreporter.write_line("(if the change is intended, rerun with --update-golden and review the new references)")
    folder = _report_folder(config)
    if folder is not None and (folder / REPORT_NAME).is_file():
        terminalreporter.write_sep("-", f"golden report: {folder / REPORT_NAME}")


@pytest.fixture(scope="session")
def golden_renderer():
    """The Renderer that assert_golden renders scenes with: one per test session (lavapipe
    by default). Override this fixture to use your own Renderer or device."""
    from ..render.renderer import Renderer

    return Renderer()


@pytest.fixture(scope="session")
def golden_tolerance(pytestconfig: pytest.Config):
    """The default Tolerance of assert_golden: the package defaults, or the ini options
    golden_threshold / golden_max_fraction. Override this fixture for another default."""
    from .golden import Tolerance

    values = {}
    threshold = pytestconfig.getini("golden_threshold")
    fraction = pytestconfig.getini("golden_max_fraction")
    try:
        if threshold not in (None, ""):
            values["threshold"] = int(threshold)
        if fraction not in (None, ""):
            values["max_fraction"] = float(fraction)
    except ValueError as error:
        raise pytest.UsageError(f"golden_threshold / golden_max_fraction: {error}") from None
    return Tolerance(**values)


class GoldenChecker:
    """The callable behind the `assert_golden` fixture."""

    def __init__(self, request: pytest.FixtureRequest, tolerance):
        self._request = request
        self._default_tolerance = tolerance
        self._config = request.config

    def _resolve(self, path) -> Path:
        path = Path(path)
        return path if path.is_absolute() else Path(self._request.path).parent / path

    def _output_dir(self, reference: Path) -> Path:
        option = self._config.getoption("--golden-output")
        if option:
            base = Path(option)
            if not base.is_absolute():
                base = Path(self._config.rootpath) / base
        elif _report_folder(self._config) is not None:
            base = _report_folder(self._config)  # the images beside the page: one artifact
        else:
            base = self._request.getfixturevalue("tmp_path_factory").getbasetemp() / "golden"
        # One folder per test, so references with the same name in different tests do not
        # collide. A node id whose parameters had to be changed to make a folder name
        # (test_x[a<b] and test_x[a>b] both read test_x_a_b) or that was cut short gets a
        # hash of the whole id: one test's images overwrote the other's, and the golden
        # report showed the same pictures for both.
        nodeid = self._request.node.nodeid
        test = re.sub(r"[^A-Za-z0-9_.-]+", "_", nodeid).strip("_")
        if test != re.sub(r"::|/", "_", nodeid) or len(test) > 150:
            test = f"{test[:150]}-{hashlib.sha1(nodeid.encode('utf-8', 'surrogatepass')).hexdigest()[:10]}"
        return base / test

    def render(self, scene, size=None):
        """A Scene, or a scene file (.toml, relative to the test file) → (H, W, 4) uint8."""
        from dataclasses import replace

        from ..scene import Scene

        if isinstance(scene, (str, os.PathLike)):
            from ..assets.scenefile import load_scene

            scene = load_scene(self._resolve(scene))
        if not isinstance(scene, Scene):
            raise TypeError(f"assert_golden: expected a Scene, a scene file path or an image array, got {type(scene).__name__}")
        if size is not None:
            scene = replace(scene, size=tuple(size))
        renderer = self._request.getfixturevalue("golden_renderer")
        return renderer.render(scene)

    def __call__(self, subject, reference, *, tolerance=None, size=None, amplification=None):
        """Render `subject` (a Scene or a .toml path) or take it as an image (an array), and
        compare it with the reference PNG; fail the test with a readable message if they
        differ. Returns the golden.CheckResult (.status: "passed", or "created"/"updated"
        with --update-golden; .comparison: the metrics). A bad scene, mesh or reference is a
        test failure with its one-line message, not a traceback."""
        __tracebackhide__ = True
        from ..errors import WgpuShadingError

        try:
            return self._check(subject, reference, tolerance=tolerance, size=size, amplification=amplification)
        except WgpuShadingError as error:
            pytest.fail(f"assert_golden({_describe(subject)}, {str(reference)!r}): {error}", pytrace=False)

    def _check(self, subject, reference, *, tolerance, size, amplification):
        __tracebackhide__ = True
        from .golden import DEFAULT_AMPLIFICATION, check_image, write_failure_images
        from ..scene import Scene

        if isinstance(subject, (str, os.PathLike, Scene)):
            image = self.render(subject, size)
        else:
            if size is not None:
                raise TypeError("assert_golden: size= applies to scenes, not to images")
            image = subject
        reference = self._resolve(reference)
        update = self._config.getoption("--update-golden")
        tolerance = tolerance if tolerance is not None else self._default_tolerance
        output_dir = self._output_dir(reference)
        if not update and not reference.exists():
            written = write_failure_images(image, None, reference, output_dir)
            _record(self._request, "failed", f"{self._request.node.nodeid}: {output_dir}")
            if _report_folder(self._config) is not None:
                from .report import entry_for_missing

                entry = entry_for_missing(self._request.node.nodeid, reference, written[0], self.accept_command())
                _record(self._request, "entry", entry.to_json())
            pytest.fail(
                f"golden reference {reference} does not exist\n"
                f"the actual image is at {written[0]}\n"
                "create the reference with: pytest --update-golden",
                pytrace=False,
            )
        result = check_image(
            image,
            reference,
            tolerance,
            update=update,
            output_dir=output_dir,
            amplification=amplification if amplification is not None else DEFAULT_AMPLIFICATION,
        )
        if _report_folder(self._config) is not None:
            from .report import entry_for_result

            entry = entry_for_result(self._request.node.nodeid, result, self.accept_command())
            _record(self._request, "entry", entry.to_json())
        if result.status in ("created", "updated"):
            _record(self._request, "written", f"{result.status} {reference}")
            return result
        if result.status == "failed":
            _record(self._request, "failed", f"{self._request.node.nodeid}: {output_dir}")
            comparison = result.comparison
            lines = [f"golden image mismatch: {reference}", comparison.message, f"tolerance: {tolerance.describe()}"]
            lines.append("images: " + ", ".join(str(p) for p in result.written))
            if result.diff_scale:
                lines.append(f"diff image: {result.diff_scale}")
            lines.append("if the change is intended, rerun with --update-golden and review the new reference")
            pytest.fail("\n".join(lines), pytrace=False)
        return result


    def accept_command(self) -> str:
        """The command that accepts this test's actual images, typed where pytest was run:
        `pytest --update-golden path/test_file.py::test_name[param]`."""
        import shlex

        node = self._request.node
        _, separator, inside = node.nodeid.partition("::")
        try:
            file = os.path.relpath(node.path, self._config.invocation_params.dir)
        except ValueError:  # another drive (Windows)
            file = str(node.path)
        return shlex.join(["pytest", "--update-golden", f"{file}{separator}{inside}"])


def _describe(subject) -> str:
    if isinstance(subject, (str, os.PathLike)):
        return repr(str(subject))
    return type(subject).__name__


@pytest.fixture
def assert_golden(request: pytest.FixtureRequest, golden_tolerance) -> GoldenChecker:
    """assert_golden(scene_or_image, "references/name.png", tolerance=None, size=None):
    compare with a stored PNG; --update-golden writes it. See wgpu_shading.pytest_plugin."""
    return GoldenChecker(request, golden_tolerance)
