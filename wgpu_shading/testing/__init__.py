"""Golden-image testing: the image comparison and its report, and the pytest plugin
(`assert_golden`). Imports `render/`, `assets/` and `scene/`."""
