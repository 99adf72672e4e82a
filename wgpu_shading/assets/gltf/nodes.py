"""glTF node graphs: world matrices, scene instances and skin poses.

The graph is walked iteratively in one pass (a 100,000-deep chain of nodes took over a
minute before): glTF 2.0 §3.5.3 makes the nodes a forest (no node has two parents, no
cycles), which is checked here, so each world matrix is computed once from its parent's.
Nodes scaled to zero (how exporters hide objects) are skipped with everything below them.
Skins (§3.7.3) are posed without animation, as viewers show a skinned file: each joint's
world matrix times its inverse bind matrix, blended by the vertex weights (the mesh
node's own transform is ignored for skinned meshes, as the spec says).
"""

from __future__ import annotations

import numpy as np

from .document import GltfData, gltf_error

_SKIN_CHUNK = 1 << 16  # vertices posed at a time: the (n, k, 4, 4) gathered matrices stay near 32 MB


def _numbers(data: GltfData, value: object, size: int, field: str) -> list[float]:
    """A node's list of `size` finite numbers (plain Python: this runs once per node)."""
    if type(value) is not list or len(value) != size:
        raise gltf_error(data.path, field, f"expected {size} numbers, got {_repr(value)}")
    for number in value:
        if type(number) not in (int, float) or not -1e15 <= number <= 1e15:  # NaN fails both
            raise gltf_error(data.path, field, f"expected {size} finite numbers within ±1e15, got {_repr(value)}")
    return value


def local_matrices(data: GltfData, nodes: list) -> tuple[np.ndarray, np.ndarray]:
    """(n, 4, 4) local matrices: `matrix` (column-major in the file) or T · R · S
    (§3.5.2), built in one numpy pass; and (n,) the determinants of their 3×3 parts."""
    count = len(nodes)
    translation, scale = np.zeros((count, 3)), np.ones((count, 3))
    rotation = np.tile([0.0, 0.0, 0.0, 1.0], (count, 1))
    given: dict[int, list[float]] = {}
    for index, node in enumerate(nodes):
        if "matrix" in node:
            given[index] = _numbers(data, node["matrix"], 16, f"nodes[{index}].matrix")
            continue
        if "translation" in node:
            translation[index] = _numbers(data, node["translation"], 3, f"nodes[{index}].translation")
        if "rotation" in node:
            rotation[index] = _numbers(data, node["rotation"], 4, f"nodes[{index}].rotation")
        if "scale" in node:
            scale[index] = _numbers(data, node["scale"], 3, f"nodes[{index}].scale")
    length = np.linalg.norm(rotation, axis=1)
    if (length == 0.0).any():
        first = int(np.flatnonzero(length == 0.0)[0])
        raise gltf_error(data.path, f"nodes[{first}].rotation", "a quaternion of length 0")
    x, y, z, w = (rotation / length[:, None]).T
    turn = np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], axis=1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], axis=1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=1),
    ], axis=1)
    matrices = np.zeros((count, 4, 4))
    matrices[:, :3, :3] = turn * scale[:, None, :]
    matrices[:, :3, 3] = translation
    matrices[:, 3, 3] = 1.0
    determinants = np.prod(scale, axis=1)  # a rotation's is 1
    for index, values in given.items():
        matrices[index] = np.array(values, dtype=np.float64).reshape(4, 4).T
        determinants[index] = np.linalg.det(matrices[index, :3, :3])
    return matrices, determinants


def world_matrices(data: GltfData, nodes: list | None = None) -> tuple[list[np.ndarray | None], list[int]]:
    """Every node's world matrix (None below a node scaled to zero) and the root nodes,
    in one iterative walk; a node with two parents or a cycle is an error. `nodes`: the
    file's nodes as an animation poses them (animations.py), else the file's own."""
    nodes = data.items("nodes") if nodes is None else nodes
    parent = [-1] * len(nodes)
    for index, node in enumerate(nodes):
        if not isinstance(node, dict):
            raise gltf_error(data.path, f"nodes[{index}]", f"expected an object, got {type(node).__name__}")
        children = node.get("children", [])
        if not isinstance(children, list):
            raise gltf_error(data.path, f"nodes[{index}].children", f"expected a list, got {_repr(children)}")
        for child in children:
            data.item("nodes", child, f"nodes[{index}].children")
            if parent[child] != -1 or child == index:
                raise gltf_error(data.path, f"nodes[{index}].children", f"node {child} has two parents or is its own child (glTF nodes form trees)")
            parent[child] = index
    roots = [index for index in range(len(nodes)) if parent[index] == -1]
    local, local_determinant = local_matrices(data, nodes)
    world: list[np.ndarray | None] = [None] * len(nodes)
    reached = [False] * len(nodes)
    stack = [(root, np.eye(4), 1.0) for root in reversed(roots)]
    while stack:
        index, parent_matrix, parent_determinant = stack.pop()
        reached[index] = True
        matrix, determinant = None, 0.0
        if parent_matrix is not None:
            determinant = parent_determinant * float(local_determinant[index])
            # scaled to zero (how exporters hide objects): hidden, with its subtree
            if abs(determinant) >= 1e-30 and np.isfinite(determinant):
                matrix = parent_matrix @ local[index]
        world[index] = matrix
        stack.extend((child, matrix, determinant) for child in reversed(nodes[index].get("children", [])))
    finite = [m for m in world if m is not None]
    if finite and not np.isfinite(np.stack(finite)).all():
        raise gltf_error(data.path, "nodes", "a world matrix overflows (transforms multiply beyond float range)")
    if not all(reached):
        first = reached.index(False)
        raise gltf_error(data.path, f"nodes[{first}]", "lies on a cycle of children (glTF nodes form trees)")
    return world, roots


