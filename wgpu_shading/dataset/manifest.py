"""Manifests (CSV or JSON Lines, one job a row) and the meshes × views shortcut.

Columns / keys (all but the first optional):
    mesh (or scene, or source)   a mesh file, builtin:NAME or a scene .toml; relative paths
                                 are relative to the manifest's folder
    id, folder, name             job id (default FOLDER/NAME), output folder (default: the
                                 mesh's stem) and file stem (default view_000, view_001, ... per folder)
    every view option's column   size, material, up, eye, azimuth, lights, ...: the table in
                                 scene/view/options.py (docs/view-options.md), read by the
                                 option's own reader ("1 2 3" or "1,2,3" for a vector in CSV)
Older manifests keep working: `infinite_viewer` (true = local_viewer false), and `up` holding
a vector (the camera's up vector, now `camera_up`; `up` holding an axis such as +Z is the
model's up axis, as `--up`).
"""

from __future__ import annotations

import csv
import glob
import hashlib
import json
from pathlib import Path
from typing import Any, Iterable

from ..assets.files import check_regular_file
from ..assets.view_loader import source_name
from ..errors import UsageError
from ..scene import BUILTIN_PREFIX, BUILTINS
from ..scene.view.options import COLUMNS, ViewOptions
from ..scene.view.reading import read_bool, read_vector
from .jobs import Job, Outputs

SOURCE_KEYS = ("mesh", "scene", "source")
_NAMED_SOURCES = ("builtin:", "example:")  # built-in meshes and the shipped examples
_JOB_KEYS = ("id", "folder", "name")
_LEGACY_KEYS = ("infinite_viewer",)
# Every value is read (and checked) when the manifest is read, so that a typo is bad input
# (exit 2) before anything renders, not a failed job found after the rest of the dataset.
KNOWN_KEYS = set(SOURCE_KEYS) | set(_JOB_KEYS) | set(COLUMNS) | set(_LEGACY_KEYS)


