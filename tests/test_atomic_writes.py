"""Files written completely or not at all (assets/atomic.py): a failure, a full disk or a
signal leaves the previous file and no temporary; messages name the file; links are written
through; `-o -` to a closed or broken standard output is one line and exit 2."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap
import time
import uuid
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.assets.animation import write_animation
from wgpu_shading.assets import atomic
from wgpu_shading.assets import image_writers as images
from wgpu_shading.assets.image_writers import check_writable, write_depth, write_image
from wgpu_shading.cli.main import main
from wgpu_shading.errors import UsageError
from wgpu_shading.testing.golden import GoldenError, check_image

OLD = b"the previous file, intact"


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob("*wgpu-shading-tmp*"))


def size(path: Path) -> int:
    """A file's size, 0 when it went away meanwhile (the writability check's probe does)."""
    try:
        return path.stat().st_size
    except FileNotFoundError:
        return 0


def noise(height: int, width: int, channels: int = 4, seed: int = 0) -> np.ndarray:
    """Incompressible pixels: the encoded file is as large as the image."""
    return np.random.default_rng(seed).integers(0, 256, (height, width, channels), dtype=np.uint8)


@pytest.fixture
def full_disk():
    """A 256 KiB tmpfs: writing more than that fails with ENOSPC, as on a full disk."""
    folder = Path(f"/tmp/wgpu-shading-full-{uuid.uuid4().hex[:8]}")
    folder.mkdir()
    result = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(folder)], capture_output=True, text=True)
    if result.returncode != 0:
        folder.rmdir()
        pytest.skip(f"cannot mount a small tmpfs to fill ({result.stderr.strip() or 'mount failed'}; needs root)")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], capture_output=True)
        folder.rmdir()


# --------------------------------------------------------------------------- failures


@pytest.mark.parametrize("name", ["t.png", "t.jpg", "t.tif", "t.bmp", "t.npy"])
def test_a_full_disk_keeps_the_previous_image_and_names_the_file(full_disk, name):
    path = full_disk / name
    path.write_bytes(OLD)
    with pytest.raises(UsageError) as caught:
        write_image(path, noise(1000, 1000))  # 4 MB of noise (a 0.6 MB JPEG) > 256 KiB
    message = str(caught.value)
    assert repr(str(path)) in message and "No space left on device" in message and "unchanged" in message
    assert path.read_bytes() == OLD and leftovers(full_disk) == []


@pytest.mark.parametrize("name", ["d.npy", "d.tiff", "d.png"])
def test_a_full_disk_keeps_the_previous_depth(full_disk, name):
    path = full_disk / name
    path.write_bytes(OLD)
    depth = np.random.default_rng(1).uniform(1.0, 9.0, (600, 600))
    with pytest.raises(UsageError, match="No space left on device"):
        write_depth(path, depth, 0.5, 10.0)
    assert path.read_bytes() == OLD and leftovers(full_disk) == []


@pytest.mark.parametrize("name", ["spin.gif", "spin.mp4"])
def test_a_full_disk_keeps_the_previous_animation_and_ffmpeg_stays_quiet(full_disk, name, capfd):
    if name.endswith(".mp4"):
        pytest.importorskip("imageio_ffmpeg")
    path = full_disk / name
    path.write_bytes(OLD)
    frames = (noise(128, 128, 3, seed) for seed in range(60))
    with pytest.raises(UsageError) as caught:
        write_animation(path, frames, fps=10)
    assert repr(str(path)) in str(caught.value) and "No space left on device" in str(caught.value)
    assert path.read_bytes() == OLD and leftovers(full_disk) == []
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""  # ffmpeg's own error lines are not shown


def test_a_full_disk_keeps_the_golden_reference(full_disk):
    reference = full_disk / "golden.png"
    old = noise(40, 40)
    Image.fromarray(old).save(reference)
    before = reference.read_bytes()
    with pytest.raises(GoldenError, match="golden.png.*No space left on device"):
        check_image(noise(300, 300, seed=5), reference, update=True)
    assert reference.read_bytes() == before and leftovers(full_disk) == []


def test_a_full_disk_keeps_the_previous_golden_report(full_disk, tmp_path):
    from wgpu_shading.testing.report import ReportEntry, write_report

    image = tmp_path / "noise.png"
    Image.fromarray(noise(400, 400)).save(image)  # 640 kB: the page embedding it does not fit in 256 KiB
    page = full_disk / "report.html"
    page.write_bytes(OLD)
    with pytest.raises(GoldenError, match="report.html.*No space left on device"):
        write_report(page, [ReportEntry("test_x", "ref.png", "failed", images={"actual": str(image)})])
    assert page.read_bytes() == OLD and leftovers(full_disk) == []


def test_cli_render_on_a_full_disk_is_one_line_naming_the_file(full_disk, capsys):
    path = full_disk / "t.npy"
    path.write_bytes(OLD)
    assert main(["render", "builtin:cube", "--size", "200x200", "-o", str(path), "-q"]) == 2  # 640 KB of float32
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(path) in err and "No space left on device" in err and "Errno" not in err
    assert path.read_bytes() == OLD and leftovers(full_disk) == []


def test_an_encoder_failure_leaves_the_previous_file(tmp_path, monkeypatch):
    path = tmp_path / "t.png"
    path.write_bytes(OLD)

    def broken_write(file, pixels, level=6, text=None):
        file.write(b"\x89PNG half")
        raise OSError(errno.EIO, "Input/output error")

    monkeypatch.setattr(images, "write_png", broken_write)
    with pytest.raises(UsageError, match=r"t.png' could not be written: Input/output error \(the file that was there is unchanged\)"):
        write_image(path, noise(8, 8))
    assert path.read_bytes() == OLD and leftovers(tmp_path) == []


def test_a_new_file_keeps_the_umask_mode_and_a_replaced_one_its_mode(tmp_path):
    fresh = tmp_path / "fresh.png"
    write_image(fresh, noise(4, 4))
    umask = os.umask(0)
    os.umask(umask)
    assert fresh.stat().st_mode & 0o777 == 0o666 & ~umask
    kept = tmp_path / "kept.png"
    kept.write_bytes(OLD)
    kept.chmod(0o640)
    write_image(kept, noise(4, 4))
    assert kept.stat().st_mode & 0o777 == 0o640


@pytest.mark.parametrize("how", ["bytes", "opened file", "encoder's own file"])
def test_every_way_of_writing_keeps_the_umask_mode_or_the_replaced_files(tmp_path, how):
    """atomic_write and atomic_open create the temporary themselves (with the umask's mode, and
    change it only to match a file they replace); atomic_path's encoders may create it 0600."""

    def write(path: Path) -> None:
        if how == "bytes":
            atomic.atomic_write(path, b"new")
        elif how == "opened file":
            atomic.atomic_write(path, lambda file: file.write(b"new"))
        else:
            with atomic.atomic_path(path) as temporary:
                descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
                os.write(descriptor, b"new")
                os.close(descriptor)

    umask = os.umask(0)
    os.umask(umask)
    fresh = tmp_path / "fresh.tar.gz"
    write(fresh)
    assert fresh.read_bytes() == b"new" and fresh.stat().st_mode & 0o777 == 0o666 & ~umask
    kept = tmp_path / "kept.bin"
    kept.write_bytes(OLD)
    kept.chmod(0o640)
    write(kept)
    assert kept.read_bytes() == b"new" and kept.stat().st_mode & 0o777 == 0o640
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("name, suffix", [("a.png", ".png"), ("a.tar.gz", ".gz"), (".hidden", ""), ("a.", ""),
                                          ("noext", ""), ("a." + "x" * 20, "")])
