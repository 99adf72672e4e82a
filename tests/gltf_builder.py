"""Write small glTF 2.0 files (JSON with data: URIs) for tests: primitives with or without
NORMAL / COLOR_0 / TEXCOORD_0 / TEXCOORD_1, in any mode, materials, samplers and a node tree."""

from __future__ import annotations

import base64
import io
import json
from pathlib import Path

import numpy as np

_FLOAT, _UINT = 5126, 5125
_TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}


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
    blob = bytearray()
    views, accessors = [], []

    def add(array: np.ndarray, component: int, target: int | None) -> int:
        array = np.ascontiguousarray(array)
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes} | ({"target": target} if target else {}))
        blob.extend(array.tobytes())
        width = 1 if array.ndim == 1 else array.shape[1]
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": len(array), "type": _TYPES[width]}
        if component == _FLOAT and width == 3:
            accessor |= {"min": array.min(axis=0).tolist(), "max": array.max(axis=0).tolist()}
        accessors.append(accessor)
        return len(accessors) - 1

    gltf_meshes = []
    for primitives in meshes:
        out = []
        for primitive in primitives:
            attributes = {"POSITION": add(np.float32(primitive["positions"]), _FLOAT, 34962)}
            for key, name in (("normals", "NORMAL"), ("colors", "COLOR_0"), ("uvs", "TEXCOORD_0"), ("uvs1", "TEXCOORD_1"), ("tangents", "TANGENT")):
                if primitive.get(key) is not None:
                    attributes[name] = add(np.float32(primitive[key]), _FLOAT, 34962)
            entry = {"attributes": attributes, "indices": add(np.uint32(primitive["indices"]).reshape(-1), _UINT, 34963)}
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
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
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
    buffer = document["buffers"][0]
    blob = bytearray(base64.b64decode(buffer["uri"].split(",", 1)[1]))
    samplers, targets = [], []

    def add(array: np.ndarray) -> int:
        array = np.ascontiguousarray(array, np.float32)
        while len(blob) % 4:
            blob.append(0)
        document["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes})
        blob.extend(array.tobytes())
        width = 1 if array.ndim == 1 else array.shape[1]
        document["accessors"].append({"bufferView": len(document["bufferViews"]) - 1, "componentType": _FLOAT,
                                      "count": len(array), "type": _TYPES[width]})
        return len(document["accessors"]) - 1

    for node, target, times, values in channels:
        times = np.asarray(times, np.float32)
        time_accessor = add(times)
        document["accessors"][time_accessor] |= {"min": [float(times.min())], "max": [float(times.max())]}
        samplers.append({"input": time_accessor, "output": add(np.asarray(values, np.float32).reshape(-1, 1 if target == "weights" else len(values[0]))),
                         "interpolation": interpolation})
        targets.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": target}})
    document.setdefault("animations", []).append({"samplers": samplers, "channels": targets})
    buffer["byteLength"] = len(blob)
    buffer["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()
    path.write_text(json.dumps(document))
    return path
