"""Write the sample meshes of examples/ (knot.obj, gear.ply, arm.glb): procedural, so the project
owns them outright (MIT, like the code) and they stay small. Deterministic: running this
again writes byte-identical files.

    .venv/bin/python examples/make_samples.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def trefoil_knot(segments: int = 180, sides: int = 18, tube: float = 0.42) -> tuple[np.ndarray, np.ndarray]:
    """A trefoil knot tube (a closed grid: no seam, so smooth vertex normals come out whole)."""
    t = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)

    def curve(t):
        return np.stack([np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t), -np.sin(3 * t)], -1)

    center = curve(t)
    tangent = curve(t + 1e-4) - curve(t - 1e-4)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    # A frame that turns smoothly: the normal leans toward the knot's axis (+Z), projected.
    reference = np.array([0.0, 0.0, 1.0])
    normal = reference - tangent * (tangent @ reference)[:, None]
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    binormal = np.cross(tangent, normal)
    angle = np.linspace(0.0, 2.0 * math.pi, sides, endpoint=False)
    ring = np.cos(angle)[None, :, None] * normal[:, None, :] + np.sin(angle)[None, :, None] * binormal[:, None, :]
    positions = (center[:, None, :] + tube * ring).reshape(-1, 3) / 3.0
    i, j = np.meshgrid(np.arange(segments), np.arange(sides), indexing="ij")
    a = i * sides + j
    b = ((i + 1) % segments) * sides + j
    c = ((i + 1) % segments) * sides + (j + 1) % sides
    d = i * sides + (j + 1) % sides
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    # Outward winding: the first triangle's normal must point away from the tube's centre line.
    p = positions[faces[0]]
    if np.dot(np.cross(p[1] - p[0], p[2] - p[0]), p[0] - center[0] / 3.0) < 0:
        faces = faces[:, ::-1]
    return positions, faces


def gear(teeth: int = 14, samples_per_tooth: int = 4, thickness: float = 0.35) -> tuple[np.ndarray, np.ndarray]:
    """A spur gear with a hole, Z up (its axis), every flat face with its own vertices so the
    facets and teeth keep sharp edges. Triangles wound counter-clockwise seen from outside."""
    count = teeth * samples_per_tooth
    angle = np.arange(count) * 2.0 * math.pi / count
    outer_radius = np.where((np.arange(count) % samples_per_tooth) < samples_per_tooth // 2, 1.0, 0.82)
    outer = np.stack([outer_radius * np.cos(angle), outer_radius * np.sin(angle)], -1)
    inner = 0.3 * np.stack([np.cos(angle), np.sin(angle)], -1)
    positions: list = []
    faces: list = []

    def quad(p0, p1, p2, p3):  # counter-clockwise seen from the side the face looks at
        start = len(positions)
        positions.extend([p0, p1, p2, p3])
        faces.extend([[start, start + 1, start + 2], [start, start + 2, start + 3]])

    top, bottom = thickness / 2.0, -thickness / 2.0
    for k in range(count):
        n = (k + 1) % count
        o0, o1, i0, i1 = outer[k], outer[n], inner[k], inner[n]
        quad([*i0, top], [*o0, top], [*o1, top], [*i1, top])  # top cap, seen from +Z
        quad([*i1, bottom], [*o1, bottom], [*o0, bottom], [*i0, bottom])  # bottom cap, from -Z
        quad([*o0, bottom], [*o1, bottom], [*o1, top], [*o0, top])  # outer wall (teeth)
        quad([*i1, bottom], [*i0, bottom], [*i0, top], [*i1, top])  # the hole's wall
    return np.array(positions), np.array(faces)


def _box(lower, upper) -> tuple[np.ndarray, np.ndarray]:
    """A box with flat faces (4 corners each, counter-clockwise seen from outside)."""
    (x0, y0, z0), (x1, y1, z1) = lower, upper
    faces = [((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)), ((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)),
             ((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)), ((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)),
             ((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)), ((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1))]
    positions = np.array([corner for face in faces for corner in face], np.float32)
    quads = np.arange(24).reshape(6, 4)
    return positions, np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]).astype(np.uint16)


def _quaternion(axis, degrees) -> list[float]:
    half = math.radians(degrees) / 2.0
    return [float(v) for v in (*(np.asarray(axis, float) * math.sin(half)), math.cos(half))]


def _look_rotation(eye, target) -> list[float]:
    """The quaternion turning a glTF camera (looking down −Z, +Y up) to look from eye at target."""
    back = np.asarray(eye, float) - np.asarray(target, float)
    back /= np.linalg.norm(back)
    right = np.cross([0.0, 1.0, 0.0], back)
    right /= np.linalg.norm(right)
    up = np.cross(back, right)
    m = np.stack([right, up, back], axis=1)  # columns: the camera's x, y, z in the world
    w = math.sqrt(max(1.0 + np.trace(m), 0.0)) / 2.0
    return [float((m[2, 1] - m[1, 2]) / (4 * w)), float((m[0, 2] - m[2, 0]) / (4 * w)), float((m[1, 0] - m[0, 1]) / (4 * w)), w]


def arm() -> bytes:
    """arm.glb: a base and an arm of two segments bent by a skin, with two animations (0
    "wave": the elbow swings ±70° over 4 s; 1 "turn": the whole arm turns about Y over
    4 s) and a camera, for `--animation-time`, `animate` and `--camera-index`
    (docs/animation.md). A GLB: the JSON chunk, then the binary one."""
    import json
    import struct

    blob = bytearray()
    views, accessors = [], []

    def add(array: np.ndarray, kind: str, component: int, bounds: bool = False) -> int:
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes})
        blob.extend(np.ascontiguousarray(array).tobytes())
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": len(array), "type": kind}
        if bounds:
            accessor |= {"min": array.min(axis=0).reshape(-1).tolist(), "max": array.max(axis=0).reshape(-1).tolist()}
        accessors.append(accessor)
        return len(accessors) - 1

    base, base_faces = _box((-0.5, 0.0, -0.5), (0.5, 0.2, 0.5))
    rings = np.linspace(0.2, 2.2, 11)
    bar = np.array([[x, y, z] for y in rings for x, z in ((-0.12, -0.12), (0.12, -0.12), (0.12, 0.12), (-0.12, 0.12))], np.float32)
    bar_faces = []
    for k in range(len(rings) - 1):
        for i in range(4):
            a, b = k * 4 + i, k * 4 + (i + 1) % 4
            bar_faces += [[a, a + 4, b + 4], [a, b + 4, b]]
    top = (len(rings) - 1) * 4
    bar_faces += [[0, 1, 2], [0, 2, 3], [top, top + 2, top + 1], [top, top + 3, top + 2]]
    elbow = np.clip((bar[:, 1] - 1.0) / 0.4, 0.0, 1.0)  # blended over 1.0..1.4 around the elbow at 1.2
    weights = np.stack([1.0 - elbow, elbow, 0 * elbow, 0 * elbow], axis=1).astype(np.float32)
    joints = np.tile(np.array([0, 1, 0, 0], np.uint16), (len(bar), 1))
    inverse_bind = np.stack([np.eye(4), np.eye(4)])
    inverse_bind[0, 1, 3], inverse_bind[1, 1, 3] = -0.2, -1.2
    float_, ushort = 5126, 5123
    meshes = [
        {"name": "base", "primitives": [{"attributes": {"POSITION": add(base, "VEC3", float_, True)},
                                         "indices": add(base_faces.reshape(-1), "SCALAR", ushort), "material": 0}]},
        {"name": "arm", "primitives": [{"attributes": {"POSITION": add(bar, "VEC3", float_, True), "JOINTS_0": add(joints, "VEC4", ushort),
                                                       "WEIGHTS_0": add(weights, "VEC4", float_)},
                                        "indices": add(np.array(bar_faces, np.uint16).reshape(-1), "SCALAR", ushort), "material": 1}]},
    ]
    skin = {"joints": [2, 3], "inverseBindMatrices": add(inverse_bind.transpose(0, 2, 1).reshape(2, 16).astype(np.float32), "MAT4", float_)}
    times = add(np.array([[0.0], [1.0], [2.0], [3.0], [4.0]], np.float32), "SCALAR", float_, True)
    wave = add(np.array([_quaternion((0, 0, 1), d) for d in (0, 70, 0, -70, 0)], np.float32), "VEC4", float_)
    turn = add(np.array([_quaternion((0, 1, 0), d) for d in (0, 90, 180, 270, 360)], np.float32), "VEC4", float_)
    document = {
        "asset": {"version": "2.0", "generator": "wgpu-shading examples/make_samples.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 5]}],
        "nodes": [
            {"name": "root", "children": [1, 2, 4]},
            {"name": "base", "mesh": 0},
            {"name": "shoulder", "translation": [0.0, 0.2, 0.0], "children": [3]},
            {"name": "elbow", "translation": [0.0, 1.0, 0.0]},
            {"name": "arm", "mesh": 1, "skin": 0},
            {"name": "camera", "camera": 0, "translation": [2.5, 1.8, 3.5], "rotation": _look_rotation((2.5, 1.8, 3.5), (0.0, 1.0, 0.0))},
        ],
        "meshes": meshes,
        "skins": [skin],
        "materials": [
            {"name": "steel", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.55, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5}},
            {"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.35, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.4}},
        ],
        "animations": [
            {"name": "wave", "samplers": [{"input": times, "output": wave}], "channels": [{"sampler": 0, "target": {"node": 3, "path": "rotation"}}]},
            {"name": "turn", "samplers": [{"input": times, "output": turn}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "rotation"}}]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1, "zfar": 50.0}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    while len(blob) % 4:
        blob.append(0)
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(blob), b"BIN\0") + bytes(blob)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def main() -> None:
    import trimesh

    positions, faces = trefoil_knot()
    lines = ["# Trefoil knot tube, generated by examples/make_samples.py (MIT, wgpu-shading)"]
    lines += [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in positions]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    (HERE / "knot.obj").write_text("\n".join(lines) + "\n")

    positions, faces = gear()
    mesh = trimesh.Trimesh(positions, faces, process=False)
    (HERE / "gear.ply").write_bytes(trimesh.exchange.ply.export_ply(mesh, encoding="binary", vertex_normal=False))
    (HERE / "arm.glb").write_bytes(arm())


if __name__ == "__main__":
    main()
