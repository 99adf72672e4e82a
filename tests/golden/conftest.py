"""The golden suite renders with the test session's one Renderer (tests/conftest.py)."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def golden_renderer(renderer):
    return renderer
