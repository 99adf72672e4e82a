"""A glTF file's animations evaluated at a chosen time (glTF 2.0 §3.11 and Appendix C).

Each channel targets one node's translation, rotation, scale or morph-target weights; its
sampler interpolates keyframes. STEP holds the keyframe at or before the time; LINEAR
interpolates, rotations by spherical linear interpolation the short way round; CUBICSPLINE
is the cubic Hermite spline through the keyframes with the file's in- and out-tangents,
scaled by the keyframe interval (Appendix C); rotations are normalized afterwards. Before
its first keyframe a sampler gives its first value, after its last its last (the spec's
clamp). Times are seconds. An animation's time range starts at 0 and ends at its last
keyframe, as f3d (VTK's glTF importer) plays it.

The result is the file's nodes with the animated properties replaced (`animated_nodes`):
world matrices, skins (joints are nodes) and morph weights are then computed from them as
for a file without animation (nodes.py, primitives.py).
"""

from __future__ import annotations

import numpy as np

from .document import GltfData, gltf_error

INTERPOLATIONS = ("STEP", "LINEAR", "CUBICSPLINE")
_PATH_WIDTHS = {"translation": 3, "rotation": 4, "scale": 3, "weights": 1}
ALL = "all"  # every animation at once (f3d 2's --animation-index -1)


def interpolate(times: np.ndarray, values: np.ndarray, time: float, interpolation: str, *, rotation: bool = False) -> np.ndarray:
    """The sampler's value at `time`. times: (k,) non-decreasing; values: (k, w) keyframes for
    STEP and LINEAR, (k, 3, w) in-tangent, value, out-tangent for CUBICSPLINE."""
    points = values[:, 1] if interpolation == "CUBICSPLINE" else values
    if time <= times[0]:
        return _unit(points[0]) if rotation else points[0].copy()
    if time >= times[-1]:
        return _unit(points[-1]) if rotation else points[-1].copy()
    key = int(np.searchsorted(times, time, side="right")) - 1  # times[key] <= time < times[key + 1]
    if interpolation == "STEP":
        return _unit(points[key]) if rotation else points[key].copy()
    interval = float(times[key + 1] - times[key])  # > 0: times[key] <= time < times[key + 1]
    s = (time - float(times[key])) / interval
    if interpolation == "LINEAR":
        if rotation:
            return _slerp(points[key], points[key + 1], s)
        return (1.0 - s) * points[key] + s * points[key + 1]
    s2, s3 = s * s, s * s * s  # Appendix C: the Hermite basis, tangents scaled by the interval
    value = ((2 * s3 - 3 * s2 + 1) * points[key] + (s3 - 2 * s2 + s) * interval * values[key, 2]
             + (-2 * s3 + 3 * s2) * points[key + 1] + (s3 - s2) * interval * values[key + 1, 0])
    return _unit(value) if rotation else value


def _unit(quaternion: np.ndarray) -> np.ndarray:
    length = float(np.linalg.norm(quaternion))
    return quaternion / length if length > 0.0 else np.array([0.0, 0.0, 0.0, 1.0])


def _slerp(start: np.ndarray, end: np.ndarray, s: float) -> np.ndarray:
    """Spherical linear interpolation the short way round (Appendix C)."""
    start, end = _unit(start), _unit(end)
    dot = float(np.dot(start, end))
    if dot < 0.0:  # q and −q are the same rotation: take the shorter arc
        end, dot = -end, -dot
    if dot > 0.9995:  # nearly parallel: sin(angle) ~ 0, the chord is the arc
        return _unit((1.0 - s) * start + s * end)
    angle = float(np.arccos(dot))
    return _unit((np.sin((1.0 - s) * angle) * start + np.sin(s * angle) * end) / np.sin(angle))


# --------------------------------------------------------------------------- the file's animations


