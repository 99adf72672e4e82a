"""Exceptions. Every error a user can cause is one of these, with a message that names
the culprit (file, key or value) and what was expected; the CLI prints the message
as one line and exits non-zero."""

from __future__ import annotations

import reprlib

MAX_MESSAGE_CHARS = 600  # a message is one readable line, whatever the input held
_SHOWN = reprlib.Repr()  # (keyword arguments need Python 3.12)
_SHOWN.maxlevel, _SHOWN.maxlist, _SHOWN.maxtuple, _SHOWN.maxdict = 3, 8, 8, 6
_SHOWN.maxstring, _SHOWN.maxother, _SHOWN.maxlong = 60, 60, 40


def shown(value: object) -> str:
    """repr() of a user value for an error message: short (a 1 MB string or a deeply nested
    list is cut, with "..."), and never recursing without bound."""
    try:
        return _SHOWN.repr(value)
    except RecursionError:  # pragma: no cover - reprlib stops at maxlevel
        return f"<{type(value).__name__}>"


def shorten(text: str, limit: int = MAX_MESSAGE_CHARS) -> str:
    """`text` on one line, at most `limit` characters (the middle is elided)."""
    text = " ".join(str(text).split())
    if len(text) <= limit:
        return text
    half = (limit - 5) // 2
    return f"{text[:half]} ... {text[-half:]}"


class WgpuShadingError(Exception):
    """Base class of every error the package raises on purpose. The message is kept to one
    line of at most MAX_MESSAGE_CHARS characters (file contents or values echoed in it are cut)."""

    def __init__(self, *args: object) -> None:
        if len(args) == 1 and isinstance(args[0], str):
            args = (shorten(args[0]),)
        super().__init__(*args)


class SceneError(WgpuShadingError, ValueError):
    """A scene, camera, light, material or object holds an invalid value."""


class MeshError(WgpuShadingError, ValueError):
    """A mesh cannot be loaded or holds invalid data (NaN vertices, bad indices, ...)."""


class UsageError(WgpuShadingError, ValueError):
    """A command-line flag, a manifest, an output path or a worker count is invalid: how the
    package was asked to work, not what it was asked to draw (SceneError, MeshError)."""


class DeviceError(WgpuShadingError, RuntimeError):
    """No usable wgpu adapter or device."""


class AccuracyError(WgpuShadingError):
    """An accuracy study or an automatic shading choice cannot be made as asked (bad option,
    missing plot library)."""


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
