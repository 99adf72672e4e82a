"""What a view is and how it changes a scene: the one table of view options (options.py)
with the readers of their values (reading.py) and the function that applies them
(apply.py); how a bare mesh becomes a scene (bare_mesh.py); turntables (turntable.py).
docs/view-options.md says how to add an option."""
