"""Bind groups, cached by the objects they bind."""

from __future__ import annotations

import wgpu

from .caches import LruCache


def cached_bind_group(device, cache: LruCache, layout, resources: tuple) -> object:
    """A bind group, cached in `cache`: the LRU cache of whoever owns the resources (the
    renderer for uniform buffers, a GpuMesh for its buffers, a GpuTexture for its view).
    The key holds the bound objects themselves (identity-hashed), not their id()s: an
    evicted buffer's id may be reused by a new one, which must not find the old group."""
    key = (layout,) + tuple(resources)
    group = cache.get(key)
    if group is None:
        entries = []
        for binding, resource in enumerate(resources):
            if isinstance(resource, wgpu.GPUBuffer):
                resource = {"buffer": resource, "offset": 0, "size": resource.size}
            entries.append({"binding": binding, "resource": resource})
        group = device.create_bind_group(layout=layout, entries=entries)
        cache.put(key, group)
    return group