def test_a_temporary_keeps_a_short_suffix_last_and_says_what_it_is(tmp_path, name, suffix):
    temporary = atomic.temporary_path(tmp_path / name, "batch-")
    counter_and_suffix = temporary.name.rsplit("-", 1)[1]
    assert temporary.parent == tmp_path and counter_and_suffix.lstrip("0123456789") == suffix
    assert atomic.is_temporary(temporary.name, "batch-") and temporary.name.startswith(f".{name}")


# --------------------------------------------------------------------------- links


def test_a_dangling_link_is_neither_filled_nor_replaced_by_the_check(tmp_path):
    (tmp_path / "elsewhere").mkdir()
    link = tmp_path / "out.png"
    link.symlink_to(tmp_path / "elsewhere" / "target.png")
    check_writable(link)
    assert link.is_symlink() and not (tmp_path / "elsewhere" / "target.png").exists()
    assert leftovers(tmp_path) == []


def test_render_writes_through_a_link_and_keeps_it(tmp_path, renderer):
    (tmp_path / "elsewhere").mkdir()
    link = tmp_path / "out.png"
    link.symlink_to(tmp_path / "elsewhere" / "target.png")
    assert main(["render", "builtin:cube", "--size", "16", "-o", str(link), "-q"]) == 0
    assert link.is_symlink() and os.readlink(link) == str(tmp_path / "elsewhere" / "target.png")
    assert Image.open(tmp_path / "elsewhere" / "target.png").size == (16, 16)