def chosen_animations(data: GltfData, index: int | str) -> list[int]:
    """The animations `index` names (an index, or "all"), checked against the file."""
    count = len(data.items("animations"))
    if index == ALL:
        return list(range(count))
    if count == 0:
        raise gltf_error(data.path, "animations", f"the file has no animations (animation index {index} asked for)")
    if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < count:
        raise gltf_error(data.path, "animations", f"animation index {index!r} is out of range: the file has {count} "
                         f"animation{'s' if count != 1 else ''} (0..{count - 1}, or all)")
    return [index]


def animation_duration(data: GltfData, indices: list[int]) -> float:
    """The end of the animations' time range (their last keyframe); they start at 0."""
    end = 0.0
    for channel in _channels(data, indices):
        end = max(end, float(channel[2][-1]))
    return end


def animated_nodes(data: GltfData, indices: list[int], time: float) -> list:
    """The file's nodes with what the animations set at `time` in place of their own
    translation, rotation, scale and weights (copies; the document is not changed)."""
    nodes = list(data.items("nodes"))
    changed: dict[int, dict] = {}
    for node, path, times, values, interpolation in _channels(data, indices):
        value = interpolate(times, values, time, interpolation, rotation=path == "rotation")
        if node not in changed:
            changed[node] = _trs(nodes[node]) if isinstance(nodes[node], dict) else {}
        changed[node][path] = [float(v) for v in value.reshape(-1)]
    for node, properties in changed.items():
        nodes[node] = properties
    return nodes


def posed_nodes(data: GltfData, time: float | None, index: int | str = 0) -> list | None:
    """The nodes as animation `index` (or "all") poses them at `time`; None (the file's own
    nodes) when no time is asked for, or when the file has no animations (said in a note)."""
    if time is None:
        return None
    if not data.items("animations"):
        data.notes.append(f"{data.path.name}: the file has no animations; the animation time {time:g} s is ignored")
        return None
    return animated_nodes(data, chosen_animations(data, index), time)


def _trs(node: dict) -> dict:
    """A copy of the node with its `matrix`, if any, as translation, rotation and scale:
    an animated node must not have one (§3.11), and three.js decomposes it as here."""
    node = dict(node)
    if "matrix" not in node:
        return node
    try:
        matrix = np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    except (TypeError, ValueError):
        return node  # kept: nodes.py reports the bad matrix, as for the file unanimated
    if not (np.abs(matrix) <= 1e15).all():  # NaN, inf or beyond the limit: as above
        return node
    del node["matrix"]
    linear = matrix[:3, :3]
    scale = np.linalg.norm(linear, axis=0)
    if np.linalg.det(linear) < 0:
        scale[0] = -scale[0]
    turn = linear / np.where(scale == 0.0, 1.0, scale)
    node.update(translation=matrix[:3, 3].tolist(), rotation=_quaternion(turn).tolist(), scale=scale.tolist())
    return node


def _quaternion(turn: np.ndarray) -> np.ndarray:
    """(x, y, z, w) of a rotation matrix (Shepperd's method: the largest diagonal term first)."""
    trace = float(np.trace(turn))
    options = [trace, turn[0, 0], turn[1, 1], turn[2, 2]]
    largest = int(np.argmax(options))
    if largest == 0:
        w = np.sqrt(max(1.0 + trace, 0.0)) / 2.0
        q = [(turn[2, 1] - turn[1, 2]) / (4 * w), (turn[0, 2] - turn[2, 0]) / (4 * w), (turn[1, 0] - turn[0, 1]) / (4 * w), w]
    else:
        i = largest - 1
        j, k = (i + 1) % 3, (i + 2) % 3
        r = np.sqrt(max(1.0 + turn[i, i] - turn[j, j] - turn[k, k], 0.0))
        q = [0.0, 0.0, 0.0, (turn[k, j] - turn[j, k]) / (2 * r)]
        q[i], q[j], q[k] = r / 2.0, (turn[j, i] + turn[i, j]) / (2 * r), (turn[k, i] + turn[i, k]) / (2 * r)
    return _unit(np.array(q, dtype=np.float64))


