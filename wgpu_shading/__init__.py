"""wgpu-shading: classic local lighting (Phong and Blinn-Phong reflection; flat, Gouraud and
Phong shading; OpenGL-style lights and materials; textures) in WGSL, rendered offscreen
with wgpu — on Mesa's lavapipe by default.

    from wgpu_shading import Renderer, load_scene, mesh_scene, turntable
    image = Renderer().render(load_scene("examples/gold_torus_phong.toml"))
    frames = Renderer().render_many(turntable(mesh_scene("builtin:torus"), 36))

The pipeline, one subpackage per stage (docs/architecture.md): scene/ (what to draw) and
assets/ (files) → render/ (feature set → WGSL from wgsl/ → cached pipeline → render pass)
→ numpy image; study/ (float64 reference, accuracy study), testing/ (golden images),
dataset/ and cli/ sit on top.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from .errors import DeviceError, MeshError, SceneError, UsageError, WgpuShadingError
    from .assets.view_loader import load_view
    from .scene.view.apply import apply_view_options
    from .scene.view.options import ViewOptions, render_command
    from .assets import load_mesh, load_scene, parse_scene
    from .assets.mesh_scene import mesh_scene
    from .render.auto_shading import AutoChoice, auto_shading
    from .render.features import FeatureSet
    from .render.renderer import Frame, PendingFrame, Renderer
    from .scene import (
        MATERIALS,
        Camera,
        DirectionalLight,
        Light,
        Material,
        Mesh,
        PositionalLight,
        Scene,
        SceneObject,
        Shading,
        SpotLight,
        Texture,
        material,
    )
    from .scene.view.turntable import turntable

__version__ = "0.1.0"

# Every name is loaded on first use: `import wgpu_shading` (which pytest does for the
# golden-image plugin in any project that installs this package) costs nothing, and
# numpy (~0.1 s) and wgpu (~0.1 s) load only when something needs them.
_LAZY = {
    "DeviceError": "errors", "MeshError": "errors", "SceneError": "errors", "UsageError": "errors", "WgpuShadingError": "errors",
    "ViewOptions": "scene.view.options", "apply_view_options": "scene.view.apply", "render_command": "scene.view.options",
    "load_view": "assets.view_loader",
    "FeatureSet": "render.features",
    "MATERIALS": "scene", "material": "scene", "Mesh": "scene",
    "load_mesh": "assets", "load_scene": "assets", "parse_scene": "assets", "mesh_scene": "assets.mesh_scene",
    "AutoChoice": "render.auto_shading", "auto_shading": "render.auto_shading", "turntable": "scene.view.turntable",
    "Frame": "render.renderer", "PendingFrame": "render.renderer", "Renderer": "render.renderer",
    "Camera": "scene", "DirectionalLight": "scene", "Light": "scene", "Material": "scene",
    "PositionalLight": "scene", "Scene": "scene", "SceneObject": "scene", "Shading": "scene",
    "SpotLight": "scene", "Texture": "scene",
    "view": "live.widget",  # a notebook widget (the [view] extra; docs/viewer.md)
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from importlib import import_module

        return getattr(import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "AutoChoice",
    "Camera",
    "DeviceError",
    "DirectionalLight",
    "FeatureSet",
    "Frame",
    "Light",
    "MATERIALS",
    "Material",
    "Mesh",
    "MeshError",
    "PendingFrame",
    "PositionalLight",
    "Renderer",
    "Scene",
    "SceneError",
    "SceneObject",
    "Shading",
    "SpotLight",
    "Texture",
    "UsageError",
    "ViewOptions",
    "WgpuShadingError",
    "apply_view_options",
    "auto_shading",
    "load_mesh",
    "load_scene",
    "load_view",
    "material",
    "mesh_scene",
    "parse_scene",
    "render_command",
    "turntable",
    "view",
]
