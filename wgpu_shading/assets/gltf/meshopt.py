"""EXT_meshopt_compression: buffer views stored compressed by meshoptimizer's codecs.

https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Vendor/EXT_meshopt_compression
A compressed view names its own buffer, range, element `count` and `byteStride`, a `mode`
(ATTRIBUTES: vertex codec; TRIANGLES: index codec; INDICES: index sequence codec) and an
optional `filter` (OCTAHEDRAL, QUATERNION, EXPONENTIAL) undone after decoding. The decoders
are those of meshoptimizer, already a dependency (render/gpu/vertex_order.py); the decoded
size (count × byteStride) is checked against the view's byteLength and the buffer limit
before anything is allocated. The view's own buffer may be a fallback without data.
"""

from __future__ import annotations

import numpy as np

EXTENSION = "EXT_meshopt_compression"
_MODES = ("ATTRIBUTES", "TRIANGLES", "INDICES")
_FILTER_STRIDES = {"OCTAHEDRAL": "4 or 8", "QUATERNION": "8", "EXPONENTIAL": "a multiple of 4", "NONE": "any"}
_FILTERS = {"NONE": None, "OCTAHEDRAL": "decode_filter_oct", "QUATERNION": "decode_filter_quat", "EXPONENTIAL": "decode_filter_exp"}


def decode_view(document, extension: object, view_length: int, where: str) -> bytes:
    """The decoded bytes of a compressed view (`view_length` of them, as the view declares).

    `document` (document.py's GltfData) reads the compressed bytes (`buffer_range`, ranges
    checked) and checked integers (`integer`), and makes the error naming the file and field
    (`error`)."""
    import meshoptimizer

    field = f"{where}.extensions.{EXTENSION}"
    if not isinstance(extension, dict):
        raise document.error(field, "expected an object with buffer, byteLength, byteStride, count and mode")
    count = document.integer(extension.get("count"), f"{field}.count", 1)
    stride = document.integer(extension.get("byteStride"), f"{field}.byteStride", 1, 256)
    mode, name = extension.get("mode"), extension.get("filter", "NONE")
    if mode not in _MODES:
        raise document.error(f"{field}.mode", f"{mode!r}: expected one of {', '.join(_MODES)}")
    if name not in _FILTERS:
        raise document.error(f"{field}.filter", f"{name!r}: expected one of {', '.join(_FILTERS)}")
    if mode == "ATTRIBUTES" and stride % 4:
        raise document.error(f"{field}.byteStride", f"{stride}: ATTRIBUTES need a multiple of 4")
    if mode != "ATTRIBUTES" and (stride not in (2, 4) or name != "NONE"):
        raise document.error(field, f"{mode} need a byteStride of 2 or 4 and no filter")
    # meshoptimizer's C filters assert these strides: checked here, never reached wrong.
    if (name == "EXPONENTIAL" and stride % 4) or (name == "QUATERNION" and stride != 8) or (name == "OCTAHEDRAL" and stride not in (4, 8)):
        raise document.error(f"{field}.byteStride", f"{stride}: the {name} filter needs {_FILTER_STRIDES[name]}")
    if mode == "TRIANGLES" and count % 3:
        raise document.error(f"{field}.count", f"{count} indices are not whole triangles")
    if count * stride != view_length:
        raise document.error(field, f"{count} elements of {stride} bytes decode to {count * stride} bytes; the bufferView declares {view_length}")
    compressed = document.buffer_range(
        extension.get("buffer"),
        document.integer(extension.get("byteOffset", 0), f"{field}.byteOffset"),
        document.integer(extension.get("byteLength"), f"{field}.byteLength", 1),
        field,
    )
    try:
        if mode == "ATTRIBUTES":
            decoded = meshoptimizer.decode_vertex_buffer(count, stride, compressed, dtype=np.dtype((np.void, stride)))
            if _FILTERS[name] is not None:
                decoded = getattr(meshoptimizer, _FILTERS[name])(decoded, count, stride)
        else:
            decode = meshoptimizer.decode_index_buffer if mode == "TRIANGLES" else meshoptimizer.decode_index_sequence
            # The binding decodes into a uint32 array whatever the index size: the indices
            # are its first count × stride bytes.
            decoded = decode(count, stride, compressed).view(np.uint8)[: count * stride]
    except (RuntimeError, ValueError) as error:
        raise document.error(field, f"cannot be decoded ({error})") from None
    data = np.ascontiguousarray(decoded).tobytes()
    if len(data) != view_length:
        raise document.error(field, f"decoded to {len(data)} bytes, not the {view_length} declared")
    return data
