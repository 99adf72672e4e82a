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


def install_hint(extra: str) -> str:
    """How to install an optional extra into the Python environment running now (the venv
    that `./run` made, in a clone): its packages, installed by this very interpreter, so the
    command cannot land in another environment (or ask PyPI for a wgpu-shading it lacks)."""
    import shlex
    import sys
    from importlib import metadata

    try:
        requirements = metadata.requires("wgpu-shading") or []
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a plain source tree
        requirements = []
    marker = f'extra == "{extra}"'
    packages = [r.split(";")[0].strip() for r in requirements if marker in r.replace("'", '"')]
    names = " ".join(shlex.quote(p) for p in packages) or shlex.quote(f"wgpu-shading[{extra}]")
    return f"install the [{extra}] extra into this environment: {shlex.quote(sys.executable)} -m pip install {names}"