def test_a_link_into_a_missing_folder_is_refused_before_rendering(tmp_path, capsys):
    link = tmp_path / "out.png"
    link.symlink_to(tmp_path / "nowhere" / "target.png")
    assert main(["render", "builtin:cube", "-o", str(link)]) == 2
    err = capsys.readouterr().err
    assert "a link to" in err and "does not exist" in err and link.is_symlink()


def test_a_device_output_is_refused_not_replaced(tmp_path):
    with pytest.raises(UsageError, match="not a regular file"):
        check_writable(Path("/dev/null"))
    link = tmp_path / "null.png"
    link.symlink_to("/dev/null")
    with pytest.raises(UsageError, match="not a regular file"):
        check_writable(link)


# --------------------------------------------------------------------------- signals

# A child process whose PNG encoder writes half a file, says so, then waits to be killed:
# the signal arrives mid-write every time.
_SLOW_WRITER = textwrap.dedent(
    """
    import signal, sys, time
    from pathlib import Path
    import wgpu_shading.assets.image_writers as images

    # Ctrl-C as in a terminal, even when the suite runs as a background job (a shell starts
    # those with SIGINT ignored, and children inherit that).
    signal.signal(signal.SIGINT, signal.default_int_handler)

    def slow_write(file, pixels, level=6, text=None):
        file.write(b"\\x89PNG half of it")
        file.flush()
        print("writing", flush=True)
        time.sleep(60)

    images.write_png = slow_write
    from wgpu_shading.cli.main import main
    sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_during_the_write_leaves_the_previous_png(tmp_path, signum, status):
    path = tmp_path / "t.png"
    path.write_bytes(OLD)
    child = subprocess.Popen(
        [sys.executable, "-c", _SLOW_WRITER, "render", "builtin:cube", "--size", "16", "-o", str(path)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        assert child.stdout.readline() == "writing\n"
        assert leftovers(tmp_path)  # the half-written temporary is there now
        child.send_signal(signum)
        _, err = child.communicate(timeout=30)
    finally:
        child.kill()
    assert child.returncode == status, err
    assert err.strip() in ("wgpu-shading: terminated", "wgpu-shading: interrupted")
    assert path.read_bytes() == OLD and leftovers(tmp_path) == []


@pytest.mark.parametrize("name", ["spin.gif", "spin.mp4"])
def test_sigterm_during_a_turntable_leaves_no_partial_animation(tmp_path, name):
    if name.endswith(".mp4"):
        pytest.importorskip("imageio_ffmpeg")
    path = tmp_path / name
    path.write_bytes(OLD)
    executable = Path(sys.executable).parent / "wgpu-shading"
    child = subprocess.Popen(
        [str(executable), "turntable", "builtin:cube", "--size", "32", "--frames", "1000000", "-o", str(path), "-q"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        deadline = time.monotonic() + 60
        while not any(size(p) > 0 for p in tmp_path.glob(f".{name}.wgpu-shading-tmp-*")):
            assert time.monotonic() < deadline and child.poll() is None, child.stderr.read() if child.poll() is not None else "timeout"
            time.sleep(0.05)
        child.send_signal(signal.SIGTERM)
        _, err = child.communicate(timeout=30)
    finally:
        child.kill()
    assert child.returncode == 143 and err.strip() == "wgpu-shading: terminated", err
    assert path.read_bytes() == OLD and leftovers(tmp_path) == []


_INTERRUPTIBLE_CLI = textwrap.dedent(
    """
    import signal, sys
    signal.signal(signal.SIGINT, signal.default_int_handler)  # as in a terminal (see _SLOW_WRITER)
    from wgpu_shading.cli.main import main
    sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.parametrize("kind", ["GPUCommandBuffer", "GPUBuffer"])
def test_a_wgpu_object_whose_constructor_ctrl_c_interrupted_is_collected_quietly(capsys, monkeypatch, kind):
    """Ctrl-C can land inside a wgpu object's __init__ (GPUCommandEncoder.finish making its
    GPUCommandBuffer, a readback GPUBuffer): the half-made object lacks what __init__ had
    not set yet, and wgpu-py's __del__ raised AttributeError when it was collected (a
    command buffer's handle, a buffer's mapped views), printing "Exception ignored ..."
    under `wgpu-shading: interrupted` (a few runs in ten of the Ctrl-C test below). Under
    the CLI's hook that is quiet; any other error in a destructor is still printed."""
    import gc
    import importlib

    import wgpu.backends.wgpu_native as native

    cli_main = importlib.import_module("wgpu_shading.cli.main")  # the module (the package exports main())
    monkeypatch.setattr(sys, "unraisablehook", cli_main.unraisable_hook)
    cls = getattr(native, kind)
    half_made = cls.__new__(cls)  # as if interrupted before its __init__ set anything
    del half_made
    gc.collect()
    assert capsys.readouterr().err == ""

    class Broken:
        def __del__(self):
            raise ValueError("a real bug")

    broken = Broken()
    del broken
    gc.collect()
    assert "a real bug" in capsys.readouterr().err


def test_ctrl_c_during_animate_leaves_the_previous_gif(tmp_path):
    # animate streams its frames into a temporary beside the output (as turntable does):
    # Ctrl-C while the GIF grows keeps the previous file and leaves no temporary.
    path = tmp_path / "arm.gif"
    path.write_bytes(OLD)
    child = subprocess.Popen(
        [sys.executable, "-c", _INTERRUPTIBLE_CLI, "animate", "example:arm.glb", "--size", "32", "--fps", "1000", "-o", str(path), "-q"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        deadline = time.monotonic() + 60
        while not any(size(p) > 0 for p in tmp_path.glob(".arm.gif.wgpu-shading-tmp-*")):
            assert time.monotonic() < deadline and child.poll() is None, child.stderr.read() if child.poll() is not None else "timeout"
            time.sleep(0.05)
        child.send_signal(signal.SIGINT)
        _, err = child.communicate(timeout=30)
    finally:
        child.kill()
    assert child.returncode == 130 and err.strip() == "wgpu-shading: interrupted", err
    assert path.read_bytes() == OLD and leftovers(tmp_path) == []


# --------------------------------------------------------------------------- standard output


def _render_to_stdout(tmp_path: Path, shell_redirect: str) -> subprocess.CompletedProcess:
    executable = Path(sys.executable).parent / "wgpu-shading"
    return subprocess.run(
        ["sh", "-c", f"'{executable}' render builtin:cube --size 16 -o - {shell_redirect}"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )


def test_render_to_a_closed_stdout_is_one_line_and_exit_2(tmp_path):
    result = _render_to_stdout(tmp_path, ">&-")
    assert result.returncode == 2, result.stderr
    assert result.stderr == "wgpu-shading: error: -o -: standard output is closed; give a file name with -o\n"


def test_render_to_a_broken_pipe_is_one_line_and_exit_2(tmp_path):
    executable = Path(sys.executable).parent / "wgpu-shading"
    read, write = os.pipe()
    os.close(read)  # nobody will read: the write fails with EPIPE
    try:
        result = subprocess.run(
            [str(executable), "render", "builtin:cube", "--size", "16", "-o", "-"],
            stdout=write, stderr=subprocess.PIPE, text=True, timeout=120,
        )
    finally:
        os.close(write)
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1 and "standard output" in result.stderr and "closed the pipe" in result.stderr


def test_a_full_disk_fails_the_batch_job_naming_its_file_and_leaves_no_temporary(full_disk, renderer):
    import json

    from wgpu_shading.dataset import Outputs, render_dataset
    from wgpu_shading.dataset.jobs import Job

    job = Job(id="m/v", source="builtin:cube", folder="m", name="v", size=(400, 400), outputs=Outputs(depth="npy"))
    result = render_dataset([job], full_disk / "out", progress=False, renderer=renderer)  # 640 KB of float32 depth
    assert list(result.failed) == ["m/v"]
    message = result.failed["m/v"]
    assert "v_depth.npy" in message and "No space left on device" in message, message
    assert leftovers(full_disk) == [] and not (full_disk / "out" / "m" / "v.json").exists()
    assert json.loads((full_disk / "out" / "report.json").read_text())["failed"] == {"m/v": message}


# A destructor that SIGTERM's exception lands in, as a wgpu object's __del__ does when the
# garbage collector runs it at the wrong moment: the exception is swallowed there.
_SWALLOWED = textwrap.dedent(
    """
    import importlib, signal, sys, time
    cli = importlib.import_module("wgpu_shading.cli.main")

    class Garbage:
        def __del__(self):
            signal.raise_signal(signal.SIGTERM)  # the handler raises here, inside __del__
            time.sleep(0.01)

    def command(argv, owns_process=False):
        Garbage()  # collected at once: its __del__ swallows the Terminated raised in it
        for _ in range(500):  # a long command; the signal must still stop it
            time.sleep(0.01)
        print("not stopped")
        return 0

    cli._main = command  # the command main() runs, with its signal handling around it
    sys.exit(cli.main([]))
    """
)


def test_sigterm_swallowed_by_a_destructor_still_stops_the_command(tmp_path):
    result = subprocess.run([sys.executable, "-c", _SWALLOWED], capture_output=True, text=True, timeout=60)
    assert result.returncode == 143 and "not stopped" not in result.stdout, (result.stdout, result.stderr)
    assert result.stderr.strip() == "wgpu-shading: terminated", result.stderr
