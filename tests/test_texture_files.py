"""Texture image files (assets/textures.py): odd pixel formats read as meant, sizes refused from
the header before decoding (at most 16384 pixels a side, and the adapter's own limit),
unreadable files named in one line, and no file left open."""

from __future__ import annotations

import gc
import os
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cli_errors import one_line_error, run_cli
from wgpu_shading import Renderer, SceneError, load_scene
from wgpu_shading.assets.textures import load_texture
from wgpu_shading.scene import Material, Scene, SceneObject, Texture, builtin


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def test_a_one_bit_png_texture_is_white_not_black(tmp_path, renderer):
    Image.new("1", (8, 8), 1).save(tmp_path / "white.png")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(
        '[output]\nsize = [32, 32]\n[ambient]\ncolor = [1, 1, 1]\n'
        '[[objects]]\nmesh = "builtin:plane"\nmaterial = { texture = "white.png" }\n'
    )
    scene = load_scene(scene_file)
    assert scene.objects[0].material.texture.pixels.min() == 255
    image = renderer.render(scene)
    assert image[16, 16, :3].tolist() == [255, 255, 255]  # ambient 1 × material 1 × texel 1


def test_a_texture_wider_than_the_limit_is_refused_before_decoding(tmp_path, capsys):
    Image.new("RGB", (16385, 1)).save(tmp_path / "wide.png")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('[[objects]]\nmesh = "builtin:plane"\nmaterial = { texture = "wide.png" }\n')
    code, err = run_cli(capsys, "render", str(scene_file), "-o", str(tmp_path / "o.png"))
    assert code == 2 and "wide.png" in err and "16385×1 pixels; at most 16384" in err


def test_a_texture_header_claiming_a_huge_image_is_refused_before_decoding(tmp_path):
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", 30000, 30000, 8, 2, 0, 0, 0)  # 30000² RGB, and no pixel data at all
    path = _write(tmp_path / "bomb.png", b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IEND", b""))
    with pytest.raises(SceneError, match=r"bomb.png': too large .*at most 16384 pixels per side"):
        load_texture(path)


def test_a_texture_beyond_the_adapters_limit_is_a_scene_error(renderer):
    limit = renderer.device.limits["max-texture-dimension-2d"]
    texture = Texture(np.zeros((1, 8, 3), np.uint8), name="wide")
    object.__setattr__(texture, "pixels", np.zeros((1, limit + 1, 4), np.uint8))  # past the scene's own check
    scene = Scene(objects=(SceneObject(builtin("builtin:plane"), Material(texture=texture)),), size=(8, 8))
    with pytest.raises(SceneError, match=f"texture 'wide': {limit + 1}×1 pixels exceeds this adapter's limit of {limit}"):
        Renderer(device=renderer.device).render(scene)


def test_a_failed_texture_read_leaves_no_open_file(tmp_path):
    """imageio's plugin search left files open (in reference cycles) when none could read one."""
    bad = _write(tmp_path / "bad.png", b"not an image at all")
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('[[objects]]\nmesh = "builtin:plane"\nmaterial = { texture = "bad.png" }\n')
    def open_on_bad_file() -> int:
        count = 0
        for fd in os.listdir("/proc/self/fd"):
            try:
                count += os.readlink(f"/proc/self/fd/{fd}") == str(bad)
            except OSError:  # closed meanwhile (another thread's file)
                pass
        return count

    gc.collect()
    gc.disable()  # cycles are not collected: what is open now stays open
    try:
        for _ in range(10):
            with pytest.raises(SceneError, match="bad.png"):
                load_scene(scene_file)
        still_open = open_on_bad_file()
    finally:
        gc.enable()
    assert still_open == 0
    assert bad.exists()


def test_an_unreadable_texture_message_has_no_memory_address(tmp_path, capsys):
    (tmp_path / "zero.png").write_bytes(b"")
    path = tmp_path / "t.toml"
    path.write_text('[[objects]]\nmesh = "builtin:cube"\nmaterial = { texture = "zero.png" }\n')
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = one_line_error(code, err, "zero.png", "not an image Pillow can read")
    assert "0x" not in line and "BytesIO" not in line, line
