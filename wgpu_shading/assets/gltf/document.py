"""The binary side of a glTF 2.0 file: GLB chunks, buffers, buffer views, accessors, images.

Read by our own code (not trimesh) so that every count and offset is checked against the
file and the documented limits before anything is allocated (docs/reliability.md,
"glTF files"): an 831-byte file whose accessor claimed 2²⁶ zero vertices took 30 s and
6.2 GB through trimesh. Sparse accessors (glTF 2.0 §3.6.2.3) are applied; URIs are
percent-decoded (§3.1: URIs are RFC 3986 references) and data: URIs decoded (large base64
ones straight from the file's bytes: data_uris.py); buffers and
images named by a URI must be regular files (a FIFO would block the reader forever).
"""

from __future__ import annotations

import base64
import json
import os
import struct
from pathlib import Path
from urllib.parse import unquote

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_VERTICES
from ..files import check_regular_file
from . import meshopt
from .data_uris import decode_data_uris

MAX_GLTF_ITEMS = 1 << 20  # nodes, meshes, accessors, ... in one file (each list)
MAX_ACCESSOR_COUNT = MAX_VERTICES  # elements of one accessor (2^25)
MAX_BUFFER_BYTES = 2 << 30  # one buffer: the mesh file limit
_COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_GLB_JSON, _GLB_BIN = 0x4E4F534A, 0x004E4942


def gltf_error(path: Path, field: str, detail: str) -> MeshError:
    return MeshError(f"mesh file {str(path)!r}: {field}: {detail}")


def regular_file_size(file: Path, where: str) -> int:
    """The size of `file`, refusing anything but a regular file without opening it (a FIFO
    or a device blocks or never ends: assets/files.py)."""
    check_regular_file(file, where, MeshError)
    try:
        return os.stat(file).st_size
    except (OSError, ValueError) as error:
        raise MeshError(f"{where}: cannot be read ({getattr(error, 'strerror', None) or error})") from None


def split_glb(raw: bytes, path: Path) -> tuple[bytes, memoryview | None]:
    """The JSON and BIN chunks of a GLB (glTF 2.0 §4.4), every length checked."""
    if len(raw) < 20:
        raise gltf_error(path, "GLB header", f"the file has {len(raw)} bytes, a GLB needs at least 20")
    version, total = struct.unpack_from("<II", raw, 4)
    if version != 2:
        raise gltf_error(path, "GLB header", f"version {version}; only glTF 2.0 is supported")
    end = min(total, len(raw))
    chunks, offset = [], 12
    while offset + 8 <= end:
        length, kind = struct.unpack_from("<II", raw, offset)
        if offset + 8 + length > end:
            raise gltf_error(path, "GLB chunk", f"a chunk of {length} bytes at byte {offset} runs past the end of the file ({end} bytes)")
        chunks.append((kind, memoryview(raw)[offset + 8 : offset + 8 + length]))  # no copy of the BIN chunk
        offset += 8 + length  # lengths include their padding (some writers leave it out)
    if not chunks or chunks[0][0] != _GLB_JSON:
        raise gltf_error(path, "GLB", "the first chunk is not JSON")
    binary = next((data for kind, data in chunks[1:] if kind == _GLB_BIN), None)
    return bytes(chunks[0][1]), binary


def _json_number(text: str) -> int | float:
    """A JSON number with a fraction or exponent: an int when it is a whole number. JSON has
    one number type, so `1.0` and `10e-1` are valid integers wherever glTF asks for one (the
    glTF-Validator's json/integer_written_as_float case); 1.5 stays a float and is refused
    where an index belongs, naming the field. Beyond 2^53 floats are not exact integers."""
    value = float(text)
    return int(value) if value.is_integer() and abs(value) <= 2.0**53 else value


def parse_json(text: bytes, path: Path) -> dict:
    try:
        document = json.loads(text, parse_float=_json_number)
    except (ValueError, struct.error) as error:
        raise MeshError(f"mesh file {str(path)!r}: not a valid glTF file ({error})") from None
    except RecursionError:
        raise MeshError(f"mesh file {str(path)!r}: not a valid glTF file (its JSON is nested too deeply)") from None
    if not isinstance(document, dict):
        raise MeshError(f"mesh file {str(path)!r}: not a valid glTF file (expected a JSON object, got {type(document).__name__})")
    return document


