"""Manifests (CSV or JSON Lines, one job a row) and the meshes × views shortcut.

Columns / keys (all but the first optional):
    mesh (or scene, or source)   a mesh file, builtin:NAME or a scene .toml; relative paths
                                 are relative to the manifest's folder
    id, folder, name             job id (default FOLDER/NAME), output folder (default: the
                                 mesh's stem) and file stem (default view_000, view_001, ... per folder)
    azimuth, elevation, distance the view: render's --camera-azimuth-angle/--camera-elevation-angle turns
                                 of the scene's camera, then the eye's distance (views.py)
    eye, target, up, fov_y, near, far, projection, ortho_height
                                 camera keys as in a scene file ("1 2 3" in CSV)
    size                         512 or 640x480
    material, frequency, reflection, blinn_exponent_scale, infinite_viewer, two_sided
                                 the `render` flags of the same names, per job
"""

from __future__ import annotations

import csv
import glob
import hashlib
import json
import math
from pathlib import Path
from typing import Any, Iterable

from ..assets.files import check_regular_file
from ..errors import SceneError
from ..scene import BUILTIN_PREFIX, BUILTINS, image_size, material
from ..scene.camera import PROJECTIONS
from ..scene.values import FREQUENCIES, REFLECTIONS
from .jobs import CAMERA_KEYS, ORBIT_KEYS, OVERRIDE_KEYS, Job, Outputs

SOURCE_KEYS = ("mesh", "scene", "source")
_NAMED_SOURCES = ("builtin:", "example:")  # built-in meshes and the shipped examples
KNOWN_KEYS = set(SOURCE_KEYS) | {"id", "folder", "name", "size"} | set(CAMERA_KEYS) | set(ORBIT_KEYS) | set(OVERRIDE_KEYS)
_BOOL_KEYS = ("infinite_viewer", "two_sided")
_VECTOR_KEYS = ("eye", "target", "up")
_NUMBER_KEYS = ("fov_y", "near", "far", "ortho_height", "blinn_exponent_scale") + ORBIT_KEYS
# Checked when the manifest is read, so that a typo is bad input (exit 2) before anything
# renders, not a failed job found after the rest of the dataset.
_CHOICE_KEYS = {"frequency": FREQUENCIES, "reflection": REFLECTIONS, "projection": PROJECTIONS}


