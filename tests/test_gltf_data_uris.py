"""Large base64 data: URIs of an embedded glTF, decoded from the file's bytes
(assets/gltf/data_uris.py): the same meshes as the same document with its buffer in a .bin
file beside it (a path that decodes nothing), whatever the JSON around the URI looks like,
and without the copies of the text that json.loads made (5.0× the mesh's arrays at 10M
triangles; docs/reliability.md)."""

from __future__ import annotations

import base64
import json
import tracemalloc

import numpy as np
import pytest

from gltf_builder import UINT, Doc
from wgpu_shading import MeshError, load_mesh
from wgpu_shading.assets.gltf.data_uris import MIN_DECODED_TEXT, decode_data_uris
from wgpu_shading.assets.gltf.document import GltfData


def _grid_doc(side: int = 80) -> tuple[Doc, list, list]:
    """A wavy grid of side² vertices (~77 KB of positions at 80: its base64 is over
    MIN_DECODED_TEXT), as a document's meshes and nodes."""
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    positions = np.stack([u, v, 0.1 * np.sin(7 * u) * np.cos(5 * v)], -1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(side - 1), np.arange(side - 1), indexing="ij")
    a = (i * side + j).reshape(-1)
    faces = np.stack([a, a + 1, a + side + 1, a, a + side + 1, a + side], -1).reshape(-1)
    doc = Doc()
    position = doc.accessor(positions, min=positions.min(0).tolist(), max=positions.max(0).tolist())
    indices = doc.accessor(faces.astype(np.uint32), UINT)
    return doc, [[{"attributes": {"POSITION": position}, "indices": indices}]], [{"mesh": 0}]


def _embedded_text(tmp_path, side: int = 80) -> tuple[str, str, object]:
    """(the embedded glTF's JSON text, its URI `@URI@`, its base64 payload, the mesh read
    from its .bin twin)."""
    doc, meshes, nodes = _grid_doc(side)
    (tmp_path / "grid.bin").write_bytes(bytes(doc.blob))
    twin = load_mesh(doc.write(tmp_path / "twin.gltf", meshes, nodes, uri="grid.bin"))
    payload = base64.b64encode(bytes(doc.blob)).decode()
    assert (len(payload) > MIN_DECODED_TEXT) == (side >= 80)
    text = json.dumps(json.loads((tmp_path / "twin.gltf").read_text()) | {"buffers": [{"byteLength": len(doc.blob), "uri": "@URI@"}]})
    return text, payload, twin


def _decoded(path) -> dict:
    """The data: URIs decoded before json.loads (marker → bytes)."""
    return decode_data_uris(path.read_bytes())[1]


def _same_mesh(mesh, twin) -> None:
    np.testing.assert_array_equal(mesh.positions, twin.positions)
    np.testing.assert_array_equal(mesh.indices, twin.indices)
    np.testing.assert_array_equal(mesh.normals, twin.normals)


@pytest.mark.parametrize("uri, separator", [
    ("data:application/octet-stream;base64,{}", ": "),  # what Blender, three.js and json.dumps write
    ("data:application/gltf-buffer;base64,{}", ":"),  # the other media type the spec names, no space
    ("data:;base64,{}", " :\n  "),  # no media type; whitespace around the colon
])
def test_an_embedded_buffer_gives_the_meshes_of_its_bin_twin(tmp_path, uri, separator):
    text, payload, twin = _embedded_text(tmp_path)
    text = text.replace('"uri": "@URI@"', f'"uri"{separator}"{uri.format(payload)}"')
    (tmp_path / "embedded.gltf").write_text(text)
    _same_mesh(load_mesh(tmp_path / "embedded.gltf"), twin)
    assert [marker.split(",")[0] for marker in _decoded(tmp_path / "embedded.gltf")] == [uri.split(",")[0]]


@pytest.mark.parametrize("how", ["escaped slashes", "line breaks", "small"])
def test_base64_text_the_strict_decoder_refuses_is_read_as_before(tmp_path, how):
    # PHP's json_encode writes `\/`; MIME-style base64 breaks lines (a JSON `\n` escape);
    # both are decoded leniently after json.loads, as every data: URI was before; so is a
    # small one.
    text, payload, twin = _embedded_text(tmp_path, side=10 if how == "small" else 80)
    if how == "escaped slashes":
        assert "/" in payload
        payload = payload.replace("/", "\\/")
    elif how == "line breaks":
        payload = "\\n".join(payload[i : i + 76] for i in range(0, len(payload), 76))
    text = text.replace('"@URI@"', f'"data:application/octet-stream;base64,{payload}"')
    (tmp_path / "embedded.gltf").write_text(text)
    _same_mesh(load_mesh(tmp_path / "embedded.gltf"), twin)
    assert _decoded(tmp_path / "embedded.gltf") == {}


def test_a_uri_key_inside_a_string_is_not_taken_for_one(tmp_path):
    # `\"uri\": \"data:…` inside a name is text, and so is the key `a"uri` (written
    # `"a\"uri"`) of a large data: URI: both stay as they are, every character, and the
    # buffer still comes from its own URI.
    text, payload, twin = _embedded_text(tmp_path)
    big = f"data:application/octet-stream;base64,{payload}"
    note = f'\\"uri\\": \\"{big}\\"'
    text = text.replace('"@URI@"', f'"{big}"')
    text = text.replace('"asset": {', f'"asset": {{"extras": {{"note": "{note}", "a\\"uri": "{big}"}}, ', 1)
    (tmp_path / "embedded.gltf").write_text(text)
    _same_mesh(load_mesh(tmp_path / "embedded.gltf"), twin)
    extras = GltfData(tmp_path / "embedded.gltf").document["asset"]["extras"]
    assert extras == {"note": f'"uri": "{big}"', 'a"uri': big}
    assert len(_decoded(tmp_path / "embedded.gltf")) == 1


def test_base64_that_cannot_be_decoded_is_the_same_error(tmp_path):
    text, payload, _ = _embedded_text(tmp_path)
    (tmp_path / "bad.gltf").write_text(text.replace('"@URI@"', f'"data:application/octet-stream;base64,{payload[:-2]}A"'))
    with pytest.raises(MeshError, match=r"buffers\[0\]\.uri: a data: URI that cannot be decoded"):
        load_mesh(tmp_path / "bad.gltf")


def test_an_unterminated_uri_is_the_json_error(tmp_path):
    text, payload, _ = _embedded_text(tmp_path)
    cut = text.replace('"@URI@"', f'"data:application/octet-stream;base64,{payload}"').split(payload)[0] + payload
    (tmp_path / "cut.gltf").write_text(cut)
    with pytest.raises(MeshError, match="not a valid glTF file"):
        load_mesh(tmp_path / "cut.gltf")


def test_decoding_an_embedded_buffer_holds_the_text_and_the_bytes_once(tmp_path):
    # 4 MB of positions: the file's text (4/3) and the decoded bytes (1) at once, 2.33×;
    # through json.loads it was the text three times over and the bytes (5×).
    doc, meshes, nodes = _grid_doc(side=580)
    path = doc.write(tmp_path / "big.gltf", meshes, nodes)
    tracemalloc.start()
    try:
        data = GltfData(path)
        data.accessor(0, "test", as_stored=True)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2.5 * len(doc.blob), peak / len(doc.blob)
