"""Shared fixtures. One Renderer (one wgpu device on lavapipe) serves the whole session:
creating a device costs ~0.5 s and the first pipeline ~0.5 s more."""

from __future__ import annotations

import pytest

from wgpu_shading import Renderer


@pytest.fixture(scope="session")
def renderer() -> Renderer:
    return Renderer()
