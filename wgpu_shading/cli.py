"""The `wgpu-shading` command line.

    wgpu-shading render SCENE.toml -o out.png
    wgpu-shading render MESH -o out.png [--frequency F] [--reflection R] [--material M] ...
    wgpu-shading turntable MESH -o spin.gif [--frames 360] [--fps 30]   a turning view
    wgpu-shading check SCENE.toml --ref golden.png [--update]   golden-image test (exit 0/1)
    wgpu-shading render SCENE --shading auto --max-error E   cheapest shading within E/255
    wgpu-shading bench accuracy [--quick] [--out DIR]       the accuracy/time study
    wgpu-shading shader SCENE.toml          print the generated WGSL
    wgpu-shading materials                  the material table
    wgpu-shading info                       adapters and versions

Errors a user can cause (missing file, bad key, bad value, no adapter) print one line on
stderr and exit with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from dataclasses import replace
from pathlib import Path
from typing import Sequence

from . import __version__
from .errors import WgpuShadingError
from .scene import FREQUENCIES, REFLECTIONS, SceneError, image_size, output_path

EXIT_USAGE = 2
EXIT_INTERNAL = 3
EXIT_MISMATCH = 1


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
    if args.size is not None:
        args.size = image_size(args.size, "--size")  # before anything divides by it
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


def _write_image(path: Path, image) -> None:
    """.npy keeps float32 exactly; image formats get the 8-bit image, written by Pillow
    directly (imageio's plugin discovery would add ~0.1 s to every cold start)."""
    import numpy as np

    if path.suffix.lower() == ".npy":
        np.save(path, image)
        return
    from PIL import Image

    if path.suffix.lower() in (".jpg", ".jpeg"):
        # JPEG has no alpha. The color is already over the background; alpha only marks
        # translucent materials, which an opaque framebuffer (OpenGL's default) shows as RGB.
        image = image[:, :, :3]
    Image.fromarray(np.ascontiguousarray(image)).save(path)


def _default_output(args: argparse.Namespace, suffix: str) -> Path:
    """-o, or the input's name with `suffix` in the current folder (builtin:torus → torus.png)."""
    if args.output:
        return Path(args.output)
    return Path(Path(args.input.split("?")[0].replace("builtin:", "")).stem + suffix)


def _check_output(path: Path, allowed: Sequence[str], float_target: bool = False) -> None:
    output_path(path, allowed)
    if float_target and path.suffix.lower() != ".npy":
        raise SceneError(f"output {str(path)!r}: --float writes exact float32 values to .npy, not {path.suffix!r}")


def command_render(args: argparse.Namespace) -> int:
    from .renderer import Renderer

    scene = _load(args)
    output = _default_output(args, ".png")
    float_target = args.float or output.suffix.lower() == ".npy"
    _check_output(output, (".png", ".npy", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"), float_target)
    renderer = Renderer(adapter=args.adapter)
    scene = _auto_shading(args, scene, renderer)
    frame = renderer.render_frame(scene, float32=float_target, depth=args.depth is not None)
    _write_image(output, frame.color)
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
    output = _default_output(args, ".gif")
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


def command_check(args: argparse.Namespace) -> int:
    """Render, compare with the reference and print the metrics: exit 0 on a match, 1 on a
    mismatch (actual, expected and diff images written), 2 on a usage error."""
    from .golden import GoldenError, Tolerance, check_image
    from .renderer import Renderer

    reference = Path(args.ref)
    if reference.suffix.lower() != ".png":
        raise GoldenError(f"--ref {args.ref!r}: the reference must be a .png file")
    if args.output_dir is not None and not Path(args.output_dir).is_dir():
        raise GoldenError(f"--output-dir {args.output_dir!r} is not an existing folder")
    if args.update and not reference.parent.exists():
        raise GoldenError(f"--ref {args.ref!r}: folder {str(reference.parent)!r} does not exist")
    tolerance = Tolerance(
        threshold=args.threshold,
        max_fraction=args.max_fraction,
        max_difference=args.max_difference,
        flip_mean=args.flip,
    )
    scene = _load(args)
    if not args.update and not reference.exists():
        raise GoldenError(f"reference {args.ref!r} does not exist; run again with --update to create it")
    image = Renderer(adapter=args.adapter).render(scene)
    result = check_image(
        image, reference, tolerance, update=args.update, output_dir=args.output_dir, amplification=args.amplify
    )
    if not args.quiet or not result.passed:
        print(result.report())
    return 0 if result.passed else EXIT_MISMATCH


def _fraction(text: str) -> float:
    """'0.001' or '0.1%'."""
    try:
        value = float(text[:-1]) / 100.0 if text.endswith("%") else float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a fraction such as 0.001 or 0.1%, got {text!r}") from None
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"expected a fraction between 0 and 1 (or 0%..100%), got {text!r}")
    return value


def _unit(text: str) -> int:
    """An integer 0..255."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer 0..255 (units of 1/255), got {text!r}") from None
    if not 0 <= value <= 255:
        raise argparse.ArgumentTypeError(f"expected an integer 0..255 (units of 1/255), got {text!r}")
    return value


def _auto_shading(args: argparse.Namespace, scene, renderer):
    """`--shading auto`: measure the candidates, print what was chosen, return the scene with it."""
    if args.shading != "auto":
        if args.max_error is not None:
            raise SceneError("--max-error goes with --shading auto")
        return scene
    if args.frequency is not None:
        raise SceneError("--shading auto chooses the frequency itself: leave out --frequency")
    from .accuracy import auto_shading

    choice = auto_shading(scene, 1.0 if args.max_error is None else args.max_error, renderer=renderer)
    if not args.quiet:
        print(choice.report())
    return choice.scene


def _error_budget(text: str) -> float:
    """A number >= 0 in units of 1/255 ('1', '0.5', '2/255')."""
    number = text[:-4] if text.endswith("/255") else text
    try:
        value = float(number)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an error in units of 1/255 such as 1 or 0.5, got {text!r}") from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"expected an error >= 0 (units of 1/255), got {text!r}")
    return value


def command_bench_accuracy(args: argparse.Namespace) -> int:
    """The accuracy/time study (docs/accuracy.md): sweep, then CSV, JSON, Markdown, pictures."""
    from dataclasses import replace as with_changes

    from .accuracy import QUICK, AccuracyError, StudyConfig, require_matplotlib, run_study, write_study
    from .renderer import Renderer

    config = QUICK if args.quick else StudyConfig()
    changes = {}
    if args.triangles:
        changes["triangles"] = tuple(args.triangles)
        changes["figure_triangles"] = tuple(n for n in config.figure_triangles if n in args.triangles) or tuple(args.triangles[:3])
    if args.sizes:
        changes["sizes"] = tuple(args.sizes)
        changes["figure_size"] = args.sizes[0] if config.figure_size not in args.sizes else config.figure_size
    if args.frames is not None:
        changes["frames"] = args.frames
    if args.no_same_mesh:
        changes["same_mesh"] = False
    config = with_changes(config, **changes)
    if args.markdown is not None and not Path(args.markdown).parent.is_dir():
        raise AccuracyError(f"--markdown {args.markdown!r}: folder {str(Path(args.markdown).parent)!r} does not exist")
    if not args.no_plot:
        require_matplotlib()  # before the sweep, not after minutes of work
    command = "wgpu-shading bench accuracy" + "".join(
        f" {flag}" for flag, on in (("--quick", args.quick), ("--no-same-mesh", args.no_same_mesh), ("--no-plot", args.no_plot)) if on
    )
    for flag, value in (("--triangles", args.triangles), ("--sizes", args.sizes)):
        if value:
            command += f" {flag} " + " ".join(str(v) for v in value)
    if args.frames is not None:
        command += f" --frames {args.frames}"
    command += f" --out {args.out}" + (f" --markdown {args.markdown}" if args.markdown else "")
    points = len(config.variants) * len(config.triangles) * len(config.sizes)
    if not args.quiet:
        shape = f"{len(config.sizes)} size(s) × {len(config.triangles)} tessellations × {len(config.variants)} shading variants"
        print(f"accuracy/time study: {points} points ({shape})", file=sys.stderr)
    study = run_study(config, Renderer(adapter=args.adapter), progress=not args.quiet, command=command)
    written = write_study(study, args.out, markdown=args.markdown, plot=not args.no_plot)
    if not args.quiet:
        from .accuracy import headline

        print(headline(study))
        print(f"wrote {', '.join(str(p) for p in written)} in {study.seconds:.0f} s")
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
    render.add_argument("--float", action="store_true", help="render to a float32 target and save it as .npy (implied by -o x.npy)")
    render.add_argument("--depth", metavar="DEPTH.npy", help="also save eye-space depth (inf = background) as .npy")
    render.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    render.add_argument(
        "--shading", choices=["auto"],
        help="auto: measure every frequency/reflection on this scene and use the cheapest within --max-error",
    )
    render.add_argument(
        "--max-error", type=_error_budget, metavar="E",
        help="error budget of --shading auto, in units of 1/255 (p99.9 of the pixels; default 1)",
    )
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

    from .golden import DEFAULT_AMPLIFICATION, Tolerance

    defaults = Tolerance()
    check = commands.add_parser(
        "check",
        parents=[gpu],
        help="render and compare with a reference image (golden-image test)",
        description=(
            "Render a scene and compare it with a reference PNG. Prints the metrics; exits 0 when they "
            "match, 1 when they differ (writes NAME.actual.png, NAME.expected.png and NAME.diff.png next "
            "to the reference or in --output-dir), 2 on a usage error. --update writes a missing or "
            "differing reference. See docs/golden-tests.md."
        ),
    )
    _add_scene_arguments(check)
    check.add_argument("--ref", required=True, metavar="REFERENCE.png", help="the reference image")
    check.add_argument("--update", action="store_true", help="write the reference when it is missing or differs")
    check.add_argument(
        "--threshold", type=_unit, default=defaults.threshold, metavar="N",
        help=f"a pixel differs when a channel differs by more than N/255 (default {defaults.threshold})",
    )
    check.add_argument(
        "--max-fraction", type=_fraction, default=defaults.max_fraction, metavar="F",
        help=f"fraction of pixels allowed to differ, e.g. 0.001 or 0.1%% (default {defaults.max_fraction:g})",
    )
    check.add_argument("--max-difference", type=_unit, metavar="N", help="also fail when any channel differs by more than N/255")
    check.add_argument(
        "--flip", type=float, metavar="MEAN", help="also fail when the mean NVIDIA FLIP error exceeds MEAN (needs flip-evaluator)"
    )
    check.add_argument("--output-dir", metavar="DIR", help="where to write the images of a failure (default: next to the reference)")
    check.add_argument(
        "--amplify", type=float, default=DEFAULT_AMPLIFICATION, metavar="K",
        help=f"the diff image shows |actual − expected| × K (default {DEFAULT_AMPLIFICATION})",
    )
    check.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    check.set_defaults(handler=command_check)

    bench = commands.add_parser("bench", help="benchmarks (accuracy)", description="Benchmarks.")
    benches = bench.add_subparsers(dest="bench", metavar="BENCHMARK")
    benches.required = True
    accuracy = benches.add_parser(
        "accuracy", parents=[gpu], help="the accuracy/time study",
        description="Sweep shading frequency × reflection model × tessellation × image size on a sphere; "
        "measure frame time and error against the exact sphere and the same-mesh float64 reference.",
    )
    accuracy.add_argument("--quick", action="store_true", help="a small sweep (3 tessellations, 128², 2 reflection models)")
    accuracy.add_argument("--out", default="accuracy", metavar="DIR", help="folder for results.csv/.json, table.md and the images (default: accuracy)")
    accuracy.add_argument("--markdown", metavar="FILE", help="also fill the generated blocks of this Markdown file (docs/accuracy.md)")
    accuracy.add_argument("--triangles", type=int, nargs="+", metavar="N", help="tessellations (triangle counts) to sweep")
    accuracy.add_argument("--sizes", type=int, nargs="+", metavar="PIXELS", help="square image sizes to sweep")
    accuracy.add_argument("--frames", type=int, help="timed frames per point (default 5; 2 with --quick)")
    accuracy.add_argument("--no-same-mesh", action="store_true", help="skip the same-mesh float64 reference")
    accuracy.add_argument("--no-plot", action="store_true", help="skip the Pareto plot (which needs matplotlib)")
    accuracy.add_argument("-q", "--quiet", action="store_true", help="no progress, print nothing on success")
    accuracy.set_defaults(handler=command_bench_accuracy)

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
    except Exception as error:  # a bug, not bad input: still one line, the traceback on request
        if os.environ.get("WGPU_SHADING_DEBUG"):
            raise
        print(
            f"wgpu-shading: internal error: {type(error).__name__}: {error} "
            "(set WGPU_SHADING_DEBUG=1 for the traceback, and please report it)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
