"""Write small glTF 2.0 files (JSON with data: URIs) for tests: primitives with or without
NORMAL / COLOR_0 / TEXCOORD_0 / TEXCOORD_1, in any mode, materials, samplers and a node tree."""

from __future__ import annotations

import base64
import io
import json
from pathlib import Path

import numpy as np

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125  # glTF componentType
_DTYPES = {FLOAT: np.float32, UBYTE: np.uint8, USHORT: np.uint16, UINT: np.uint32}
_TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4", 16: "MAT4"}


class Doc:
    """A glTF document with one buffer, built array by array (what write_gltf and
    add_animation use; tests that shape accessors by hand use it directly)."""

    def __init__(self, blob: bytes = b"", views: list | None = None, accessors: list | None = None):
        self.blob = bytearray(blob)
        self.views, self.accessors = views if views is not None else [], accessors if accessors is not None else []

    def view(self, array: np.ndarray, target: int | None = None) -> int:
        while len(self.blob) % 4:
            self.blob.append(0)
        array = np.ascontiguousarray(array)
        self.views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": array.nbytes} | ({"target": target} if target else {}))
        self.blob.extend(array.tobytes())
        return len(self.views) - 1

    def accessor(self, array, component=FLOAT, target: int | None = None, **extra) -> int:
        array = np.asarray(array, _DTYPES[component])
        width = 1 if array.ndim == 1 else array.shape[1]
        self.accessors.append({"bufferView": self.view(array, target), "componentType": component, "count": len(array), "type": _TYPES[width]} | extra)
        return len(self.accessors) - 1

    def buffer(self, uri: str | None = None) -> dict:
        return {"byteLength": len(self.blob), "uri": uri or "data:application/octet-stream;base64," + base64.b64encode(bytes(self.blob)).decode()}

    def write(self, path: Path, meshes, nodes, uri: str | None = None, **extra) -> Path:
        """meshes: per mesh, its primitives as glTF dicts (accessor indices already made);
        a node with `"_child": True` is left out of the scene's roots."""
        document = {
            "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [i for i, n in enumerate(nodes) if not n.pop("_child", False)]}],
            "nodes": nodes, "meshes": [{"primitives": p} for p in meshes],
            "buffers": [self.buffer(uri)], "bufferViews": self.views, "accessors": self.accessors,
        } | extra
        path.write_text(json.dumps(document))
        return path


def quad(x0: float, y0: float, size: float = 1.0, z: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A square facing +Z (counter-clockwise), lower-left corner at (x0, y0)."""
    positions = np.array([[x0, y0, z], [x0 + size, y0, z], [x0 + size, y0 + size, z], [x0, y0 + size, z]], np.float32)
    return positions, np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def png_data_uri(pixels: np.ndarray) -> str:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(np.asarray(pixels, np.uint8)).save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode()


def write_gltf(path: Path, meshes: list[list[dict]], materials: list[dict] = (), nodes: list[dict] | None = None,
               textures: list[dict] = (), images: list[np.ndarray] = (), samplers: list[dict] = (), extra: dict | None = None) -> Path:
    """meshes: per mesh, primitives as dicts with arrays `positions`, `indices` and optional
    `normals`, `colors` (RGBA float), `uvs`, `uvs1` (TEXCOORD_1), `tangents` (xyzw), plus `material` (index)
    and `mode`. nodes default to one per mesh."""
    doc = Doc()

    def add(array: np.ndarray, component: int, target: int) -> int:
        bounds = {"min": array.min(axis=0).tolist(), "max": array.max(axis=0).tolist()} if component == FLOAT and array.shape[1:] == (3,) else {}
        return doc.accessor(array, component, target, **bounds)

    gltf_meshes = []
    for primitives in meshes:
        out = []
        for primitive in primitives:
            attributes = {"POSITION": add(np.float32(primitive["positions"]), FLOAT, 34962)}
            for key, name in (("normals", "NORMAL"), ("colors", "COLOR_0"), ("uvs", "TEXCOORD_0"), ("uvs1", "TEXCOORD_1"), ("tangents", "TANGENT")):
                if primitive.get(key) is not None:
                    attributes[name] = add(np.float32(primitive[key]), FLOAT, 34962)
            entry = {"attributes": attributes, "indices": add(np.uint32(primitive["indices"]).reshape(-1), UINT, 34963)}
            if primitive.get("material") is not None:
                entry["material"] = primitive["material"]
            if primitive.get("mode") is not None:
                entry["mode"] = primitive["mode"]
            out.append(entry)
        gltf_meshes.append({"primitives": out})
    if nodes is None:
        nodes = [{"mesh": index} for index in range(len(meshes))]
    document = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": gltf_meshes,
        "buffers": [doc.buffer()],
        "bufferViews": doc.views,
        "accessors": doc.accessors,
    }
    if materials:
        document["materials"] = list(materials)
    if images:
        document["images"] = [{"uri": png_data_uri(image)} for image in images]
        document["textures"] = list(textures) or [{"source": 0}]
    if samplers:
        document["samplers"] = list(samplers)
    document.update(extra or {})
    path.write_text(json.dumps(document))
    return path


def add_animation(path: Path, channels: list[tuple[int, str, np.ndarray, np.ndarray]], interpolation: str = "LINEAR") -> Path:
    """Add one animation to a file write_gltf wrote: channels of (node, path — translation,
    rotation, scale or weights —, keyframe times, values (one row per keyframe, or three for
    CUBICSPLINE)), their accessors appended to the file's buffer."""
    document = json.loads(path.read_text())
    doc = Doc(base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1]), document["bufferViews"], document["accessors"])
    samplers, targets = [], []

    def add(array: np.ndarray) -> int:
        return doc.accessor(np.asarray(array, np.float32))

    for node, target, times, values in channels:
        times = np.asarray(times, np.float32)
        time_accessor = add(times)
        document["accessors"][time_accessor] |= {"min": [float(times.min())], "max": [float(times.max())]}
        samplers.append({"input": time_accessor, "output": add(np.asarray(values, np.float32).reshape(-1, 1 if target == "weights" else len(values[0]))),
                         "interpolation": interpolation})
        targets.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": target}})
    document.setdefault("animations", []).append({"samplers": samplers, "channels": targets})
    document["buffers"][0] = doc.buffer()
    path.write_text(json.dumps(document))
    return path
