"""The `wgpu-shading` command line.

    wgpu-shading render SCENE.toml -o out.png
    wgpu-shading render MESH -o out.png [--frequency F] [--reflection R] [--material M] ...
    wgpu-shading turntable MESH -o spin.gif [--frames 360] [--fps 30]   a turning view
    wgpu-shading shader SCENE.toml          print the generated WGSL
    wgpu-shading materials                  the material table
    wgpu-shading info                       adapters and versions

Errors a user can cause (missing file, bad key, bad value, no adapter) print one line on
stderr and exit with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace
from pathlib import Path
from typing import Sequence

from . import __version__
from .errors import WgpuShadingError
from .scene import FREQUENCIES, REFLECTIONS, SceneError

EXIT_USAGE = 2


# --------------------------------------------------------------------------- scene from arguments


def _size(text: str) -> tuple[int, int]:
    """'512' or '640x480'."""
    parts = text.lower().replace("×", "x").split("x")
    try:
        numbers = [int(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT or SIZE, got {text!r}") from None
    if len(numbers) == 1:
        numbers *= 2
    if len(numbers) != 2:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT or SIZE, got {text!r}")
    return numbers[0], numbers[1]


def framing_camera(mesh, size: tuple[int, int], fov_y: float = 45.0):
    """A camera that frames the whole mesh, looking from the front and a little above."""
    import numpy as np

    from .scene import Camera

    lower, upper = mesh.bounds()
    center = (lower + upper) / 2.0
    radius = max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-12)
    aspect = size[0] / size[1]
    half_fov = math.radians(fov_y) / 2.0
    narrowest = min(half_fov, math.atan(math.tan(half_fov) * aspect))
    distance = radius / math.sin(narrowest) * 1.05
    direction = np.array([0.0, 0.35, 1.0]) / np.linalg.norm([0.0, 0.35, 1.0])
    eye = center + direction * distance
    return Camera(
        eye=tuple(eye),
        target=tuple(center),
        up=(0.0, 1.0, 0.0),
        fov_y=fov_y,
        near=max(distance - 1.5 * radius, distance * 1e-3),
        far=distance + 1.5 * radius,
    )


def mesh_scene(mesh_source: str, size: tuple[int, int], material_name: str | None):
    """A scene for a bare mesh: framed by the camera, lit like the seeds' demo (a white light
    up, right and in front, global ambient 0.2), the file's material or gold."""
    import numpy as np

    from .materials import material
    from .meshes import load_mesh
    from .scene import PositionalLight, Scene, SceneObject

    mesh = load_mesh(mesh_source)
    if material_name:
        chosen = material(material_name)
    else:
        chosen = mesh.material or material("gold")
    lower, upper = mesh.bounds()
    center = (lower + upper) / 2.0
    radius = max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-12)
    light_position = center + np.array([5.0, 2.0, 2.0]) * radius * 1.5
    return Scene(
        objects=(SceneObject(mesh, chosen),),
        lights=(PositionalLight(position=tuple(light_position)),),
        camera=framing_camera(mesh, size),
        size=size,
    )


def _load(args: argparse.Namespace):
    """The scene named on the command line, with the command-line overrides applied."""
    from .materials import material
    from .scenefile import load_scene

    source: str = args.input
    if source.lower().endswith(".toml"):
        scene = load_scene(source)
        if args.size:
            scene = replace(scene, size=args.size)
        if args.material:
            chosen = material(args.material)
            scene = replace(scene, objects=tuple(replace(o, material=chosen) for o in scene.objects))
    else:
        scene = mesh_scene(source, args.size or (512, 512), args.material)
    shading = scene.shading
    overrides = {
        key: value
        for key, value in (
            ("frequency", args.frequency),
            ("reflection", args.reflection),
            ("blinn_exponent_scale", args.blinn_exponent_scale),
        )
        if value is not None
    }
    if args.infinite_viewer:
        overrides["local_viewer"] = False
    if args.two_sided:
        overrides["two_sided"] = True
    if overrides:
        scene = replace(scene, shading=replace(shading, **overrides))
    return scene


