"""The render passes a frame is made of: the colour pass (`color.py`) and the normals-and-ids
pass of datasets (`extra_outputs.py`). docs/architecture.md#render--the-gpu."""
