"""Measurement: the float64 reference renderer (independent of the GPU path), the
accuracy/time study and `--shading auto`. Imports `render/`, `assets/` and `scene/`.

`reference.py` and `accuracy.py` gather the public names of `reference_*.py` (the float64
reference: transforms, lighting, rasterizer, same-mesh and analytic renders) and
`accuracy_*.py` (the study: configuration, metrics, sweep, results, tables, pictures,
writing, auto shading); their docstrings say which module holds what. The reference
modules import only `scene/`, never a GPU module."""