def _channels(data: GltfData, indices: list[int]):
    """(node, path, times, values, interpolation) of every usable channel of the animations,
    each sampler checked (a channel without a node, or of a path this reader does not
    animate, e.g. KHR_animation_pointer's, is skipped)."""
    nodes = data.items("nodes")
    for index in indices:
        animation = data.item("animations", index, "animation index")
        where = f"animations[{index}]"
        samplers, channels = animation.get("samplers", []), animation.get("channels", [])
        if not isinstance(samplers, list) or not isinstance(channels, list):
            raise gltf_error(data.path, where, "expected lists of samplers and channels")
        for number, channel in enumerate(channels):
            target = channel.get("target") if isinstance(channel, dict) else None
            if not isinstance(target, dict) or "node" not in target or target.get("path") not in _PATH_WIDTHS:
                continue
            node = target["node"]
            data.item("nodes", node, f"{where}.channels[{number}].target.node")
            sampler_index = channel.get("sampler")
            if not isinstance(sampler_index, int) or isinstance(sampler_index, bool) or not 0 <= sampler_index < len(samplers):
                raise gltf_error(data.path, f"{where}.channels[{number}].sampler",
                                 f"{sampler_index!r} is not an index into the animation's {len(samplers)} samplers")
            times, values, interpolation = _sampler(data, samplers[sampler_index], target["path"], f"{where}.samplers[{sampler_index}]")
            if target["path"] == "weights" or isinstance(nodes[node], dict):
                yield node, target["path"], times, values, interpolation


def _sampler(data: GltfData, sampler: object, path: str, where: str) -> tuple[np.ndarray, np.ndarray, str]:
    if not isinstance(sampler, dict):
        raise gltf_error(data.path, where, f"expected an object, got {type(sampler).__name__}")
    interpolation = sampler.get("interpolation", "LINEAR")
    if interpolation not in INTERPOLATIONS:
        raise gltf_error(data.path, f"{where}.interpolation", f"{interpolation!r}; expected one of {', '.join(INTERPOLATIONS)}")
    times = data.accessor(sampler.get("input"), f"{where}.input")
    if times.shape[1] != 1 or times.dtype.kind != "f":
        raise gltf_error(data.path, f"{where}.input", "expected float scalars (keyframe times in seconds)")
    times = times[:, 0]
    if not np.isfinite(times).all() or (np.diff(times) < 0).any():
        raise gltf_error(data.path, f"{where}.input", "keyframe times must be finite and increasing")
    values = data.accessor(sampler.get("output"), f"{where}.output")
    width = values.shape[1]
    if values.dtype.kind != "f" or not np.isfinite(values).all():
        raise gltf_error(data.path, f"{where}.output", "expected finite floats (or normalized integers)")
    if width != _PATH_WIDTHS[path]:
        raise gltf_error(data.path, f"{where}.output", f"{path} needs elements of width {_PATH_WIDTHS[path]}, got {width}")
    per_key = 3 if interpolation == "CUBICSPLINE" else 1  # in-tangent, value, out-tangent
    if path == "weights":  # one value per morph target and keyframe
        if len(values) % (len(times) * per_key):
            raise gltf_error(data.path, f"{where}.output", f"{len(values)} weights are not a whole number per keyframe ({len(times)} keyframes)")
        values = values.reshape(len(times), len(values) // (len(times) * per_key) * per_key)
    elif len(values) != len(times) * per_key:
        raise gltf_error(data.path, f"{where}.output", f"expected {len(times) * per_key} elements for {len(times)} {interpolation} keyframes, got {len(values)}")
    values = values.reshape(len(times), per_key, -1) if per_key == 3 else values.reshape(len(times), -1)
    return times, values, interpolation