def read_manifest(path: str | Path, outputs: Outputs | None = None, defaults: dict[str, Any] | None = None) -> list[Job]:
    """The jobs of a .csv or .jsonl/.ndjson manifest. `defaults` fill keys a row leaves out
    (e.g. size or material from the command line)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".csv", ".jsonl", ".ndjson"):
        raise SceneError(f"manifest {str(path)!r}: expected a .csv or .jsonl file")
    check_regular_file(path, f"manifest {str(path)!r}", SceneError)  # a FIFO would block the read
    try:
        text = path.read_text(encoding="utf-8-sig")  # spreadsheets write "CSV UTF-8" with a BOM
    except OSError as error:
        raise SceneError(f"manifest {str(path)!r}: {error.strerror or error}") from None
    except UnicodeDecodeError as error:
        raise SceneError(
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
                raise SceneError(f"manifest {str(path)!r} line {number}: not JSON ({error.msg})") from None
            except RecursionError:
                raise SceneError(f"manifest {str(path)!r} line {number}: JSON nested too deeply") from None
            if not isinstance(row, dict):
                raise SceneError(f"manifest {str(path)!r} line {number}: expected a JSON object")
            rows.append((number, row))
    if not rows:
        raise SceneError(f"manifest {str(path)!r}: no jobs")
    base = path.parent
    return jobs_from_rows(((f"{path} line {number}", row) for number, row in rows), base, outputs or Outputs(), defaults or {})


def _csv_rows(text: str, path: Path) -> list[tuple[int, dict]]:
    """(line number, row) pairs; a repeated column (csv.DictReader keeps the last one
    silently) or a row with more cells than the header has columns is an error."""
    reader = csv.reader(text.splitlines())
    header = next(reader, None) or []
    repeated = sorted({column for column in header if header.count(column) > 1})
    if repeated:
        raise SceneError(f"manifest {str(path)!r} line 1: column {repeated[0]!r} appears twice")
    rows = []
    for cells in reader:
        number = reader.line_num
        if not any(cell.strip() for cell in cells):
            continue
        if len(cells) > len(header):
            raise SceneError(
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
        row = {key: value for key, value in {**defaults, **raw}.items() if value not in ("", None)}
        unknown = sorted(set(row) - KNOWN_KEYS)
        if unknown:
            raise SceneError(f"{where}: unknown column {unknown[0]!r}; expected some of {', '.join(sorted(KNOWN_KEYS))}")
        sources = [key for key in SOURCE_KEYS if key in row]
        if len(sources) != 1:
            raise SceneError(f"{where}: expected exactly one of mesh, scene, source")
        source = _resolve(str(row[sources[0]]), base)
        if source.startswith(BUILTIN_PREFIX) and source[len(BUILTIN_PREFIX):].partition("?")[0] not in BUILTINS:
            # A typo in a built-in's name is bad input, found before anything renders.
            raise SceneError(f"{where}: unknown built-in mesh {source!r}; available: {', '.join(BUILTIN_PREFIX + n for n in BUILTINS)}")
        folder = str(row.get("folder") or folder_of_source.get(source) or _folder_for(source, folder_of_source))
        folder_of_source.setdefault(source, folder)
        index = names_per_folder.get(folder, 0)
        names_per_folder[folder] = index + 1
        name = str(row.get("name", f"view_{index:03d}"))
        _check_name(name, where, "name")
        _check_name(folder, where, "folder")
        job_id = str(row.get("id", f"{folder}/{name}"))
        if job_id in ids:
            raise SceneError(f"{where}: job id {job_id!r} appears twice (two rows would write the same files)")
        ids.add(job_id)
        if (folder, name) in outputs_of:
            raise SceneError(f"{where}: folder {folder!r} name {name!r} is also job {outputs_of[folder, name]!r}'s (both would write the same files)")
        outputs_of[folder, name] = job_id
        jobs.append(
            Job(
                id=job_id,
                source=source,
                folder=folder,
                name=name,
                size=image_size(_parse_size(row["size"], where), f"{where}: size") if "size" in row else None,
                camera={key: _value(key, row[key], where) for key in CAMERA_KEYS if key in row},
                orbit={key: _value(key, row[key], where) for key in ORBIT_KEYS if key in row},
                overrides={key: _value(key, row[key], where) for key in OVERRIDE_KEYS if key in row},
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
            raise SceneError(f"--meshes {pattern!r}: no file matches")
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
    stem = Path(source.split("?")[0].replace("builtin:", "").replace("example:", "")).stem or "mesh"
    if stem in taken.values():
        stem = f"{stem}-{hashlib.sha1(source.encode()).hexdigest()[:6]}"
    return stem


def _check_name(name: str, where: str, key: str) -> None:
    if not name or name in (".", "..") or "/" in name or "\\" in name:
        raise SceneError(f"{where}: {key} {name!r} must be a plain file name (no folders)")


def _parse_size(value: Any, where: str) -> Any:
    if isinstance(value, str):
        parts = value.lower().replace("×", "x").split("x")
        try:
            numbers = [int(part) for part in parts]
        except ValueError:
            raise SceneError(f"{where}: size: expected WIDTHxHEIGHT or SIZE, got {value!r}") from None
        return numbers * 2 if len(numbers) == 1 else numbers
    if isinstance(value, (int, float)):
        return [value, value]
    return value


def _value(key: str, value: Any, where: str) -> Any:
    """A CSV string or a JSON value, converted to what the key needs."""
    if key in _BOOL_KEYS:
        if isinstance(value, bool):
            return value
        text = str(value).strip().lower()
        if text in ("1", "true", "yes"):
            return True
        if text in ("0", "false", "no"):
            return False
        raise SceneError(f"{where}: {key}: expected true or false, got {value!r}")
    if key in _VECTOR_KEYS:
        if isinstance(value, str):
            value = value.replace(",", " ").split()
        try:
            numbers = [float(v) for v in value]
        except (TypeError, ValueError):
            raise SceneError(f"{where}: {key}: expected 3 numbers such as \"0 1 3\", got {value!r}") from None
        if len(numbers) != 3 or not all(math.isfinite(v) for v in numbers):
            raise SceneError(f"{where}: {key}: expected 3 finite numbers, got {value!r}")
        return tuple(numbers)
    if key in _NUMBER_KEYS:
        try:
            if isinstance(value, bool):  # JSON true is not 1 degree
                raise TypeError
            number = float(value)
        except (TypeError, ValueError):
            raise SceneError(f"{where}: {key}: expected a number, got {value!r}") from None
        if not math.isfinite(number):
            raise SceneError(f"{where}: {key}: expected a finite number, got {value!r}")
        if key == "distance" and not number > 0.0:
            raise SceneError(f"{where}: distance: expected a positive number, got {value!r}")
        return number
    text = str(value)
    if key in _CHOICE_KEYS and text not in _CHOICE_KEYS[key]:
        raise SceneError(f"{where}: {key}: expected one of {', '.join(_CHOICE_KEYS[key])}, got {value!r}")
    if key == "material":
        try:
            material(text)
        except SceneError as error:
            raise SceneError(f"{where}: {error}") from None
    return text
