"""`render`, `turntable`, `animate` and `shader`: a scene or mesh to an image, an animation, or WGSL."""

from __future__ import annotations

import argparse
import math
import sys

from ..errors import UsageError
from ..assets.animation import MAX_FPS, MIN_FPS
from .arguments import add_scene_arguments, check_output, default_output, error_budget, scene_from_args


def command_render(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ..assets.image_writers import DEPTH_SUFFIXES, IMAGE_SUFFIXES, STDOUT, output_path, png_bytes, write_depth, write_image
    from ..render.renderer import Renderer

    to_stdout = args.output == STDOUT
    # Every output is checked before the scene is even loaded: a typo costs nothing.
    output = None if to_stdout else default_output(args, ".png")
    float_target = args.float or (output is not None and output.suffix.lower() == ".npy")
    if to_stdout and args.float:
        raise UsageError("-o - writes an 8-bit PNG to standard output; --float needs a .npy file")
    if to_stdout:
        _check_stdout()
    if output is not None:
        check_output(output, IMAGE_SUFFIXES, float_target)
    depth_path = None if args.depth is None else output_path(Path(args.depth), DEPTH_SUFFIXES, "--depth")
    if depth_path is not None and output is not None and depth_path.resolve() == output.resolve():
        # Otherwise the depth image silently replaces the colour image.
        raise UsageError(f"--depth {str(depth_path)!r} is the same file as the output; give depth its own name")
    scene = scene_from_args(args)
    renderer = Renderer(adapter=args.adapter)
    scene = _auto_shading(args, scene, renderer)
    frame = renderer.render_frame(scene, float32=float_target, depth=depth_path is not None)
    if to_stdout:
        _write_stdout(png_bytes(frame.color))
    else:
        write_image(output, frame.color)
    report = sys.stderr if to_stdout else sys.stdout  # standard output carries the PNG
    if depth_path is not None:
        stored = write_depth(depth_path, frame.depth, scene.camera.near, scene.camera.far)
        if not args.quiet:
            print(f"wrote {depth_path} (depth: {stored})", file=report)
    if not args.quiet:
        width, height = scene.size
        print(
            f"wrote {'standard output' if to_stdout else output} ({width}×{height}, "
            f"{scene.shading.frequency} shading, {scene.shading.reflection} reflection)",
            file=report,
        )
    return 0


def _check_stdout() -> None:
    """`-o -` needs an open standard output (checked before rendering)."""
    import os

    try:
        if sys.stdout is None:
            raise OSError("closed")
        os.fstat(sys.stdout.fileno())
    except (OSError, ValueError):
        raise UsageError("-o -: standard output is closed; give a file name with -o") from None


def _write_stdout(data: bytes) -> None:
    """The PNG to standard output; a reader that went away (broken pipe, `| head -c 10`) is one
    line and exit 2. Standard output is then pointed at /dev/null so that Python's flush at
    exit does not print a second error."""
    import os

    try:
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
    except (OSError, ValueError) as error:
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            os.close(devnull)
        except (OSError, ValueError):
            pass
        reason = "the reader closed the pipe" if isinstance(error, BrokenPipeError) else (getattr(error, "strerror", None) or str(error))
        raise UsageError(f"-o -: the PNG could not be written to standard output: {reason}") from None


def command_turntable(args: argparse.Namespace) -> int:
    from ..assets.animation import check_animation_path, write_animation
    from ..scene.view.turntable import turntable
    from ..render.renderer import Renderer

    if args.frames < 1:
        raise UsageError(f"--frames must be at least 1, got {args.frames}")
    _check_fps(args.fps)
    if not (math.isfinite(args.degrees) and abs(args.degrees) <= 1e6):
        raise UsageError(f"--degrees must be a finite number of degrees (at most 1e6 in size), got {args.degrees}")
    scene = scene_from_args(args)
    output = default_output(args, ".gif")
    check_animation_path(output)  # before rendering: a wrong suffix should not cost a minute
    renderer = Renderer(adapter=args.adapter)
    from tqdm import tqdm

    frames = (frame.color for frame in renderer.render_many(turntable(scene, args.frames, args.degrees)))
    # A bar on a terminal only: quiet with -q, and when stderr is a log or a pipe.
    with tqdm(total=args.frames, unit="frame", file=sys.stderr, disable=args.quiet or not sys.stderr.isatty()) as bar:
        written = write_animation(output, frames, fps=args.fps, progress=lambda done: bar.update(done - bar.n))
    if not args.quiet:
        width, height = scene.size
        print(f"wrote {output} ({written} frames, {width}×{height}, {args.fps:g} fps, {args.degrees:g}° turn)")
    return 0



def command_animate(args: argparse.Namespace) -> int:
    from ..assets.animation import check_animation_path, write_animation
    from ..assets.animation_frames import AnimationFrames
    from ..render.renderer import Renderer
    from ..scene.view.reading import MAX_SECONDS
    from .arguments import view_options_from_args

    _check_fps(args.fps)
    for flag, value in (("--start", args.start), ("--end", args.end)):
        if value is not None and not (math.isfinite(value) and abs(value) <= MAX_SECONDS):
            raise UsageError(f"{flag} must be a finite number of seconds (at most {MAX_SECONDS:g} in size), got {value}")
    output = default_output(args, ".gif")
    check_animation_path(output)  # before rendering: a wrong suffix should not cost a minute
    frames = AnimationFrames(args.input, view_options_from_args(args), args.fps, args.start, args.end)
    renderer = Renderer(adapter=args.adapter)
    from tqdm import tqdm

    images = (frame.color for frame in renderer.render_many(frames))
    with tqdm(total=len(frames), unit="frame", file=sys.stderr, disable=args.quiet or not sys.stderr.isatty()) as bar:
        written = write_animation(output, images, fps=args.fps, progress=lambda done: bar.update(done - bar.n))
    if not args.quiet:
        print(f"wrote {output} ({written} frames, {frames.start:g} s to {frames.times[-1]:g} s of animation "
              f"{frames.animation}, {args.fps:g} fps)")
    return 0


def _check_fps(fps: float) -> None:
    if not (MIN_FPS <= fps <= MAX_FPS):
        raise UsageError(f"--fps must be between {MIN_FPS:g} and {MAX_FPS:g} frames per second, got {fps}")


def _auto_shading(args: argparse.Namespace, scene, renderer):
    """`--shading auto`: measure the candidates, print what was chosen, return the scene with it."""
    if args.shading != "auto":
        if args.max_error is not None:
            raise UsageError("--max-error goes with --shading auto")
        return scene
    if args.frequency is not None:
        raise UsageError("--shading auto chooses the frequency itself: leave out --frequency")
    from ..render.auto_shading import auto_shading

    choice = auto_shading(scene, 1.0 if args.max_error is None else args.max_error, renderer=renderer)
    if not args.quiet:
        print(choice.report())
    return choice.scene



def command_shader(args: argparse.Namespace) -> int:
    from ..render.shaders.shadergen import generate_wgsl
    from ..render.stroke_features import edge_features, part_features

    scene = scene_from_args(args)
    seen = set()
    for index, obj in enumerate(scene.objects):
        # One draw per part (each with its own material), points and lines included, and the
        # edges' draw with --edges: print each distinct shader once.
        draws = [(part_features(scene, obj, index, part, material), f" part {part.name!r}" if len(obj.mesh.parts) > 1 else "")
                 for part, material in zip(obj.mesh.parts, obj.part_materials()) if part.count]
        if scene.shading.edges and obj.mesh.triangle_count:
            draws.append((edge_features(scene), " edges"))
        for features, label in draws:
            if features in seen:
                continue
            seen.add(features)
            print(f"// ===== objects {index}: {obj.mesh.name}{label}")
            print(generate_wgsl(features))
    if not scene.objects:
        print("// the scene has no objects: nothing is drawn, no shader is needed")
    return 0



def add_render(commands, gpu: argparse.ArgumentParser) -> None:
    render = commands.add_parser(
        "render", parents=[gpu], help="render a scene or a mesh to an image", description="Render a scene file or a mesh to an image."
    )
    add_scene_arguments(render)
    from ..assets.animation import ANIMATION_SUFFIXES
    from ..assets.image_writers import DEPTH_FORMATS, IMAGE_FORMATS, formats_text

    render.add_argument(
        "-o", "--output",
        help=f"output image: {formats_text(IMAGE_FORMATS)}, or - for PNG on standard output (default: INPUT.png)",
    )
    render.add_argument("--float", action="store_true", help="render to a float32 target and save it as .npy (implied by -o x.npy)")
    render.add_argument("--depth", metavar="DEPTH", help=f"also save eye-space depth: {formats_text(DEPTH_FORMATS)}")
    render.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    render.add_argument(
        "--shading", choices=["auto"],
        help="auto: measure every frequency/reflection on this scene and use the cheapest within --max-error",
    )
    render.add_argument(
        "--max-error", type=error_budget, metavar="E",
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
    add_scene_arguments(spin)
    spin.add_argument("-o", "--output", help=f"output animation: {' or '.join(ANIMATION_SUFFIXES)} (default: INPUT.gif)")
    spin.add_argument("--frames", type=int, default=360, help="number of frames (default: 360, one per degree)")
    spin.add_argument("--degrees", type=float, default=360.0, help="total turn in degrees (default: 360, a loop)")
    spin.add_argument("--fps", type=float, default=30.0, help="frames per second of the animation (default: 30)")
    spin.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    spin.set_defaults(handler=command_turntable)

    play = commands.add_parser(
        "animate",
        parents=[gpu],
        help="render a glTF file's animation to a GIF or MP4",
        description="Play a glTF file's animation (node transforms, skins, morph weights) from --start to --end "
        "at --fps frames per second, as --animation-time would draw each moment, and write an animated GIF "
        "(looping) or an MP4 (needs imageio-ffmpeg: the [video] extra). One camera frames every pose; "
        "--animation-index chooses the animation (or all), --camera-index the file's own camera.",
    )
    add_scene_arguments(play)
    play.add_argument("-o", "--output", help="output animation: .gif or .mp4 (default: INPUT.gif)")
    play.add_argument("--fps", type=float, default=30.0, help="frames per second, of the animation and of the output (default: 30)")
    play.add_argument("--start", type=float, metavar="SECONDS", help="first frame's time (default: 0)")
    play.add_argument("--end", type=float, metavar="SECONDS", help="last frame's time at most (default: the animation's last keyframe)")
    play.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    play.set_defaults(handler=command_animate)


def add_shader(commands, gpu: argparse.ArgumentParser) -> None:
    shader = commands.add_parser("shader", help="print the WGSL generated for a scene", description="Print the WGSL generated for each object's feature set.")
    add_scene_arguments(shader)
    shader.set_defaults(handler=command_shader)