def scene_roots(data: GltfData, roots: list[int]) -> list[int]:
    """The root nodes of the scene to draw: `scene` (else scenes[0]); every root when the
    file has no scenes."""
    scenes = data.items("scenes")
    if not scenes:
        return roots
    chosen = data.document.get("scene", 0)
    scene = data.item("scenes", chosen, "scene")
    listed = scene.get("nodes", [])
    if not isinstance(listed, list):
        raise gltf_error(data.path, f"scenes[{chosen}].nodes", f"expected a list, got {_repr(listed)}")
    for node in listed:
        data.item("nodes", node, f"scenes[{chosen}].nodes")
    return listed


def scene_nodes(data: GltfData, roots: list[int]) -> list[int]:
    """The nodes of the scene in depth-first order (iterative)."""
    nodes = data.items("nodes")
    order, stack = [], list(reversed(roots))
    seen = set()
    while stack:
        index = stack.pop()
        if index in seen:
            raise gltf_error(data.path, "scene nodes", f"node {index} is listed twice")
        seen.add(index)
        order.append(index)
        stack.extend(reversed(nodes[index].get("children", [])))
    return order


def skin_matrices(data: GltfData, skin_index: object, world: list, field: str) -> np.ndarray:
    """(joints, 4, 4): each joint's world matrix × its inverse bind matrix."""
    skin = data.item("skins", skin_index, field)
    where = f"skins[{skin_index}]"
    joints = skin.get("joints")
    if not isinstance(joints, list) or not joints:
        raise gltf_error(data.path, f"{where}.joints", f"expected a list of node indices, got {_repr(joints)}")
    for joint in joints:
        data.item("nodes", joint, f"{where}.joints")
    if "inverseBindMatrices" in skin:
        inverse = data.accessor(skin["inverseBindMatrices"], f"{where}.inverseBindMatrices")
        if inverse.shape[1] != 16 or len(inverse) < len(joints):
            raise gltf_error(data.path, f"{where}.inverseBindMatrices", f"expected {len(joints)} MAT4, got {inverse.shape[0]} of width {inverse.shape[1]}")
        inverse = inverse[: len(joints)].reshape(-1, 4, 4).transpose(0, 2, 1)  # column-major in the file
    else:
        inverse = np.broadcast_to(np.eye(4), (len(joints), 4, 4))
    hidden = np.zeros((4, 4))  # a joint under a zero-scaled node collapses its vertices
    joint_world = np.stack([world[joint] if world[joint] is not None else hidden for joint in joints])
    matrices = joint_world @ inverse
    if not np.isfinite(matrices).all():
        raise gltf_error(data.path, f"{where}.inverseBindMatrices", "the joint matrices are not finite")
    return matrices


def pose(matrices: np.ndarray, joints: np.ndarray, weights: np.ndarray, positions: np.ndarray,
         normals: np.ndarray | None, where: str, data: GltfData) -> tuple[np.ndarray, np.ndarray | None]:
    """Linear blend skinning: p' = Σ w_k · M[j_k] · p; normals by the same blended matrix
    (as three.js does), then normalized. Weights are normalized; vertices whose weights sum
    to zero stay where they are."""
    if joints.min(initial=0) < 0 or joints.max(initial=0) >= len(matrices):
        raise gltf_error(data.path, where, f"a JOINTS value {int(joints.max())} is beyond the skin's {len(matrices)} joints")
    if not np.isfinite(weights).all():
        raise gltf_error(data.path, where, "WEIGHTS values must be finite")
    total = weights.sum(axis=1, keepdims=True)
    unweighted = (total[:, 0] <= 0.0)
    weights = np.where(total > 0.0, weights / np.where(total > 0.0, total, 1.0), 0.0)
    out_positions = np.empty_like(positions)
    out_normals = None if normals is None else np.empty_like(normals)
    for start in range(0, len(positions), _SKIN_CHUNK):
        part = slice(start, start + _SKIN_CHUNK)
        blended = np.einsum("nk,nkij->nij", weights[part], matrices[joints[part]])  # (n, 4, 4)
        keep = unweighted[part]
        blended[keep] = np.eye(4)
        out_positions[part] = np.einsum("nij,nj->ni", blended[:, :3, :3], positions[part]) + blended[:, :3, 3]
        if normals is not None:
            turned = np.einsum("nij,nj->ni", blended[:, :3, :3], normals[part])
            length = np.linalg.norm(turned, axis=1, keepdims=True)
            out_normals[part] = np.where(length > 0.0, turned / np.where(length > 0.0, length, 1.0), normals[part])
    return out_positions, out_normals


def _repr(value: object) -> str:
    import reprlib

    return reprlib.repr(value)