class GltfData:
    """A glTF document and lazy access to its buffers, accessors and images."""

    def __init__(self, path: Path, json_only: bool = False):
        """json_only: read a GLB's JSON chunk alone (for its lights); buffers are then absent."""
        self.path = path
        regular_file_size(path, f"mesh file {str(path)!r}")
        with open(path, "rb", buffering=0) as file:  # unbuffered: read() below is one piece
            raw = file.read(20)
            if json_only and raw[:4] == b"glTF" and len(raw) == 20:
                raw += file.read(struct.unpack_from("<I", raw, 12)[0])
            else:  # the whole file in one piece: `raw += file.read()` held it twice
                file.seek(0)
                raw = file.read()
        self.binary: memoryview | None = None
        self._data_uris: dict[str, bytes | None] = {}  # marker → a large data: URI's bytes (data_uris.py)
        if raw[:4] == b"glTF":
            text, self.binary = split_glb(raw, path)
        else:
            text, self._data_uris = decode_data_uris(raw, decode=not json_only)
        del raw  # an embedded glTF's text: its buffers are decoded now
        self.document = parse_json(text, path)
        self.notes: list[str] = []  # warnings for the user, said once the file is read (meshes.py)
        self._buffers: dict[int, bytes] = {}
        self._accessors: dict[tuple[int, bool], np.ndarray] = {}
        self._decoded_views: dict[object, bytes] = {}
        self._forgotten = False  # forget_binary_data() was called
        # reader.py's classic materials, made (their textures decoded) once however many times
        # the document is posed (an animation's frames: assets/animation_frames.py)
        self.materials: dict[tuple, object] = {}

    # ------------------------------------------------------------------ JSON fields

    def items(self, key: str) -> list:
        """A top-level list of the document (nodes, meshes, ...), checked to be a list of
        objects within MAX_GLTF_ITEMS."""
        value = self.document.get(key, [])
        if not isinstance(value, list):
            raise gltf_error(self.path, key, f"expected a list, got {type(value).__name__}")
        if len(value) > MAX_GLTF_ITEMS:
            raise gltf_error(self.path, key, f"{len(value)} entries; at most {MAX_GLTF_ITEMS} are supported")
        return value

    def item(self, key: str, index: object, field: str) -> dict:
        """Entry `index` of a top-level list, with an error naming `field` if it is not one."""
        table = self.items(key)
        if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(table):
            kind = "an integer index" if isinstance(index, float) else "an index"
            raise gltf_error(self.path, field, f"{_short(index)} is not {kind} into {key} (0..{len(table) - 1})")
        entry = table[index]
        if not isinstance(entry, dict):
            raise gltf_error(self.path, f"{key}[{index}]", f"expected an object, got {type(entry).__name__}")
        return entry

    def integer(self, value: object, field: str, low: int = 0, high: int = MAX_BUFFER_BYTES) -> int:
        if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
            raise gltf_error(self.path, field, f"expected an integer in {low}..{high}, got {_short(value)}")
        return value

    # ------------------------------------------------------------------ buffers

    def uri_bytes(self, uri: object, field: str, limit: int) -> bytes:
        """The bytes a glTF URI names: a data: URI, or a file relative to the glTF file
        (percent-decoded), at most `limit` bytes."""
        if not isinstance(uri, str):
            raise gltf_error(self.path, field, f"expected a URI string, got {_short(uri)}")
        if uri in self._data_uris:
            data = self._data_uris[uri]
            if data is None:
                raise RuntimeError(f"{self.path}: read for its JSON alone (json_only) before {field} was read")
            return data
        if uri.startswith("data:"):
            header, _, payload = uri.partition(",")
            try:
                data = base64.b64decode(payload, validate=False) if header.endswith(";base64") else unquote(payload).encode("latin-1")
            except (ValueError, UnicodeEncodeError) as error:
                raise gltf_error(self.path, field, f"a data: URI that cannot be decoded ({error})") from None
            return data
        if ":" in uri.split("/", 1)[0] and not (len(uri) > 1 and uri[1] == ":"):
            raise gltf_error(self.path, field, f"{_short(uri)}: only files next to the glTF file and data: URIs are read")
        name = unquote(uri)
        if "\x00" in name:
            raise gltf_error(self.path, field, f"{_short(uri)}: a path cannot contain a NUL character")
        file = self.path.parent / name
        where = f"mesh file {str(self.path)!r}: {field} {str(file)!r}"
        if not file.exists():
            raise MeshError(f"{where}: not found")
        size = regular_file_size(file, where)
        if size > limit:
            raise MeshError(f"{where}: {size} bytes; at most {limit} are read")
        try:
            return file.read_bytes()
        except OSError as error:
            raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None

    def buffer(self, index: object, field: str) -> bytes:
        if index in self._buffers:
            return self._buffers[index]
        if self._forgotten:
            raise RuntimeError(f"{self.path}: its binary data was let go (forget_binary_data) before {field} was read")
        entry = self.item("buffers", index, field)
        where = f"buffers[{index}]"
        length = self.integer(entry.get("byteLength"), f"{where}.byteLength", 1)
        if "uri" in entry:
            data = self.uri_bytes(entry["uri"], f"{where}.uri", MAX_BUFFER_BYTES)
        elif index == 0 and self.binary is not None:
            data = self.binary
        else:
            raise gltf_error(self.path, where, "has no uri and the file has no binary chunk")
        if len(data) < length:
            raise gltf_error(self.path, f"{where}.byteLength", f"{length} bytes declared, {len(data)} present")
        self._buffers[index] = data
        return data

    def view(self, index: object, field: str) -> tuple[bytes, int, int, int | None]:
        """(buffer, start, length, byteStride) of a buffer view, its range checked; a view
        compressed with EXT_meshopt_compression decoded (once) into a buffer of its own."""
        entry = self.item("bufferViews", index, field)
        where = f"bufferViews[{index}]"
        length = self.integer(entry.get("byteLength"), f"{where}.byteLength", 1, MAX_BUFFER_BYTES)
        stride = entry.get("byteStride")
        if stride is not None:
            stride = self.integer(stride, f"{where}.byteStride", 4, 252)
        compressed = entry.get("extensions", {}).get(meshopt.EXTENSION) if isinstance(entry.get("extensions"), dict) else None
        if compressed is not None:
            if index not in self._decoded_views:
                self._decoded_views[index] = meshopt.decode_view(self, compressed, length, where)
            return self._decoded_views[index], 0, length, stride
        data = self.buffer(entry.get("buffer"), f"{where}.buffer")
        start = self.integer(entry.get("byteOffset", 0), f"{where}.byteOffset")
        if start + length > len(data):
            raise gltf_error(self.path, where, f"bytes {start}..{start + length} lie beyond its buffer ({len(data)} bytes)")
        return data, start, length, stride

    def error(self, field: str, detail: str) -> MeshError:
        return gltf_error(self.path, field, detail)

    def buffer_range(self, buffer: object, start: int, length: int, field: str) -> bytes:
        """Bytes start..start + length of a buffer, the range checked."""
        data = self.buffer(buffer, f"{field}.buffer")
        if start + length > len(data):
            raise gltf_error(self.path, field, f"bytes {start}..{start + length} lie beyond buffer {buffer} ({len(data)} bytes)")
        return bytes(data[start : start + length])

    def view_bytes(self, index: object, field: str) -> bytes:
        data, start, length, _ = self.view(index, field)
        return bytes(data[start : start + length])

    # ------------------------------------------------------------------ accessors

    def forget_binary_data(self) -> None:
        """Let go of the file's binary data and what was read from it (buffers, accessors,
        decoded views): the document's JSON stays, which is all its lights and cameras read.
        Once a read's pieces are made, what they need is in them, and a big mesh's buffers
        and float64 accessors, kept for the lights and cameras' sake, were twice its arrays
        while the Mesh was built (docs/performance.md, "Loading a large mesh"). Reading an
        accessor afterwards is an error."""
        self._accessors.clear()
        self._buffers.clear()
        self._decoded_views.clear()
        self._data_uris.clear()
        self.binary = None
        self._forgotten = True

    def accessor(self, index: object, field: str, as_stored: bool = False) -> np.ndarray:
        """An accessor's elements as an (count, width) array: float64 for floats and
        normalized integers (§3.11: c / (2^n − 1), signed ones clamped at −1), int64 for
        integers; sparse substitutions applied. `as_stored`: float32 stays float32 (a
        read-only view of the file's bytes where it can be) and unsigned integers become
        uint32, for a big mesh's positions, normals and indices: their float64 and int64
        copies were most of a 10M-triangle load's peak (docs/performance.md, "Loading a large
        mesh"). Its reader converts them to float64 itself, where it computes with them."""
        if isinstance(index, int) and (index, as_stored) in self._accessors:
            return self._accessors[index, as_stored]
        entry = self.item("accessors", index, field)
        where = f"accessors[{index}]"
        dtype = _lookup(_COMPONENTS, entry.get("componentType"))
        if dtype is None:
            raise gltf_error(self.path, f"{where}.componentType", f"{_short(entry.get('componentType'))} is not a glTF component type")
        width = _lookup(_WIDTHS, entry.get("type"))
        if width is None:
            raise gltf_error(self.path, f"{where}.type", f"{_short(entry.get('type'))} is not a glTF accessor type")
        count = self.integer(entry.get("count"), f"{where}.count", 1, MAX_ACCESSOR_COUNT)
        dtype = np.dtype(dtype).newbyteorder("<")
        if width in (4, 9) and entry["type"].startswith("MAT") and dtype.itemsize < 4:
            raise gltf_error(self.path, f"{where}.type", f"{entry['type']} of {dtype.itemsize}-byte components is not supported")
        if "bufferView" in entry:
            data, start, length, stride = self.view(entry["bufferView"], f"{where}.bufferView")
            offset = self.integer(entry.get("byteOffset", 0), f"{where}.byteOffset")
            element = width * dtype.itemsize
            stride = stride or element
            if stride < element:
                raise gltf_error(self.path, where, f"byteStride {stride} is smaller than one element ({element} bytes)")
            needed = offset + stride * (count - 1) + element
            if needed > length:
                raise gltf_error(self.path, where, f"{count} elements need {needed} bytes of bufferView {entry['bufferView']}, which has {length}")
            values = np.ndarray((count, width), dtype, buffer=data, offset=start + offset, strides=(stride, dtype.itemsize))
        else:
            if "sparse" not in entry:
                raise gltf_error(self.path, where, "has neither a bufferView nor sparse values (every element would be zero)")
            values = np.zeros((count, width), dtype)
        if "sparse" in entry:
            values = self._apply_sparse(values, entry["sparse"], count, width, dtype, where)
        values = self._convert(values, dtype, bool(entry.get("normalized", False)), as_stored)
        if isinstance(index, int):
            self._accessors[index, as_stored] = values
        return values

    def _apply_sparse(self, values, sparse, count, width, dtype, where) -> np.ndarray:
        if not isinstance(sparse, dict) or not isinstance(sparse.get("indices"), dict) or not isinstance(sparse.get("values"), dict):
            raise gltf_error(self.path, f"{where}.sparse", "expected an object with count, indices and values")
        changed = self.integer(sparse.get("count"), f"{where}.sparse.count", 1, count)
        indices_entry, values_entry = sparse["indices"], sparse["values"]
        index_type = _lookup(_COMPONENTS, indices_entry.get("componentType"))
        if index_type not in (np.uint8, np.uint16, np.uint32):
            raise gltf_error(self.path, f"{where}.sparse.indices.componentType", f"{_short(indices_entry.get('componentType'))}: expected 5121, 5123 or 5125")
        index_type = np.dtype(index_type).newbyteorder("<")
        positions = self._packed(indices_entry, changed, 1, index_type, f"{where}.sparse.indices").reshape(-1).astype(np.int64)
        if positions.max() >= count:
            raise gltf_error(self.path, f"{where}.sparse.indices", f"index {int(positions.max())} is beyond the accessor's {count} elements")
        replacement = self._packed(values_entry, changed, width, dtype, f"{where}.sparse.values")
        values = np.array(values)  # a copy: the buffer itself is shared and read-only
        values[positions] = replacement
        return values

    def _packed(self, entry: dict, count: int, width: int, dtype: np.dtype, where: str) -> np.ndarray:
        data, start, length, _ = self.view(entry.get("bufferView"), f"{where}.bufferView")
        offset = self.integer(entry.get("byteOffset", 0), f"{where}.byteOffset")
        needed = offset + count * width * dtype.itemsize
        if needed > length:
            raise gltf_error(self.path, where, f"{count} elements need {needed} bytes of its bufferView, which has {length}")
        return np.frombuffer(data, dtype, count * width, start + offset).reshape(count, width)

    @staticmethod
    def _convert(values: np.ndarray, dtype: np.dtype, normalized: bool, as_stored: bool) -> np.ndarray:
        if as_stored and not normalized and dtype.kind in "fu":
            return values if dtype.kind == "f" else values.astype(np.uint32)
        if dtype.kind == "f":
            return values.astype(np.float64)
        if normalized:
            scaled = values.astype(np.float64) / float(np.iinfo(dtype).max)
            return np.maximum(scaled, -1.0) if dtype.kind == "i" else scaled
        return values.astype(np.int64)

    # ------------------------------------------------------------------ images

    def image_bytes(self, index: object, field: str, limit: int) -> bytes:
        entry = self.item("images", index, field)
        if "uri" in entry:
            return self.uri_bytes(entry["uri"], f"images[{index}].uri", limit)
        if "bufferView" in entry:
            return self.view_bytes(entry["bufferView"], f"images[{index}].bufferView")
        raise gltf_error(self.path, f"images[{index}]", "has neither a uri nor a bufferView")


def _lookup(table: dict, key: object):
    """table[key], or None for a missing or unhashable key (a list where a number belongs)."""
    return table.get(key) if isinstance(key, (int, str)) and not isinstance(key, bool) else None


def _short(value: object) -> str:
    import reprlib

    return reprlib.repr(value)
