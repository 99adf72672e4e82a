"""Large base64 data: URIs of a glTF's JSON, decoded straight from the file's bytes.

An embedded glTF (the sample models' `glTF-Embedded` variants; Blender's "glTF Embedded"
export) carries its buffers as base64 text, 4/3 of their size. Parsed by json.loads, each
became a str as large as the text, then a second copy when its header was cut off, then
the decoded bytes: a 10M-triangle embedded glTF peaked at 5.0× the mesh's arrays to load,
where its GLB twin takes 2.1× (docs/reliability.md, "Peak memory of a large mesh load").

Here each `"uri": "data:…;base64,…"` value of at least MIN_DECODED_TEXT characters is
decoded from a view of the file's bytes (no copy) and replaced in the JSON by a short
marker, which GltfData.uri_bytes looks up. Only text that Python's strict base64 decoder
accepts is taken this way (the alphabet and its padding, nothing else: no JSON escape such
as `\\/`, no line breaks); strict and lenient decoding agree on it. Anything else is left
in the JSON and decoded as before, so which bytes a file gives never depends on this path.
"""

from __future__ import annotations

import binascii
import re
import secrets

MIN_DECODED_TEXT = 1 << 16  # characters: smaller URIs cost little through json.loads
# The key `uri`, then a base64 data: URI whose media type has no quote, comma or escape and
# whose text starts with MIN_DECODED_TEXT base64 characters: the regex engine passes over
# small URIs itself (from the literal `"uri"` on, which it finds at memchr's speed), so a
# file of millions of them costs no Python loop here.
_BASE64_URI = re.compile(rb'"uri"\s*:\s*"(data:[^",\\]*;base64),(?=[A-Za-z0-9+/]{%d})' % MIN_DECODED_TEXT)


def decode_data_uris(raw: bytes, decode: bool = True) -> tuple[bytes, dict[str, bytes | None]]:
    """(the JSON with each large base64 data: URI replaced by a marker, marker → its bytes).
    decode=False: the markers map to None (a read of the JSON alone: punctual lights)."""
    pieces: list[bytes] = []
    decoded: dict[str, bytes | None] = {}
    token = secrets.token_hex(8)  # a marker cannot be a URI the file itself holds
    kept_from = 0
    with memoryview(raw) as view:
        position = 0
        while (match := _BASE64_URI.search(raw, position)) is not None:
            start = match.end()
            end = position = raw.find(b'"', start)
            if end < 0:
                break  # an unterminated string: json.loads names the error
            if raw[match.start() - 1 : match.start()] == b"\\":
                continue  # `\"uri\"`: text inside a string (where every quote is escaped), not a key
            try:
                header = match.group(1).decode("utf-8")
                data = binascii.a2b_base64(view[start:end], strict_mode=True) if decode else None
            except (UnicodeDecodeError, binascii.Error):
                continue  # left in the JSON: decoded (leniently) or refused as before
            marker = f"{header},#wgpu-shading-{token}-{len(decoded)}"
            pieces += [raw[kept_from : match.start(1)], marker.encode("utf-8")]
            decoded[marker] = data
            kept_from = end
    if not decoded:
        return raw, decoded
    pieces.append(raw[kept_from:])
    return b"".join(pieces), decoded
