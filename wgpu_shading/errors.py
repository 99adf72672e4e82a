"""Exceptions. Every error a user can cause is one of these, with a message that names
the culprit (file, key or value) and what was expected; the CLI prints the message
as one line and exits non-zero."""

from __future__ import annotations


class WgpuShadingError(Exception):
    """Base class of every error the package raises on purpose."""


class SceneError(WgpuShadingError, ValueError):
    """A scene, camera, light, material or object holds an invalid value."""


class MeshError(WgpuShadingError, ValueError):
    """A mesh cannot be loaded or holds invalid data (NaN vertices, bad indices, ...)."""


class DeviceError(WgpuShadingError, RuntimeError):
    """No usable wgpu adapter or device."""
