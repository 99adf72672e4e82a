"""The one loader of a view: what `wgpu-shading render SOURCE [flags]` draws, and what a
`batch` job, the live viewer and `turntable` start from."""

from __future__ import annotations

from pathlib import Path

from ..scene.view.apply import apply_view_options
from ..scene.view.options import ViewOptions


def is_scene_file(source: str) -> bool:
    return source.lower().endswith(".toml")


def source_name(source: str, fallback: str) -> str:
    """What a file made from `source` is named after: its stem, without builtin:/example:
    or a built-in's parameters (builtin:torus?segments=8 → torus, example:gear.ply → gear),
    `fallback` when that leaves nothing. render's default -o, batch's folders and the live
    viewer's screenshots all use it."""
    source = source.split("?")[0]
    for prefix in ("builtin:", "example:"):
        source = source.removeprefix(prefix)
    return Path(source).stem or fallback


def load_source(source: str, options: ViewOptions, framing=None, loaded=None):
    """The scene file or the framed bare mesh, read with the options that act when a file is
    read (ViewOptions.loading(): crease_angle for the mesh reader; a bare mesh is framed for
    its up axis and image size). Load it once and apply several ViewOptions to it:
    load_view(source, o) == apply_view_options(load_source(source, o), o). `framing`: a mesh
    a bare mesh's camera frames instead of the file's (animation_frames.py: every pose of an
    animation); `loaded`: the bare mesh file as already read (meshes.LoadedMesh), not read
    again (animation_frames.py: one parse for every frame)."""
    from .mesh_scene import mesh_scene
    from .scenefile import load_scene

    if is_scene_file(source):
        return load_scene(source, reading=options.mesh_reading())
    return mesh_scene(
        source,
        options.size,
        None,  # the material, like every option that does not change what is read, is applied after
        up=options.up,
        file_lights=not options.viewer_lights,
        reading=options.mesh_reading(),
        camera_index=options.camera_index,
        framing=framing,
        loaded=loaded,
    )


def load_view(source: str, options: ViewOptions = ViewOptions(), framing=None, loaded=None):
    """The Scene `wgpu-shading render SOURCE` with these options draws: a scene file (.toml),
    a mesh file, builtin:NAME or example:NAME, with every option applied (`framing`,
    `loaded`: as load_source)."""
    return apply_view_options(load_source(source, options, framing, loaded), options)