def _add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("input", help="a scene file (.toml), a mesh file (OBJ, PLY, STL, OFF, GLB) or builtin:NAME")
    parser.add_argument("--size", type=_size, help="image size, WIDTHxHEIGHT or SIZE (default: the scene's, or 512)")
    parser.add_argument("--frequency", choices=FREQUENCIES, help="shading frequency (overrides the scene)")
    parser.add_argument("--reflection", choices=REFLECTIONS, help="reflection model (overrides the scene)")
    parser.add_argument(
        "--blinn-exponent-scale", type=float, metavar="K", help="Blinn-Phong exponent = shininess × K (seed: 3, OpenGL: 1)"
    )
    parser.add_argument("--material", help="material name for every object (see `wgpu-shading materials`)")
    parser.add_argument("--infinite-viewer", action="store_true", help="OpenGL's default viewer: V = (0, 0, 1)")
    parser.add_argument("--two-sided", action="store_true", help="light back faces with the flipped normal")


# --------------------------------------------------------------------------- commands


def _write_image(path: Path, image, float_target: bool) -> None:
    import numpy as np

    suffix = path.suffix.lower()
    if suffix == ".npy":
        np.save(path, image)
        return
    if suffix == ".png" and not float_target:
        # 8-bit PNGs go straight to Pillow: imageio's plugin discovery and import cost
        # ~0.1 s, a seventh of the whole cold start of `wgpu-shading render`.
        from PIL import Image

        Image.fromarray(np.ascontiguousarray(image)).save(path)
        return
    import imageio.v3 as iio

    if float_target:
        if suffix != ".png":
            raise SceneError(f"{path}: --float writes .npy or 16-bit .png, not {suffix!r}")
        image = np.round(np.clip(image, 0.0, 1.0) * 65535.0).astype(np.uint16)
    iio.imwrite(path, image)


def _check_output(path: Path, allowed: Sequence[str]) -> None:
    if path.suffix.lower() not in allowed:
        raise SceneError(f"output {str(path)!r}: unsupported format; use one of {', '.join(allowed)}")
    if not path.parent.exists():
        raise SceneError(f"output {str(path)!r}: folder {str(path.parent)!r} does not exist")


