"""What `batch` is asked to do (docs/datasets.md): manifests, `--meshes`/`--views`, the
scheduler address. Bad input is exit 2 with one line naming the file, line, column or flag,
before anything renders (docs/reliability.md)."""

from __future__ import annotations

import pytest

from cli_errors import one_line_error, run_cli
from wgpu_shading.dataset import read_manifest
from wgpu_shading.errors import UsageError


@pytest.mark.parametrize(
    "name, data, words",
    [
        ("latin1.csv", b"mesh,name\nbuiltin:cube,caf\xe9\n", ["latin1.csv", "UTF-8"]),
        ("utf16.csv", "mesh,azimuth\nbuiltin:cube,0\n".encode("utf-16"), ["utf16.csv", "UTF-8"]),
        ("deep.jsonl", b'{"mesh": "builtin:cube", "eye": ' + b"[" * 100_000 + b"]" * 100_000 + b"}\n", ["deep.jsonl", "line 1", "nested too deeply"]),
        ("twice.csv", b"mesh,azimuth,mesh\nbuiltin:cube,0,builtin:sphere\n", ["twice.csv", "column 'mesh'", "twice"]),
        ("cells.csv", b"mesh,azimuth\nbuiltin:cube,0,5,6\n", ["cells.csv", "line 2", "4 cells", "2 columns"]),
    ],
)
def test_bad_manifests_are_one_line_errors(tmp_path, capsys, name, data, words):
    path = tmp_path / name
    path.write_bytes(data)
    code, err = run_cli(capsys, "batch", str(path), "-o", str(tmp_path / "ds"), "-q")
    line = one_line_error(code, err, *words)
    with pytest.raises(UsageError) as error:  # a manifest is how the work is asked for, not a scene
        read_manifest(path)
    assert line == f"wgpu-shading: error: {error.value}"


def test_a_csv_manifest_with_a_byte_order_mark_reads_its_first_column(tmp_path):
    # Spreadsheets save "CSV UTF-8" with a BOM: the first column was '\ufeffmesh', unknown.
    path = tmp_path / "excel.csv"
    path.write_bytes("\ufeffmesh,azimuth\nbuiltin:cube,30\n".encode("utf-8"))
    (job,) = read_manifest(path)
    assert job.source == "builtin:cube"


@pytest.mark.parametrize(
    "row, words",
    [
        ("material\nbuiltin:cube,unobtainium", ["line 2", "unknown material 'unobtainium'"]),
        ("frequency\nbuiltin:cube,foo", ["line 2", "frequency", "'foo'"]),
        ("reflection\nbuiltin:cube,lambert", ["line 2", "reflection", "'lambert'"]),
        ("projection\nbuiltin:cube,fisheye", ["line 2", "projection", "'fisheye'"]),
        ("distance\nbuiltin:cube,-1", ["line 2", "distance", "-1"]),
        ("distance\nbuiltin:cube,0", ["line 2", "distance", "0"]),
    ],
)
def test_a_bad_manifest_value_is_bad_input_before_anything_renders(tmp_path, capsys, row, words):
    # These were found only when the job ran: exit 1 ("1 job(s) failed") after the rest of
    # the dataset had rendered, though the documented status for bad input is 2.
    path = tmp_path / "jobs.csv"
    path.write_text("mesh," + row + "\n")
    code, err = run_cli(capsys, "batch", str(path), "-o", str(tmp_path / "ds"), "-q", "--size", "8")
    one_line_error(code, err, "jobs.csv", *words)
    assert not (tmp_path / "ds" / "cube").exists()


def test_a_json_boolean_is_not_an_angle(tmp_path):
    path = tmp_path / "jobs.jsonl"
    path.write_text('{"mesh": "builtin:cube", "azimuth": true}\n')
    with pytest.raises(UsageError, match="azimuth: expected a number, got True"):
        read_manifest(path)


def test_an_unknown_builtin_in_batch_is_bad_input(tmp_path, capsys):
    # It was a failed job (exit 1) after the other meshes had rendered.
    code, err = run_cli(capsys, "batch", "--meshes", "builtin:cube", "--meshes", "builtin:sphre", "--views", "1",
                     "--size", "8", "-o", str(tmp_path / "ds"), "-q")
    one_line_error(code, err, "unknown built-in mesh 'builtin:sphre'", "builtin:sphere")
    assert not (tmp_path / "ds" / "cube").exists()


def test_batch_views_beyond_the_limit_fail_before_anything_is_listed(tmp_path, capsys):
    code, err = run_cli(capsys, "batch", "-o", str(tmp_path / "ds"), "--meshes", "builtin:cube", "--views", "100000000000")
    assert code == 2 and "views: expected 1 to 100000 views per mesh, got 100000000000" in err


def test_a_malformed_scheduler_address_is_bad_input(tmp_path, capsys):
    pytest.importorskip("distributed")
    # Dask's ValueError ("missing port number in address") ended as exit 3.
    code, err = run_cli(capsys, "batch", "--meshes", "builtin:cube", "--views", "1", "--size", "8",
                     "-o", str(tmp_path / "ds"), "-q", "--scheduler", "garbage")
    one_line_error(code, err, "--scheduler 'garbage'", "cannot connect")