def read_manifest(path: str | Path, outputs: Outputs | None = None, defaults: dict[str, Any] | None = None) -> list[Job]:
    """The jobs of a .csv or .jsonl/.ndjson manifest. `defaults` fill keys a row leaves out
    (e.g. size or material from the command line)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".csv", ".jsonl", ".ndjson"):
        raise UsageError(f"manifest {str(path)!r}: expected a .csv or .jsonl file")
    check_regular_file(path, f"manifest {str(path)!r}", UsageError)  # a FIFO would block the read
    try:
        text = path.read_text(encoding="utf-8-sig")  # spreadsheets write "CSV UTF-8" with a BOM
    except OSError as error:
        raise UsageError(f"manifest {str(path)!r}: {error.strerror or error}") from None
    except UnicodeDecodeError as error:
        raise UsageError(
            f"manifest {str(path)!r}: not UTF-8 text (byte {error.object[error.start]:#04x} at offset {error.start}); "
            "save it as UTF-8"
        ) from None
    if suffix == ".csv":
        rows = _csv_rows(text, path)
    else:
        rows = []
        for number, line in enumerate(text.splitlines(), 1):
            if not line.strip():
                continue
            try:
                row = json.loads(line)
            except json.JSONDecodeError as error:
                raise UsageError(f"manifest {str(path)!r} line {number}: not JSON ({error.msg})") from None
            except RecursionError:
                raise UsageError(f"manifest {str(path)!r} line {number}: JSON nested too deeply") from None
            if not isinstance(row, dict):
                raise UsageError(f"manifest {str(path)!r} line {number}: expected a JSON object")
            rows.append((number, row))
    if not rows:
        raise UsageError(f"manifest {str(path)!r}: no jobs")
    base = path.parent
    return jobs_from_rows(((f"{path} line {number}", row) for number, row in rows), base, outputs or Outputs(), defaults or {})


def _csv_rows(text: str, path: Path) -> list[tuple[int, dict]]:
    """(line number, row) pairs; a repeated column (csv.DictReader keeps the last one
    silently) or a row with more cells than the header has columns is an error."""
    reader = csv.reader(text.splitlines())
    header = next(reader, None) or []
    repeated = sorted({column for column in header if header.count(column) > 1})
    if repeated:
        raise UsageError(f"manifest {str(path)!r} line 1: column {repeated[0]!r} appears twice")
    rows = []
    for cells in reader:
        number = reader.line_num
        if not any(cell.strip() for cell in cells):
            continue
        if len(cells) > len(header):
            raise UsageError(
                f"manifest {str(path)!r} line {number}: {len(cells)} cells, but the header has {len(header)} columns"
            )
        rows.append((number, dict(zip(header, cells))))
    return rows


def jobs_from_rows(rows: Iterable[tuple[str, dict]], base: Path, outputs: Outputs, defaults: dict[str, Any]) -> list[Job]:
    jobs: list[Job] = []
    names_per_folder: dict[str, int] = {}
    folder_of_source: dict[str, str] = {}
    ids: set[str] = set()
    outputs_of: dict[tuple[str, str], str] = {}  # (folder, name) → the job id that writes there
    for where, raw in rows:
        given = {key: value for key, value in raw.items() if value not in ("", None)}
        row = {**defaults, **_current_columns(given, where)}
        unknown = sorted(set(row) - KNOWN_KEYS)
        if unknown:
            raise UsageError(f"{where}: unknown column {unknown[0]!r}; expected some of {', '.join(sorted(KNOWN_KEYS))}")
        sources = [key for key in SOURCE_KEYS if key in row]
        if len(sources) != 1:
            raise UsageError(f"{where}: expected exactly one of mesh, scene, source")
        source = _resolve(str(row[sources[0]]), base)
        if source.startswith(BUILTIN_PREFIX) and source[len(BUILTIN_PREFIX):].partition("?")[0] not in BUILTINS:
            # A typo in a built-in's name is bad input, found before anything renders.
            raise UsageError(f"{where}: unknown built-in mesh {source!r}; available: {', '.join(BUILTIN_PREFIX + n for n in BUILTINS)}")
        folder = str(row.get("folder") or folder_of_source.get(source) or _folder_for(source, folder_of_source))
        folder_of_source.setdefault(source, folder)
        index = names_per_folder.get(folder, 0)
        names_per_folder[folder] = index + 1
        name = str(row.get("name", f"view_{index:03d}"))
        _check_name(name, where, "name")
        _check_name(folder, where, "folder")
        job_id = str(row.get("id", f"{folder}/{name}"))
        if job_id in ids:
            raise UsageError(f"{where}: job id {job_id!r} appears twice (two rows would write the same files)")
        ids.add(job_id)
        if (folder, name) in outputs_of:
            raise UsageError(f"{where}: folder {folder!r} name {name!r} is also job {outputs_of[folder, name]!r}'s (both would write the same files)")
        outputs_of[folder, name] = job_id
        jobs.append(
            Job.with_view(
                row_view_options(row, where),
                id=job_id,
                source=source,
                folder=folder,
                name=name,
                outputs=outputs,
            )
        )
    return jobs


def mesh_jobs(
    patterns: Iterable[str],
    views: list[dict[str, float]],
    outputs: Outputs | None = None,
    defaults: dict[str, Any] | None = None,
) -> list[Job]:
    """Every mesh matching the glob `patterns` (or builtin:NAME) × every view (an orbit dict
    from views.turntable_views / views.sphere_views): one folder per mesh."""
    sources: list[str] = []
    for pattern in patterns:
        if pattern.startswith(_NAMED_SOURCES):  # not files: the loaders resolve them
            sources.append(pattern)
            continue
        matches = sorted(glob.glob(pattern, recursive=True))
        if not matches:
            raise UsageError(f"--meshes {pattern!r}: no file matches")
        sources.extend(matches)
    rows = ((f"mesh {source}", {"mesh": source, **view}) for source in dict.fromkeys(sources) for view in views)
    return jobs_from_rows(rows, Path.cwd(), outputs or Outputs(), defaults or {})


def _resolve(source: str, base: Path) -> str:
    if source.startswith(_NAMED_SOURCES):
        return source
    path = Path(source).expanduser()
    return str(path if path.is_absolute() else (base / path).resolve())


def _folder_for(source: str, taken: dict[str, str]) -> str:
    """The mesh's stem; a second mesh with the same stem gets a short hash of its path."""
    stem = source_name(source, "mesh")
    if stem in taken.values():
        stem = f"{stem}-{hashlib.sha1(source.encode()).hexdigest()[:6]}"
    return stem


def _check_name(name: str, where: str, key: str) -> None:
    if not name or name in (".", "..") or "/" in name or "\\" in name:
        raise UsageError(f"{where}: {key} {name!r} must be a plain file name (no folders)")


def _is_vector(value: Any) -> bool:
    """Three numbers ("0 0 1", "0,0,1", [0, 0, 1]), not an axis name such as +Z."""
    try:
        read_vector(value, "up")
    except UsageError:
        return False
    return True


def _current_columns(row: dict[str, Any], where: str) -> dict[str, Any]:
    """The row with the columns older manifests used under their current names: `up` holding
    a vector was the camera's up vector (`camera_up`); `infinite_viewer` is `local_viewer`
    inverted. (Before the command line's defaults fill the row, so `--up +Z` still applies.)"""
    row = dict(row)
    if "up" in row and _is_vector(row["up"]):
        if "camera_up" in row:
            raise UsageError(f"{where}: up {row['up']!r} is a camera up vector and camera_up is given too; keep one")
        row["camera_up"] = row.pop("up")
    if "infinite_viewer" in row:
        if "local_viewer" in row:
            raise UsageError(f"{where}: give local_viewer or infinite_viewer, not both")
        row["local_viewer"] = not read_bool(row.pop("infinite_viewer"), f"{where}: infinite_viewer")
    return row


def row_view_options(row: dict[str, Any], where: str) -> ViewOptions:
    """The view options of one manifest row (its other keys are the job's source and names)."""
    values: dict[str, Any] = {}
    for key, value in _current_columns(row, where).items():
        if key in SOURCE_KEYS or key in _JOB_KEYS:
            continue
        option = COLUMNS[key]
        values[option.name] = option.read(value, f"{where}: {key}")
    return ViewOptions(**values)
