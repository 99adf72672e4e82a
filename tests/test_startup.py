"""Cold start: the prebuilt cffi type table for wgpu-py (wgpu_shading/render/_prebuilt_ffi.py).

Each test runs a fresh Python process, because the table only matters (and can only be
installed) before wgpu's backend is first imported. Nothing here is timed: the tests
check that the fast path is taken, that it draws exactly what wgpu-py's own path draws,
and that every way it can fail falls back to a working render.
"""

from __future__ import annotations

import marshal
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
    assert len(list((tmp_path / "cache" / "wgpu-shading").glob("wgpu-ffi-*.marshal"))) == 1
    cached_kind, cached = render_in_new_process(tmp_path, "cached")  # reads the cached table
    assert cached_kind == "PrebuiltFFI"
    plain_kind, plain = render_in_new_process(tmp_path, "plain", WGPU_SHADING_PREBUILT_FFI="0")
    assert plain_kind == "FFI"  # wgpu-py's own in-line FFI
    assert (first[:, :, :3] > 0).any()
    np.testing.assert_array_equal(first, plain)
    np.testing.assert_array_equal(cached, plain)


def test_a_damaged_cache_file_is_rebuilt(tmp_path):
    render_in_new_process(tmp_path, "build")
    (table,) = (tmp_path / "cache" / "wgpu-shading").glob("wgpu-ffi-*.marshal")
    whole = table.read_bytes()
    for damage in (whole[: len(whole) // 2], marshal.dumps(("a name", {"_types": 3.5})), marshal.dumps([1, 2])):
        table.write_bytes(damage)
        kind, image = render_in_new_process(tmp_path, "rebuilt")
        assert kind == "PrebuiltFFI" and (image[:, :, :3] > 0).any()
        assert marshal.loads(table.read_bytes()) == marshal.loads(whole)


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
              "wgpu_shading.testing.comparison", "wgpu_shading.render.passes.extra_outputs", "wgpu_shading.dataset",
              "wgpu_shading.render.passes.shadow", "wgpu_shading.render.passes.shadow_views", "wgpu_shading.render.gpu.shadow_maps",
              "wgpu_shading.render.passes.strokes", "wgpu_shading.render.gpu.stroke_uploads", "wgpu_shading.testing.images",
              "wgpu_shading.testing.tolerance"}
    assert not unused & imported, unused & imported


# The installed program ends its process without Python's teardown (cli/process_end.py)
# and starts numpy with one OpenBLAS thread unless the user chose (cli/main.py console_main).

CONSOLE_WITH_REPORTED_END = """
import gc, importlib, os, sys
sys.argv = ["wgpu-shading", *(sys.argv[1:] or ["materials"])]
program = importlib.import_module("wgpu_shading.cli.main")  # the module (the package's `main` is the function)
program.end_process = lambda code: print(
    "END", os.environ.get("OPENBLAS_NUM_THREADS"), code, gc.isenabled(), gc.get_freeze_count() > 1000,
    "lvp_icd." in os.environ.get("VK_DRIVER_FILES", ""),
)
program.console_main()
"""


@pytest.mark.parametrize("chosen, expected", [(None, "1"), ("3", "3")])
def test_the_program_runs_numpy_with_one_blas_thread_unless_the_user_chose(chosen, expected):
    env = {key: value for key, value in os.environ.items() if key != "OPENBLAS_NUM_THREADS"}
    if chosen:
        env["OPENBLAS_NUM_THREADS"] = chosen
    result = subprocess.run([sys.executable, "-c", CONSOLE_WITH_REPORTED_END], capture_output=True, text=True, env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[-1].split()[:3] == ["END", expected, "0"]


def _reported_end(*arguments: str, **environment: str) -> list[str]:
    env = {key: value for key, value in os.environ.items() if not key.startswith(("VK_DRIVER_FILES", "VK_ICD_FILENAMES", "WGPU_SHADING_ADAPTER"))}
    result = subprocess.run([sys.executable, "-c", CONSOLE_WITH_REPORTED_END, *arguments], capture_output=True, text=True,
                            env={**env, **environment}, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout.splitlines()[-1].split()


def test_the_command_runs_with_the_garbage_collector_on_and_the_start_up_objects_frozen(tmp_path):
    # Off while the program imports (cli/process_start.py); a long command must collect.
    assert _reported_end("render", "builtin:torus?segments=8", "--size", "16", "-o", str(tmp_path / "t.png"), "-q")[3:5] == ["True", "True"]


def test_a_lavapipe_command_loads_only_lavapipe_s_driver_and_info_lists_every_adapter(tmp_path):
    from wgpu_shading.render.device import driver_manifest_folders

    if not any(Path(folder, "lvp_icd.x86_64.json").is_file() for folder in driver_manifest_folders()):
        pytest.skip("lavapipe's driver manifest is not at a standard place (x86-64) on this machine")
    render = ["render", "builtin:torus?segments=8", "--size", "16", "-o", str(tmp_path / "t.png"), "-q"]
    assert _reported_end(*render)[5] == "True"
    assert (tmp_path / "t.png").is_file()
    assert _reported_end("info")[5] == "False"  # `info` shows every adapter there is
    assert _reported_end(*render, WGPU_SHADING_ADAPTER="llvmpipe")[5] == "True"


END_AFTER = """
import sys, threading, time
from pathlib import Path
from wgpu_shading.cli.process_end import end_process
mark = Path(sys.argv[1])
def later():
    time.sleep(0.3)
    mark.write_text("done")
threading.Thread(target=later, daemon=sys.argv[2] == "daemon").start()
sys.stdout.write("unflushed text")  # no newline: still in the buffer when the process ends
end_process(int(sys.argv[3]))
"""


@pytest.mark.parametrize("code", [0, 2])
def test_the_end_of_the_process_flushes_output_and_keeps_the_exit_status(tmp_path, code):
    mark = tmp_path / "mark"
    result = subprocess.run([sys.executable, "-c", END_AFTER, str(mark), "daemon", str(code)], capture_output=True, text=True, timeout=60)
    assert (result.returncode, result.stdout) == (code, "unflushed text")
    assert not mark.exists()  # a daemon thread does not hold the process: it ended at once


def test_the_process_waits_for_a_thread_that_is_not_a_daemon(tmp_path):
    mark = tmp_path / "mark"
    result = subprocess.run([sys.executable, "-c", END_AFTER, str(mark), "worker", "0"], capture_output=True, text=True, timeout=60)
    assert (result.returncode, result.stdout) == (0, "unflushed text")
    assert mark.read_text() == "done"  # Python's orderly exit waited for it, as without end_process


def test_a_reader_that_went_away_ends_the_program_quietly(tmp_path):
    # `wgpu-shading materials | head -1`: the rest of the table has nowhere to go.
    program = subprocess.Popen([_program(), "materials"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    program.stdout.readline()
    program.stdout.close()
    _, err = program.communicate(timeout=60)
    assert program.returncode in (0, 141) and b"Traceback" not in err and b"Exception ignored" not in err


def _program() -> str:
    import shutil

    return shutil.which("wgpu-shading", path=str(Path(sys.executable).parent)) or "wgpu-shading"


DEFERRED_STUBS = """
import sys
from wgpu_shading.cli.process_start import defer_module
assert defer_module("pyglm.glm_typing", "pyglm", "glm_typing.py")
from pyglm import glm
import pyglm
print("Number" in vars(sys.modules["pyglm.glm_typing"]))  # not executed by pyglm's import
print(pyglm.typing.Number, pyglm.glm_typing.F32Vec3)  # executed on the first read
from pyglm.glm_typing import F32Vector3
print(F32Vector3, defer_module("pyglm.glm_typing", "pyglm", "glm_typing.py"))
"""


def test_pyglm_s_typing_aliases_load_when_first_read():
    # The program defers them (cli/process_start.py): they must read the same as pyglm's own.
    deferred = subprocess.run([sys.executable, "-c", DEFERRED_STUBS], capture_output=True, text=True, timeout=60)
    assert deferred.returncode == 0, deferred.stderr
    plain = subprocess.run(
        [sys.executable, "-c", "import pyglm; print(pyglm.typing.Number, pyglm.glm_typing.F32Vec3); print(pyglm.glm_typing.F32Vector3)"],
        capture_output=True, text=True, timeout=60,
    )
    lines = deferred.stdout.splitlines()
    assert lines[0] == "False"
    assert lines[1:] == [plain.stdout.splitlines()[0], plain.stdout.splitlines()[1] + " False"]
