"""files.text_line_blocks: a text file in blocks of whole lines, whatever the sizes of the
reads and of the blocks, refused at a NUL byte with its offset."""

from __future__ import annotations

import numpy as np
import pytest

from wgpu_shading.assets import files
from wgpu_shading.assets.files import text_line_blocks
from wgpu_shading.errors import MeshError

TEXTS = {
    "lines": b"".join(b"v %d 0 0\n" % i for i in range(500)),
    "no final newline": b"v 0 0 0\nf 1 2 3",
    "CR LF": b"v 0 0 0\r\nv 1 0 0\r\n" * 50,
    "classic Mac (no newline at all)": b"v 0 0 0\rv 1 0 0\rf 1 2 3\r" * 200,
    "a line longer than a block": b"v 0 0 0\n# " + b"x" * 3000 + b"\nv 1 2 3\n",
    "empty": b"",
}


@pytest.mark.parametrize("text", TEXTS.values(), ids=TEXTS.keys())
@pytest.mark.parametrize("chunk", [16, 1000, 1 << 24])
def test_blocks_are_the_file_in_whole_lines(tmp_path, monkeypatch, text, chunk):
    path = tmp_path / "text.obj"
    path.write_bytes(text)
    monkeypatch.setattr(files, "TEXT_CHUNK", chunk)
    longest = max(len(line) + 1 for line in text.split(b"\n"))
    for block_bytes in (1, 2, 40, 999, 1 << 24):
        blocks = list(text_line_blocks(path, "text", MeshError, block_bytes))
        assert b"".join(blocks) == text
        assert all(block.endswith(b"\n") for block in blocks[:-1])
        assert all(0 < len(block) <= max(block_bytes, longest) for block in blocks)


def test_a_nul_byte_is_refused_with_its_offset(tmp_path, monkeypatch):
    path = tmp_path / "text.obj"
    path.write_bytes(b"v 0 0 0\n" * 100 + b"\0")
    monkeypatch.setattr(files, "TEXT_CHUNK", 64)
    with pytest.raises(MeshError, match=r"text: not a text file \(a NUL byte at offset 800\)"):
        list(text_line_blocks(path, "text", MeshError, 16))


def test_utf16_text_is_one_block(tmp_path):
    path = tmp_path / "text.obj"
    text = "v 0 0 0\nf 1 1 1\n".encode("utf-16")
    path.write_bytes(text)
    assert list(text_line_blocks(path, "text", MeshError, 4)) == [text]


def test_a_line_longer_than_told_stops_the_reading_at_once(tmp_path, monkeypatch):
    """longest_line: a reader whose lines are short is not made to hold a line of a whole
    file (ASCII STL, stl_ascii.py): LongLine once the line goes on past a chunk beyond it."""
    path = tmp_path / "text.stl"
    path.write_bytes(b"solid x\n" + b"1 " * 50_000)  # 100 KB without a newline
    monkeypatch.setattr(files, "TEXT_CHUNK", 1 << 12)
    reads = []
    real_open = open

    def counting_open(*args, **kwargs):
        handle = real_open(*args, **kwargs)
        read = handle.read
        handle_read = lambda size=-1: reads.append(size) or read(size)  # noqa: E731
        return type("Counted", (), {"read": staticmethod(handle_read), "__enter__": lambda self: self,
                                    "__exit__": lambda self, *exc: handle.close()})()

    monkeypatch.setattr(files, "open", counting_open, raising=False)
    with pytest.raises(files.LongLine):
        list(text_line_blocks(path, "text", MeshError, 1 << 10, longest_line=1 << 13))
    assert len(reads) < 8  # a few chunks of 4 KiB, not the 25 of the whole line
    assert list(text_line_blocks(path, "text", MeshError, 1 << 10))[-1].startswith(b"1 1 ")  # without: one block


def test_block_lines_are_the_blocks_split_lines_decoded_when_asked():
    """BlockLines gives the strings `data.decode("utf-8", errors="replace").split("\\n")`
    gives (the OBJ reader's lines before), line by line, sliced, as sub-ranges and as lines
    taken out of order's way (`take`), over random blocks of CR, LF, bytes beyond ASCII and
    broken UTF-8; `text` is their bytes joined by newlines."""
    import random

    from wgpu_shading.assets.mesh_formats.line_sections import BlockLines

    rng = random.Random(5)
    pieces = [b"v 1", b"a", b"\n", b"\n", b"\r", b" ", b"\xe2\x82", b"\xac", b"\xff", b"\xc3\xa9"]
    for _ in range(1500):
        data = b"".join(rng.choice(pieces) for _ in range(rng.randint(1, 12)))
        ends = [index + 1 for index, byte in enumerate(data) if byte == 10]
        starts = np.array([0] + [end for end in ends if end < len(data)])
        expected = data.decode("utf-8", errors="replace").split("\n")[: len(starts)]
        lines = BlockLines(data, starts)
        assert len(lines) == len(expected) and list(lines) == expected
        assert [lines[k] for k in range(len(lines))] == expected and lines[-1] == expected[-1]
        first = rng.randrange(len(expected))
        stop = rng.randint(first + 1, len(expected))
        assert lines[first:stop] == expected[first:stop]
        assert list(lines.sub(first, stop)) == expected[first:stop]
        assert lines.text(first, stop).decode("utf-8", errors="replace") == "\n".join(expected[first:stop])
        chosen = np.array(sorted(rng.sample(range(len(expected)), rng.randint(1, len(expected)))))
        assert list(lines.take(chosen)) == [expected[k] for k in chosen]
        assert list(lines.sub(first, stop).take(np.array([0]))) == [expected[first]]
