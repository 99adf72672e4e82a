"""Uniform buffers, kept between frames and rewritten only when their bytes change."""

from __future__ import annotations

import wgpu

from .caches import LruCache


def uniform_buffer(device, cache: LruCache, key: tuple, payload: bytes) -> object:
    """The uniform buffer cached under `key` (made on first use), holding `payload`.

    Queue writes are ordered with submissions, so a buffer holds the last bytes written
    to it for every later frame: writing the same bytes again (a re-render, an object a
    camera move did not change) is skipped. The cache keeps [buffer, bytes last written]."""
    cached = cache.get(key)
    if cached is None:
        buffer = device.create_buffer(size=len(payload), usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)
        cached = cache.put(key, [buffer, None])
    if payload != cached[1]:
        device.queue.write_buffer(cached[0], 0, payload)
        cached[1] = payload
    return cached[0]
