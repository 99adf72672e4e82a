"""The example scenes and sample meshes that ship inside the package (`example:NAME`).

The repository's `examples/` folder is installed as the package `wgpu_shading.examples`
(pyproject.toml), so `wgpu-shading render example:knot.obj` works from any folder on
any machine that installed wgpu-shading, and an example scene's relative paths (its
textures, the sample meshes) resolve next to the installed file.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import SceneError
from .files import installed_folder

EXAMPLE_PREFIX = "example:"

# Examples that read the model collection (not shipped: the files are large and not ours).
MODELS_HINT = (
    "this example needs the public model collection common-3d-test-models "
    "(https://github.com/alecjacobson/common-3d-test-models: spot.obj, spot_texture.png, suzanne.obj) "
    "in a folder shared/models two levels above the scene file ({folder})"
)


def examples_folder() -> Path:
    """The installed examples folder (the repository's examples/ in an editable install)."""
    return installed_folder("wgpu_shading.examples")


def example_names() -> list[str]:
    """Every example scene and sample mesh, as names for `example:NAME`."""
    suffixes = {".toml", ".obj", ".ply", ".stl", ".off", ".glb"}
    return sorted(p.name for p in examples_folder().iterdir() if p.suffix.lower() in suffixes)


def resolve_example(source: str) -> str:
    """`example:NAME` → the installed file's path; anything else unchanged."""
    if not source.startswith(EXAMPLE_PREFIX):
        return source
    name = source[len(EXAMPLE_PREFIX):]
    names = example_names()
    if name not in names:
        import difflib  # (imported on a mistake only: ~2 ms of every start)
        close = difflib.get_close_matches(name, names, n=1)
        hint = f"did you mean 'example:{close[0]}'?" if close else "expected one of " + ", ".join(names)
        raise SceneError(f"{source!r}: no such example; {hint} (`wgpu-shading examples` lists them)")
    return str(examples_folder() / name)


def models_hint(path: Path) -> str:
    """The hint for a missing file under a `shared/models` folder ('' for any other path)."""
    parts = Path(path).parts
    if "models" in parts and parts[parts.index("models") - 1 : parts.index("models")] == ("shared",):
        folder = Path(*parts[: parts.index("models") + 1])
        return "; " + MODELS_HINT.format(folder=folder.resolve())
    return ""
