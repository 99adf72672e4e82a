"""`materials` and `info`: the material table, the adapters and versions."""

from __future__ import annotations

import argparse

from .. import __version__


def command_materials(args: argparse.Namespace) -> int:
    from ..scene import MATERIALS

    def rgb(values) -> str:
        return " ".join(f"{v:.4f}" for v in values[:3])

    print(f"{'name':<16} {'ambient RGB':<22} {'diffuse RGB':<22} {'specular RGB':<22} {'shininess':>9} {'alpha':>6}")
    for name, m in MATERIALS.items():
        print(f"{name:<16} {rgb(m.ambient):<22} {rgb(m.diffuse):<22} {rgb(m.specular):<22} {m.shininess:>9.3f} {m.diffuse[3]:>6.3f}")
    print("\nshininess in OpenGL units (the classic table's fraction × 128); use a name in a scene file as material = \"gold\"")
    return 0


def command_examples(args: argparse.Namespace) -> int:
    from ..assets.examples import example_names, examples_folder

    print(f"example scenes and sample meshes (in {examples_folder()}); use them as example:NAME")
    for name in example_names():
        print(f"  example:{name}")
    return 0


def command_info(args: argparse.Namespace) -> int:
    import platform

    import numpy as np
    import wgpu

    from ..render.device import default_device, describe_device, list_adapters, requested_adapter

    print(f"wgpu-shading {__version__}, Python {platform.python_version()}, wgpu-py {wgpu.__version__}, numpy {np.__version__}")
    selector = requested_adapter(args.adapter)
    print(f"adapter selector: {selector!r} (set with --adapter or WGPU_SHADING_ADAPTER)")
    adapters = list_adapters(selector)
    print("adapters:")
    for adapter in adapters:
        info = adapter.info
        print(f"  - {adapter.summary} [{info.get('adapter_type')}, {info.get('description')}]")
    device = default_device(selector)
    print(f"using: {describe_device(device)}")
    limits = device.limits
    print(f"max image side: {limits['max-texture-dimension-2d']}, max buffer: {limits['max-buffer-size'] / 2**20:.0f} MiB")
    print(mesh_cache_line())
    return 0


def mesh_cache_line() -> str:
    """Where mesh files read once are kept (docs/real-world-files.md), and how full it is."""
    from ..assets.disk_cache import CACHE_VARIABLE, SIZE_VARIABLE, disk_cache

    cache = disk_cache()
    if cache is None:
        return f"mesh cache: off (set {CACHE_VARIABLE} to a folder, and {SIZE_VARIABLE} above 0, to keep meshes read once)"
    entries, size = cache.usage()
    return (f"mesh cache: {cache.folder} ({entries} {'entry' if entries == 1 else 'entries'}, "
            f"{size / 2**20:.1f} of {cache.max_bytes / 2**20:.0f} MiB; "
            f"{CACHE_VARIABLE}=off turns it off)")



def add_info(commands, gpu: argparse.ArgumentParser) -> None:
    materials = commands.add_parser("materials", help="list the material table", description="List the built-in material table.")
    materials.set_defaults(handler=command_materials)

    examples = commands.add_parser(
        "examples", help="list the example scenes and sample meshes (example:NAME)",
        description="List the example scenes and sample meshes that ship with wgpu-shading.",
    )
    examples.set_defaults(handler=command_examples)

    info = commands.add_parser("info", parents=[gpu], help="show the adapter and versions", description="Show adapters, the one in use, and versions.")
    info.set_defaults(handler=command_info)
