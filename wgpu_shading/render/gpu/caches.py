"""Bounded caches: everything a Renderer keeps between frames is evicted least-recently-used.

A service that renders for hours with ever-changing feature sets, output sizes and meshes
must level off in memory. The limits (docs/reliability.md states them):

    pipelines        PIPELINE_CACHE_ENTRIES per renderer (~2 MB of compiled code each)
    render targets   TARGET_CACHE_ENTRIES sizes × formats (color, depth and readback)
    mesh uploads     MESH_CACHE_ENTRIES meshes and at most MESH_CACHE_BYTES of buffers
    texture uploads  TEXTURE_CACHE_ENTRIES uploads and at most TEXTURE_CACHE_BYTES, for
                     all of them: one cache, keyed (texture, stored format), so an image
                     stored in two formats is two entries under the same bound
    uniform buffers  UNIFORM_CACHE_ENTRIES (one per object index and layout size)
    bind groups      BIND_GROUP_CACHE_ENTRIES per owner
    shadow maps      SHADOW_MAP_CACHE_ENTRIES textures (map size × layer count; docs/shadows.md)
                     and at most MAX_SHADOW_MAP_BYTES (shadow_maps.py) besides the newest
    frame plans      FRAME_PLAN_ENTRIES scenes' prepared draws (frame_plans.py), only while
                     the caches above that they use are unchanged

Eviction only drops the cache's reference; wgpu releases the GPU object when the last
reference goes (a frame still in flight keeps its own). The caches are not thread-safe
by themselves: the Renderer mutates them under its lock.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict
from typing import Callable, Generic, Hashable, TypeVar

PIPELINE_CACHE_ENTRIES = 32
TARGET_CACHE_ENTRIES = 4
MESH_CACHE_ENTRIES = 64
MESH_CACHE_BYTES = 1 << 30  # 1 GiB
TEXTURE_CACHE_ENTRIES = 32
TEXTURE_CACHE_BYTES = 512 << 20  # 512 MiB
UNIFORM_CACHE_ENTRIES = 1024
BIND_GROUP_CACHE_ENTRIES = 256
SHADOW_MAP_CACHE_ENTRIES = 2  # a 2048² map is 16 MiB a layer
FRAME_PLAN_ENTRIES = 8

V = TypeVar("V")


class LruCache(Generic[V]):
    """A mapping that keeps at most `max_entries` values (and, with `size_of`, at most
    `max_bytes` in total), dropping the least recently used first. The newest entry is
    always kept, even when it alone exceeds `max_bytes`."""

    def __init__(self, max_entries: int, max_bytes: int | None = None, size_of: Callable[[V], int] | None = None):
        if max_entries < 1:
            raise ValueError(f"max_entries must be at least 1, got {max_entries}")
        self.max_entries = max_entries
        self.max_bytes = max_bytes
        self._size_of = size_of
        self._entries: OrderedDict[Hashable, V] = OrderedDict()
        self._sizes: dict[Hashable, int] = {}  # as measured when stored
        self._bytes = 0
        self.evictions = 0
        self.changes = 0  # entries put, replaced or dropped so far (frame_plans.py watches it)

    def __len__(self) -> int:
        return len(self._entries)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._entries

    @property
    def nbytes(self) -> int:
        return self._bytes

    def values(self) -> list[V]:
        return list(self._entries.values())

    def peek(self, key: Hashable) -> V | None:
        """The value, without making it the most recently used."""
        return self._entries.get(key)

    def get(self, key: Hashable) -> V | None:
        value = self._entries.get(key)
        if value is not None:
            self._entries.move_to_end(key)
        return value

    def put(self, key: Hashable, value: V) -> V:
        self.pop(key)
        self._entries[key] = value
        self.changes += 1
        if self._size_of is not None:
            self._sizes[key] = self._size_of(value)
            self._bytes += self._sizes[key]
        while len(self._entries) > 1 and (
            len(self._entries) > self.max_entries or (self.max_bytes is not None and self._bytes > self.max_bytes)
        ):
            oldest = next(iter(self._entries))
            self.pop(oldest)
            self.evictions += 1
        return value

    def pop(self, key: Hashable) -> V | None:
        value = self._entries.pop(key, None)
        self._bytes -= self._sizes.pop(key, 0)
        if value is not None:
            self.changes += 1
        return value

    def clear(self) -> None:
        if self._entries:
            self.changes += 1
        self._entries.clear()
        self._sizes.clear()
        self._bytes = 0


class ObjectCache(Generic[V]):
    """An LruCache keyed by the identity of objects it does not keep alive (Mesh, Texture):
    an entry goes when its object is garbage-collected, or when it is evicted. `variant`
    keeps several values of one object (a texture stored as rgba8unorm and as
    rgba8unorm-srgb) as separate entries within the same bounds."""

    def __init__(self, max_entries: int, max_bytes: int | None = None, size_of: Callable[[V], int] | None = None):
        self._cache: LruCache[tuple[weakref.ref, V]] = LruCache(
            max_entries, max_bytes, None if size_of is None else (lambda item: size_of(item[1]))
        )
        self._dead: list[tuple] = []  # keys whose objects died; purged on the next access (never from a GC callback)

    def __len__(self) -> int:
        self._purge()
        return len(self._cache)

    @property
    def nbytes(self) -> int:
        self._purge()
        return self._cache.nbytes

    @property
    def evictions(self) -> int:
        return self._cache.evictions

    @property
    def changes(self) -> int:
        """Entries put, replaced or dropped so far (evicted, or their object collected)."""
        self._purge()
        return self._cache.changes

    def clear(self) -> None:
        self._dead.clear()
        self._cache.clear()

    def _purge(self) -> None:
        while self._dead:
            key = self._dead.pop()
            item = self._cache.peek(key)
            if item is not None and item[0]() is None:
                self._cache.pop(key)

    def get(self, obj: object, variant: Hashable = None) -> V | None:
        self._purge()
        item = self._cache.get((id(obj), variant))
        if item is None or item[0]() is not obj:
            return None
        return item[1]

    def pop(self, obj: object, variant: Hashable = None) -> V | None:
        """Drop the object's entry (before a new value is made, so both are never held)."""
        self._purge()
        item = self._cache.pop((id(obj), variant))
        return None if item is None or item[0]() is not obj else item[1]

    def put(self, obj: object, value: V, variant: Hashable = None) -> V:
        self._purge()
        key = (id(obj), variant)
        dead = self._dead
        self._cache.put(key, (weakref.ref(obj, lambda _ref, key=key: dead.append(key)), value))
        return value
