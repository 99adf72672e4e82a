"""Morph targets (glTF 2.0 §3.7.2.2): a primitive's vertices moved by weighted
displacements before skinning and the node's transform.

    position = POSITION + Σ_i weight_i · targets[i].POSITION

and likewise NORMAL (then normalized) and TANGENT (its xyz; the handedness w is kept).
The weights are the node's `weights`, else its mesh's, else zero (§3.7.2.2), or what an
animation sets at the chosen time (animations.py gives them as the node's). Sparse target
accessors, which exporters use for targets that move few vertices, are read as any
accessor (document.py). Targets of weight 0 are not read at all.
"""

from __future__ import annotations

import numpy as np

from .document import GltfData, gltf_error

_MORPHED = ("POSITION", "NORMAL", "TANGENT")


def morph_weights(data: GltfData, node: dict, mesh: dict, where: str) -> list[float] | None:
    """The weights a node gives its mesh's targets: the node's own, else the mesh's."""
    for owner, field in ((node, f"{where}.weights"), (mesh, "weights")):
        weights = owner.get("weights")
        if weights is None:
            continue
        if type(weights) is not list or not all(type(w) in (int, float) and abs(w) <= 1e6 for w in weights):
            raise gltf_error(data.path, field, f"expected a list of numbers within ±1e6, got {str(weights)[:60]}")
        return [float(w) for w in weights]
    return None


def apply_morph_targets(data: GltfData, primitive: dict, arrays: dict, weights: list[float] | None, where: str) -> dict:
    """`arrays` (primitives.py) with POSITION, NORMAL and TANGENT morphed by `weights`;
    the same dict when nothing moves."""
    targets = primitive.get("targets")
    if not targets or not weights or not any(weights):
        return arrays
    if not isinstance(targets, list) or not all(isinstance(t, dict) for t in targets):
        raise gltf_error(data.path, f"{where}.targets", "expected a list of objects (attribute name → accessor)")
    if len(weights) != len(targets):
        data.notes.append(f"{data.path.name}: {where}: {len(weights)} morph weights for {len(targets)} targets; "
                          f"{'the extra weights are ignored' if len(weights) > len(targets) else 'the missing ones are 0'}")
    count = len(arrays["POSITION"])
    out = dict(arrays)
    for name in _MORPHED:
        if arrays.get(name) is None:
            continue
        moved = arrays[name][:, :3].astype(np.float64)  # (a copy; POSITION and NORMAL may be stored float32)
        for index, (target, weight) in enumerate(zip(targets, weights)):
            if weight == 0.0 or name not in target:
                continue
            field = f"{where}.targets[{index}].{name}"
            delta = data.accessor(target[name], field).astype(np.float64)  # KHR_mesh_quantization: integers too
            if delta.shape != (count, 3) or not np.isfinite(delta).all():
                raise gltf_error(data.path, field, f"expected {count} finite VEC3 displacements, got {delta.shape[0]} of width {delta.shape[1]}")
            moved += weight * delta
        if name == "NORMAL":
            length = np.linalg.norm(moved, axis=1, keepdims=True)
            moved = np.where(length > 0.0, moved / np.where(length > 0.0, length, 1.0), arrays[name])
        out[name] = moved if name != "TANGENT" else np.concatenate([moved, arrays[name][:, 3:]], axis=1)
    if not np.isfinite(out["POSITION"]).all():
        raise gltf_error(data.path, f"{where}.targets", "the morphed positions are not finite")
    return out
