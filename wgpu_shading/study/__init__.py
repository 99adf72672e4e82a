"""Measurement, in two subpackages that import `render/`, `assets/` and `scene/`:

- `reference/`: the float64 reference renderer, written from docs/conventions.md
  independently of the GPU path (it imports only `scene/`, never a GPU module);
- `accuracy/`: the accuracy/time study (`wgpu-shading bench accuracy`, docs/accuracy.md),
  measured against the reference.

The automatic shading choice (`--shading auto`) is a renderer feature:
`render/auto_shading.py`."""
