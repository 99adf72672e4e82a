"""Mesh files (OBJ/MTL, PLY, STL, OFF, glTF/GLB, XYZ/PTS point text) into one Mesh with one part per material.

Each format has one reader, listed by suffix in MESH_READERS (as trimesh's exchange/ lists
its loaders): `reader(path, file size) → MeshFile` (mesh_pieces.py), the one type every
reader returns. OBJ is read by mesh_formats/obj.py (trimesh's OBJ reader mis-resolves
relative indices and drops smoothing groups); OFF by mesh_formats/off.py (a token stream:
trimesh wanted one face per line); binary STL by mesh_formats/stl.py; PLY and ASCII STL
through trimesh (mesh_formats/trimesh_reader.py), binary PLY point clouds with numpy
(mesh_formats/ply.py); glTF by our own accessor reader (gltf/); point clouds as text
(.xyz, .pts) by mesh_formats/point_text.py.
The pieces' normals follow docs/real-world-files.md: the file's normals win; glTF primitives
without NORMAL are flat; otherwise vertices are welded by position and split at the crease
angle (scene/geometry/crease_normals.py).
"""

from __future__ import annotations

import importlib
import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import MeshError
from ..scene.geometry.builtins import BUILTIN_PREFIX, builtin
from ..scene.geometry.mesh import Mesh
from ..scene.view.reading import MAX_SECONDS
from .examples import resolve_example
from .files import check_regular_file
from .mesh_formats.checks import file_size_or_error
from .mesh_pieces import MeshFile, assemble

# suffix → reader ("module:function" in this package): the one list of the mesh formats (a
# new format is a reader and a line here). A reader's module is imported when a file of its
# format is read: `render builtin:torus` needs none, and the glTF reader alone took ~13 ms of
# every cold start (docs/performance.md#cold-start-process-start-to-png-on-disk).
MESH_READERS: dict[str, str] = {
    ".obj": "mesh_formats.obj:read_obj",
    ".ply": "mesh_formats.ply:read_ply",
    ".stl": "mesh_formats.stl:read_stl",
    ".off": "mesh_formats.off:read_off",
    ".xyz": "mesh_formats.point_text:read_xyz",
    ".pts": "mesh_formats.point_text:read_pts",
    ".glb": "gltf.reader:read_gltf",
    ".gltf": "gltf.reader:read_gltf",
}
MESH_SUFFIXES = tuple(MESH_READERS)
# Readers whose Mesh may depend on more than the file (buffers, images, an animation):
# never looked up in the mesh cache (the others say so per file: MeshFile.self_contained).
_NEVER_CACHED = frozenset({MESH_READERS[".glb"], MESH_READERS[".gltf"]})
DEFAULT_CREASE_ANGLE = 60.0  # degrees (docs/real-world-files.md)


def mesh_reader(reader: str) -> Callable[[Path, int], MeshFile]:
    """The reader function a MESH_READERS entry names, its module imported now."""
    module, function = reader.split(":")
    return getattr(importlib.import_module(f".{module}", __package__), function)


def _without_camera(index: int) -> None:
    return None  # a built-in has no cameras


@dataclass(frozen=True)
class LoadedMesh:
    """A mesh file read once: its Mesh, and its own lights and cameras when asked
    (MeshFile.lights, MeshFile.camera). shows False: at the animation time asked for, every
    object of the file is hidden (scaled to zero, as exporters make objects appear); `mesh`
    is then the file unanimated, for the view to be placed around, and the view is drawn
    empty (assets/mesh_scene.py), as viewers show that moment."""

    mesh: Mesh
    lights: Callable[[], list]
    camera: Callable[[int], object] = _without_camera
    shows: bool = True


def load_mesh(source: str | os.PathLike[str], *, crease_angle: float = DEFAULT_CREASE_ANGLE,
              animation_time: float | None = None, animation_index: int | str | None = None) -> Mesh:
    """A built-in (`builtin:torus`), a shipped sample (`example:knot.obj`) or a mesh file
    (OBJ, PLY, STL, OFF, GLB/glTF, XYZ/PTS).

    crease_angle (degrees, 0..180): where the file has no normals, edges sharper than this
    are creases (docs/real-world-files.md); 180 is the plain average of the welded faces, 0 is flat.
    animation_time (seconds): a glTF file as its animation `animation_index` (0 unless given;
    1, 2, ... or "all") poses it then (docs/animation.md); None: as the file's nodes say,
    unanimated, unless an animation_index is given (then its start, time 0). A moment at
    which every object is hidden has no Mesh: MeshError (`render` draws it empty)."""
    loaded = read_mesh(source, crease_angle=crease_angle, animation_time=animation_time, animation_index=animation_index)
    if not loaded.shows:
        time, index = _animation(animation_time, animation_index)
        raise MeshError(f"mesh file {str(source)!r}: nothing shows at {time:g} s of animation {index} (every object is hidden then)")
    return loaded.mesh