def command_render(args: argparse.Namespace) -> int:
    from .renderer import Renderer

    scene = _load(args)
    output = Path(args.output or (Path(args.input.split("?")[0].replace("builtin:", "")).stem + ".png"))
    float_target = args.float or output.suffix.lower() == ".npy"
    _check_output(output, (".png", ".npy", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"))
    renderer = Renderer(adapter=args.adapter)
    frame = renderer.render_frame(scene, float32=float_target, depth=args.depth is not None)
    _write_image(output, frame.color, float_target)
    if args.depth is not None:
        import numpy as np

        np.save(args.depth, frame.depth.astype(np.float32))
    if not args.quiet:
        width, height = scene.size
        print(f"wrote {output} ({width}×{height}, {scene.shading.frequency} shading, {scene.shading.reflection} reflection)")
    return 0


def command_turntable(args: argparse.Namespace) -> int:
    from .batch import check_animation_path, turntable, write_animation
    from .renderer import Renderer

    if args.frames < 1:
        raise SceneError(f"--frames must be at least 1, got {args.frames}")
    if not (args.fps > 0 and math.isfinite(args.fps)):
        raise SceneError(f"--fps must be a positive number, got {args.fps}")
    scene = _load(args)
    output = Path(args.output or (Path(args.input.split("?")[0].replace("builtin:", "")).stem + ".gif"))
    check_animation_path(output)  # before rendering: a wrong suffix should not cost a minute
    renderer = Renderer(adapter=args.adapter)
    frames = (frame.color for frame in renderer.render_many(turntable(scene, args.frames, args.degrees)))
    show_progress = not args.quiet and sys.stderr.isatty()

    def progress(done: int) -> None:
        print(f"\rframe {done}/{args.frames}", end="", file=sys.stderr, flush=True)

    written = write_animation(output, frames, fps=args.fps, progress=progress if show_progress else None)
    if show_progress:
        print(file=sys.stderr)
    if not args.quiet:
        width, height = scene.size
        print(f"wrote {output} ({written} frames, {width}×{height}, {args.fps:g} fps, {args.degrees:g}° turn)")
    return 0


def command_shader(args: argparse.Namespace) -> int:
    from .features import object_features
    from .shadergen import generate_wgsl

    scene = _load(args)
    seen = set()
    for index, obj in enumerate(scene.objects):
        features = object_features(scene, obj, index)
        if features in seen:
            continue
        seen.add(features)
        print(f"// ===== objects {index}: {obj.mesh.name}")
        print(generate_wgsl(features))
    if not scene.objects:
        print("// the scene has no objects: nothing is drawn, no shader is needed")
    return 0


def command_materials(args: argparse.Namespace) -> int:
    from .materials import MATERIALS

    def rgb(values) -> str:
        return " ".join(f"{v:.4f}" for v in values[:3])

    print(f"{'name':<16} {'ambient RGB':<22} {'diffuse RGB':<22} {'specular RGB':<22} {'shininess':>9} {'alpha':>6}")
    for name, m in MATERIALS.items():
        print(f"{name:<16} {rgb(m.ambient):<22} {rgb(m.diffuse):<22} {rgb(m.specular):<22} {m.shininess:>9.3f} {m.diffuse[3]:>6.3f}")
    print("\nshininess in OpenGL units (the classic table's fraction × 128); use a name in a scene file as material = \"gold\"")
    return 0


def command_info(args: argparse.Namespace) -> int:
    import platform

    import numpy as np
    import wgpu

    from .device import default_device, describe_device, list_adapters, requested_adapter

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
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="wgpu-shading",
        description="Classic local lighting (Phong/Blinn-Phong; flat, Gouraud, Phong shading) rendered offscreen with wgpu.",
    )
    parser.add_argument("--version", action="version", version=f"wgpu-shading {__version__}")
    # Options of every command that uses the GPU.
    gpu = argparse.ArgumentParser(add_help=False)
    gpu.add_argument(
        "--adapter", help="lavapipe (default), gpu, or part of an adapter's name; also WGPU_SHADING_ADAPTER"
    )
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    render = commands.add_parser(
        "render", parents=[gpu], help="render a scene or a mesh to an image", description="Render a scene file or a mesh to an image."
    )
    _add_scene_arguments(render)
    render.add_argument("-o", "--output", help="output image: .png (8-bit), .npy (float32), .jpg, .tif (default: INPUT.png)")
    render.add_argument("--float", action="store_true", help="render to a float32 target (.npy, or 16-bit .png)")
    render.add_argument("--depth", metavar="DEPTH.npy", help="also save eye-space depth (inf = background) as .npy")
    render.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    render.set_defaults(handler=command_render)

    spin = commands.add_parser(
        "turntable",
        parents=[gpu],
        help="render a turning view of a scene or mesh to a GIF or MP4",
        description="Render the scene turning about the camera's up axis (camera and lights stay put) "
        "and write an animated GIF (looping) or an MP4 (needs imageio-ffmpeg: the [video] extra).",
    )
    _add_scene_arguments(spin)
    spin.add_argument("-o", "--output", help="output animation: .gif or .mp4 (default: INPUT.gif)")
    spin.add_argument("--frames", type=int, default=360, help="number of frames (default: 360, one per degree)")
    spin.add_argument("--degrees", type=float, default=360.0, help="total turn in degrees (default: 360, a loop)")
    spin.add_argument("--fps", type=float, default=30.0, help="frames per second of the animation (default: 30)")
    spin.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    spin.set_defaults(handler=command_turntable)

    shader = commands.add_parser("shader", help="print the WGSL generated for a scene", description="Print the WGSL generated for each object's feature set.")
    _add_scene_arguments(shader)
    shader.set_defaults(handler=command_shader)

    materials = commands.add_parser("materials", help="list the material table", description="List the built-in material table.")
    materials.set_defaults(handler=command_materials)

    info = commands.add_parser("info", parents=[gpu], help="show the adapter and versions", description="Show adapters, the one in use, and versions.")
    info.set_defaults(handler=command_info)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.handler(args)
    except WgpuShadingError as error:
        print(f"wgpu-shading: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as error:  # unwritable output, full disk, ...
        print(f"wgpu-shading: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("wgpu-shading: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
