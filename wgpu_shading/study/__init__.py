"""Measurement: the float64 reference renderer (independent of the GPU path), the
accuracy/time study and `--shading auto`. Imports `render/`, `assets/` and `scene/`."""
