"""GPU objects that outlive a frame, and the caches that bound them (`caches.py`): everything
one device keeps is in `device_cache.py` (pipelines by key: `pipelines.py`; mesh and texture
uploads: `mesh_uploads.py` with `vertex_order.py`, `texture_uploads.py` with `mips.py`;
`samplers.py`, `uniform_buffers.py`, `bind_groups.py`; render targets: `targets.py`, read
back by `readback.py`). docs/architecture.md#render--the-gpu."""
