"""Cold start: the prebuilt cffi type table for wgpu-py (wgpu_shading/render/_prebuilt_ffi.py).

Each test runs a fresh Python process, because the table only matters (and can only be
installed) before wgpu's backend is first imported. Nothing here is timed: the tests
check that the fast path is taken, that it draws exactly what wgpu-py's own path draws,
and that every way it can fail falls back to a working render.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

RENDER_AND_REPORT = """
import sys, numpy as np
from wgpu_shading import Renderer
from wgpu_shading.assets.mesh_scene import mesh_scene
renderer = Renderer()
image = renderer.render(mesh_scene("builtin:torus?segments=24", (96, 64), None))
np.save(sys.argv[1], image)
import wgpu.backends.wgpu_native._ffi as ffi_module
print(type(ffi_module.ffi).__name__)
"""


def render_in_new_process(tmp_path: Path, name: str, **environment: str) -> tuple[str, np.ndarray]:
    """(the class name of the FFI wgpu-py ended up with, the rendered image)."""
    out = tmp_path / f"{name}.npy"
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache"), **environment}
    result = subprocess.run(
        [sys.executable, "-c", RENDER_AND_REPORT, str(out)], capture_output=True, text=True, env=env, timeout=120
    )
    assert result.returncode == 0, result.stderr
    return result.stdout.strip(), np.load(out)


def test_prebuilt_table_is_used_cached_and_draws_the_same_image(tmp_path):
    first_kind, first = render_in_new_process(tmp_path, "first")  # builds and caches the table
    assert first_kind == "PrebuiltFFI"
    assert len(list((tmp_path / "cache" / "wgpu-shading").glob("wgpu-ffi-*.txt"))) == 1
    cached_kind, cached = render_in_new_process(tmp_path, "cached")  # reads the cached table
    assert cached_kind == "PrebuiltFFI"
    plain_kind, plain = render_in_new_process(tmp_path, "plain", WGPU_SHADING_PREBUILT_FFI="0")
    assert plain_kind == "FFI"  # wgpu-py's own in-line FFI
    assert (first[:, :, :3] > 0).any()
    np.testing.assert_array_equal(first, plain)
    np.testing.assert_array_equal(cached, plain)


def test_a_damaged_cache_file_is_rebuilt(tmp_path):
    render_in_new_process(tmp_path, "build")
    (table,) = (tmp_path / "cache" / "wgpu-shading").glob("wgpu-ffi-*.txt")
    table.write_text("('truncated', {'_types': b'\\x00")
    kind, image = render_in_new_process(tmp_path, "rebuilt")
    assert kind == "PrebuiltFFI" and (image[:, :, :3] > 0).any()
    assert table.read_text().startswith("(")


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root can write anywhere")
def test_an_unwritable_cache_folder_still_renders(tmp_path):
    (tmp_path / "cache").mkdir()
    (tmp_path / "cache").chmod(0o500)
    try:
        kind, image = render_in_new_process(tmp_path, "unwritable")
    finally:
        (tmp_path / "cache").chmod(0o700)
    assert kind == "PrebuiltFFI" and (image[:, :, :3] > 0).any()


def test_a_cache_path_that_is_a_file_still_renders(tmp_path):
    # Works for root too: nothing can be created below a regular file.
    (tmp_path / "cache").write_text("not a folder")
    kind, image = render_in_new_process(tmp_path, "blocked")
    assert kind == "PrebuiltFFI" and (image[:, :, :3] > 0).any()


@pytest.mark.parametrize(
    "selector, environment",
    [("lavapipe", {}), ("llvmpipe", {}), (None, {"WGPU_SHADING_ADAPTER": "llvmpipe"})],
)
def test_adapter_selection_still_works_on_the_fast_path(tmp_path, selector, environment):
    out = tmp_path / "a.png"
    args = ["render", "builtin:cube", "--size", "32", "-o", str(out), "-q"]
    if selector:
        args += ["--adapter", selector]
    result = _run_cli(args, {"XDG_CACHE_HOME": str(tmp_path / "cache"), **environment})
    assert result.returncode == 0, result.stderr
    assert out.exists()


@pytest.mark.parametrize("args, environment", [(["--adapter", "no-such-gpu"], {}), ([], {"WGPU_SHADING_ADAPTER": "no-such-gpu"})])
def test_an_unknown_adapter_is_still_a_one_line_error(tmp_path, args, environment):
    result = _run_cli(["render", "builtin:cube", "-o", str(tmp_path / "x.png"), *args], environment)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0 and "Traceback" not in result.stderr
    assert "no adapter matches 'no-such-gpu'" in result.stderr


def _run_cli(args: list[str], environment: dict[str, str]) -> subprocess.CompletedProcess:
    import shutil

    executable = shutil.which("wgpu-shading", path=str(Path(sys.executable).parent)) or "wgpu-shading"
    env = {key: value for key, value in os.environ.items() if key != "WGPU_SHADING_ADAPTER"}
    return subprocess.run([executable, *args], capture_output=True, text=True, env={**env, **environment}, timeout=120)


FFI_REJECTED = """
import numpy as np
import wgpu_shading.render._prebuilt_ffi as prebuilt
from wgpu_shading import Renderer
from wgpu_shading.assets.mesh_scene import mesh_scene

built = prebuilt._prebuilt_ffi

def rejected():  # an FFI that a future wgpu-py would use in some way we did not foresee
    ffi = built()
    def refuse(*args, **kwargs):
        raise RuntimeError("unexpected use")
    type(ffi).set_source = refuse
    return ffi

prebuilt._prebuilt_ffi = rejected
print(prebuilt.load_wgpu_native())
image = Renderer().render(mesh_scene("builtin:torus?segments=24", (96, 64), None))
import wgpu.backends.wgpu_native._ffi as ffi_module
print(type(ffi_module.ffi).__name__, bool((image[:, :, :3] > 0).any()))
"""


def test_when_wgpu_py_rejects_the_prebuilt_table_it_imports_normally(tmp_path):
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    result = subprocess.run([sys.executable, "-c", FFI_REJECTED], capture_output=True, text=True, env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["False", "FFI", "True"]


def test_render_of_a_builtin_imports_no_reader_pass_or_tool_it_does_not_use(tmp_path):
    """What `render builtin:torus` imports is what it uses: no mesh-file reader (the glTF
    reader alone was ~13 ms of every start), no golden-image comparison, no dataset pass.
    docs/performance.md#cold-start-process-start-to-png-on-disk."""
    script = (
        "import sys\nfrom wgpu_shading.cli.main import main\n"
        f"status = main(['render', 'builtin:torus?segments=12', '--size', '16', '-o', {str(tmp_path / 't.png')!r}, '-q'])\n"
        "print(' '.join(sorted(name for name in sys.modules if name.startswith('wgpu_shading'))))\n"
        "sys.exit(status)\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    imported = set(result.stdout.split())
    assert "wgpu_shading.render.renderer" in imported and (tmp_path / "t.png").is_file()
    unused = {"wgpu_shading.assets.gltf.reader", "wgpu_shading.assets.mesh_formats.obj", "wgpu_shading.testing.golden",
              "wgpu_shading.testing.comparison", "wgpu_shading.render.passes.extra_outputs", "wgpu_shading.dataset"}
    assert not unused & imported, unused & imported
