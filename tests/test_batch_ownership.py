"""Batch outputs that cannot collide (dataset/names.py) and one run per output folder
(dataset/lock.py): refused before anything renders, with one line naming both jobs."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from wgpu_shading.cli import main
from wgpu_shading.dataset import Outputs, render_dataset
from wgpu_shading.dataset.jobs import Job
from wgpu_shading.dataset.lock import folder_lock
from wgpu_shading.errors import UsageError


def job(name: str, outputs: Outputs = Outputs(), folder: str = "m") -> Job:
    return Job(id=f"{folder}/{name}", source="builtin:cube", folder=folder, name=name, size=(16, 16), outputs=outputs)


@pytest.mark.parametrize(
    "names, outputs, file",
    [
        (["x", "x_depth"], Outputs(depth="png16"), "m/x_depth.png"),  # x's depth map, x_depth's colour image
        (["x_depth", "x"], Outputs(depth="png16"), "m/x_depth.png"),
        (["x", "x_ids"], Outputs(ids=True), "m/x_ids.png"),
        (["x", "x_depth"], Outputs(color="none", depth="npy", normals="eye"), None),  # no shared file: accepted
        (["x", "x_normals_eye"], Outputs(normals="eye"), None),  # x_normals_eye.npy vs x_normals_eye.png: different
        (["View", "view"], Outputs(), "m/view.png"),  # one file on macOS and Windows
    ],
)
def test_two_jobs_writing_one_file_are_refused_before_rendering(tmp_path, names, outputs, file):
    jobs = [job(name, outputs) for name in names]
    out = tmp_path / "out"
    if file is None:
        from wgpu_shading.dataset.names import check_output_names

        check_output_names(jobs)
        return
    with pytest.raises(UsageError) as caught:
        render_dataset(jobs, out, progress=False)
    message = str(caught.value)
    assert f"'m/{names[0]}'" in message and f"'m/{names[1]}'" in message and "same file" in message
    assert file.lower() in message.lower()
    assert not out.exists()  # nothing made, nothing rendered


@pytest.mark.parametrize("name", ["cameras", "Cameras"])
def test_a_view_named_cameras_is_refused(tmp_path, name):
    with pytest.raises(UsageError, match=rf"'m/{name}'.*record m/{name}.json would be the folder's camera file.*reserved"):
        render_dataset([job(name)], tmp_path / "out", progress=False)


def test_a_folder_named_like_the_report_is_refused(tmp_path):
    with pytest.raises(UsageError, match="folder 'report.json' is the run's report's name"):
        render_dataset([job("v", folder="report.json")], tmp_path / "out", progress=False)


def test_cli_manifest_with_colliding_rows_is_one_line_and_exit_2(tmp_path, capsys):
    manifest = tmp_path / "jobs.csv"
    manifest.write_text("mesh,name\nbuiltin:cube,x\nbuiltin:cube,x_depth\n")
    assert main(["batch", str(manifest), "-o", str(tmp_path / "out"), "--depth", "png16", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "x_depth.png" in err and "same file" in err
    assert not (tmp_path / "out").exists()


def test_a_second_run_into_a_locked_folder_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    with folder_lock(out):
        with pytest.raises(UsageError, match=rf"is being written by another batch run \(pid {os.getpid()}\); wait"):
            render_dataset([job("v")], out, progress=False)
    assert not (out / "m").exists()


def test_the_lock_is_refused_to_another_process_and_released_when_it_ends(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    holder = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(
            f"""
            import sys
            from pathlib import Path
            from wgpu_shading.dataset.lock import folder_lock
            with folder_lock(Path({str(out)!r})):
                print("locked", flush=True)
                sys.stdin.readline()
            """
        )],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
    )
    try:
        assert holder.stdout.readline() == "locked\n"
        with pytest.raises(UsageError, match=rf"another batch run \(pid {holder.pid}\)"):
            with folder_lock(out):
                pass
    finally:
        holder.kill()  # killed, not released: the kernel drops the lock with the process
        holder.wait()
    with folder_lock(out):
        pass


def test_clean_up_removes_only_batch_temporaries(tmp_path, renderer):
    out = tmp_path / "out"
    (out / "m").mkdir(parents=True)
    stale = out / "m" / ".v.png.wgpu-shading-tmp-batch-99999-deadbeef-0.png"  # a killed batch run's
    foreign = out / "m" / ".other.png.wgpu-shading-tmp-4242-cafebabe-0.png"  # a `render -o` writing meanwhile
    stale.write_bytes(b"partial")
    foreign.write_bytes(b"in flight")
    result = render_dataset([job("v")], out, progress=False, renderer=renderer)
    assert result.rendered == ["m/v"]
    assert not stale.exists() and foreign.read_bytes() == b"in flight"
