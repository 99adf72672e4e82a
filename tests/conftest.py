"""Shared fixtures. One Renderer (one wgpu device on lavapipe) serves the whole session:
creating a device costs ~0.5 s and the first pipeline ~0.5 s more."""

from __future__ import annotations

import os

import pytest

from wgpu_shading import Renderer
from wgpu_shading.assets.disk_cache import CACHE_VARIABLE

# Every test parses the files it loads (their warnings, their errors, their timing), and
# writes nothing into the user's cache folder; tests/test_mesh_cache.py turns the cache
# on in a folder of its own (assets/disk_cache.py). Subprocesses (the CLI, Dask workers)
# inherit it.
os.environ[CACHE_VARIABLE] = "off"


@pytest.fixture(scope="session")
def renderer() -> Renderer:
    return Renderer()