def read_mesh(source: str | os.PathLike[str], *, crease_angle: float = DEFAULT_CREASE_ANGLE,
              animation_time: float | None = None, animation_index: int | str | None = None) -> LoadedMesh:
    """load_mesh's mesh with the file's own lights (a bare glTF is lit by them) and cameras,
    the file parsed once."""
    # Checked before anything else: a built-in ignores the angle (its normals are exact), but
    # a bad value is still the caller's mistake, whatever the source.
    if not (isinstance(crease_angle, (int, float)) and 0.0 <= crease_angle <= 180.0):
        raise MeshError(f"crease_angle: expected a number of degrees between 0 and 180, got {crease_angle!r}")
    animation = _animation(animation_time, animation_index)
    text = resolve_example(str(source))
    if text.startswith(BUILTIN_PREFIX):
        return LoadedMesh(builtin(text), lambda: [])
    if "\x00" in text:
        raise MeshError(f"mesh file {text!r}: a path cannot contain a NUL character")
    path = Path(text)
    if not path.exists():
        raise MeshError(f"mesh file {text!r} not found")
    check_regular_file(path, f"mesh file {text!r}", MeshError)  # a folder, FIFO or device: refused unread
    reader = MESH_READERS.get(path.suffix.lower())
    if reader is None:
        raise MeshError(f"mesh file {text!r}: unsupported format {path.suffix!r}; expected one of {', '.join(MESH_SUFFIXES)}")
    file_size = file_size_or_error(path, f"mesh file {text!r}")  # size limit, before anything is read
    # A file read before is not parsed again (mesh_cache.py), nor its reader imported; glTF
    # files are never kept. (Imported here: `render builtin:torus` never needs it, nor hashlib.)
    from .mesh_cache import mesh_entry

    entry = mesh_entry(path, file_size, crease_angle) if animation is None and reader not in _NEVER_CACHED else None
    kept = entry.load(path.name) if entry is not None else None
    if kept is not None:
        _say(kept[1], None, 4)  # (the caller of load_mesh, as loaded_mesh's notes)
        return LoadedMesh(kept[0], lambda: [])
    read = mesh_reader(reader)
    notes = []
    with np.errstate(all="ignore"):  # bad values become MeshErrors, not warnings on stderr
        gltf = reader == MESH_READERS[".gltf"]
        if animation is not None and not gltf:
            notes.append(f"{path.name}: only glTF files hold animations; the animation time {animation[0]:g} s is ignored")
        found = read(path, file_size, animation) if animation is not None and gltf else read(path, file_size)
        if animation is not None and gltf and not any(piece.element_count for piece in found.pieces):
            # Nothing shows at this moment: the file unanimated places the view, drawn empty.
            # (Read again: this moment alone pays for it.)
            rest = read(path, file_size)
            if any(piece.element_count for piece in rest.pieces):
                loaded = loaded_mesh(rest, text, path.name, crease_angle, notes)
                return LoadedMesh(loaded.mesh, found.lights, found.camera, shows=False)
    loaded = loaded_mesh(found, text, path.name, crease_angle, notes)
    if entry is not None and found.self_contained:
        entry.keep(loaded.mesh, list(dict.fromkeys([*notes, *found.notes])))
    return loaded


def loaded_mesh(found: MeshFile, source: str, name: str, crease_angle: float, notes: list[str] = (),
                said: set[str] | None = None) -> LoadedMesh:
    """A reader's MeshFile as read_mesh gives it: its pieces assembled into one Mesh named
    `name`, the notes said once each once the file was read without error (or to say why
    nothing is left). `said`: notes already said to this caller, not said again (an
    animation poses one parsed file for every frame: animation_frames.py)."""
    with np.errstate(all="ignore"):  # bad values become MeshErrors, not warnings on stderr
        pieces = [p for p in found.pieces if p.element_count]
        mesh = assemble(pieces, name, float(crease_angle)) if pieces else None
    _say([*notes, *found.notes], said, 5)
    if mesh is None:
        raise MeshError(f"mesh file {source!r} contains no triangles, lines or points: nothing to draw")
    return LoadedMesh(mesh, found.lights, found.camera)


def _say(notes: list[str], said: set[str] | None, stacklevel: int) -> None:
    """Each note once, as a warning; `stacklevel` as warnings.warn counts it from here."""
    for note in dict.fromkeys(notes):
        if said is None or note not in said:
            warnings.warn(note, stacklevel=stacklevel)
            said is None or said.add(note)


def _animation(time: float | None, index: int | str | None) -> tuple[float, int | str] | None:
    """(time, animation) to pose a glTF file at, or None: an animation chosen alone is shown
    at its start (time 0); animation 0 unless one is chosen."""
    if time is not None and not (isinstance(time, (int, float)) and not isinstance(time, bool) and abs(time) <= MAX_SECONDS):
        raise MeshError(f"animation_time: expected a number of seconds (at most {MAX_SECONDS:g} in size), got {time!r}")  # NaN too
    if time is None and index is None:
        return None
    return (0.0 if time is None else float(time)), (0 if index is None else index)
