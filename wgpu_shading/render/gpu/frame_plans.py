"""Frame plans: what a pass prepared for one Scene object (its draws, its uniform values),
kept for the next frame of that same object.

A Scene is frozen, and so is all it holds (a mesh's arrays and a texture's pixels are
read-only copies: scene/geometry/mesh.py, scene/material.py), so what a pass prepares for
one Scene object — which pipeline each part uses, the uniform blocks, the textures —
is the same every time that object is drawn, as long as the device's caches still hold
the uploads and pipelines the draws name. A plan is therefore used again only while the
mesh, texture and pipeline caches have not changed since it was made (nothing put,
replaced, evicted or collected: their `changes` counts); any change drops every plan, so
no plan keeps an upload alive that its cache has let go.

What it saves is the Python of preparing a frame again (the feature sets, the uniform
blocks, the pipeline and texture look-ups: a third of a small frame's Python before it is
submitted; docs/performance.md, "the small torus frame"). What it cannot see, it does not
keep: a pass stores a plan only when its frame has no work pending in the caches (a
mesh's cluster build still to start or to finish: mesh_uploads.clusters_settled), and
the key holds what the environment switches per frame (WGPU_SHADING_CLUSTERS).

Bounded (caches.FRAME_PLAN_ENTRIES scenes, least recently used first) and keyed by the
scene's identity without keeping it alive: a plan goes with its scene. Not thread-safe by
itself: the Renderer uses it under its lock, like the rest of the DeviceCache.
"""

from __future__ import annotations

from typing import Callable, Generic, Hashable, TypeVar

from .caches import FRAME_PLAN_ENTRIES, ObjectCache

P = TypeVar("P")


class FramePlans(Generic[P]):
    """Plans by (scene, variant), valid while `changes()` (the watched caches' change count) stays the same."""

    def __init__(self, changes: Callable[[], int], max_entries: int = FRAME_PLAN_ENTRIES):
        self._changes = changes
        self._plans: ObjectCache[P] = ObjectCache(max_entries)
        self._made_at: int | None = None  # the change count every stored plan was made at

    def __len__(self) -> int:
        return len(self._plans)

    def _current(self) -> None:
        changes = self._changes()
        if changes != self._made_at:
            self._plans.clear()  # made against caches that have changed since
            self._made_at = changes

    def get(self, scene: object, variant: Hashable) -> P | None:
        """The plan made for this very scene object, if the caches are as it left them."""
        self._current()
        return self._plans.get(scene, variant)

    def put(self, scene: object, variant: Hashable, plan: P) -> P:
        """Keep `plan`, made for `scene` against the caches as they are now."""
        self._current()
        return self._plans.put(scene, plan, variant)
