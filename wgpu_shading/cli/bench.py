"""`bench accuracy`: the accuracy/time study (docs/accuracy.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _check_outputs(args: argparse.Namespace) -> bool:
    """Before minutes of work: --markdown's folder exists and the file can be written, --out
    (created if missing: its nearest existing ancestor must take new files) can be; returns
    whether the plot can be drawn (everything else needs only the core packages)."""
    from ..assets.image_writers import check_folder_writable, check_writable
    from ..study.accuracy import AccuracyError, require_matplotlib

    if args.markdown is not None:
        if not Path(args.markdown).parent.is_dir():
            raise AccuracyError(f"--markdown {args.markdown!r}: folder {str(Path(args.markdown).parent)!r} does not exist")
        check_writable(Path(args.markdown), "--markdown")
    existing = Path(args.out).absolute()
    while not existing.exists():
        existing = existing.parent
    check_folder_writable(existing, "--out")
    if args.no_plot:
        return False
    try:
        require_matplotlib()
    except AccuracyError as error:
        print(f"wgpu-shading: note: {error}; writing everything else", file=sys.stderr)
        return False
    return True


def command_bench_accuracy(args: argparse.Namespace) -> int:
    """The accuracy/time study (docs/accuracy.md): sweep, then CSV, JSON, Markdown, pictures."""
    if args.shadows:
        return command_shadow_study(args)
    from dataclasses import replace as with_changes

    from ..study.accuracy import QUICK, StudyConfig, run_study, write_study
    from ..render.renderer import Renderer

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
    plot = _check_outputs(args)
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
    written = write_study(study, args.out, markdown=args.markdown, plot=plot)
    if not args.quiet:
        from ..study.accuracy import headline

        print(headline(study))
        print(f"wrote {', '.join(str(p) for p in written)} in {study.seconds:.0f} s")
    return 0

def command_shadow_study(args: argparse.Namespace) -> int:
    """`bench accuracy --shadows`: map size × filter × bias on the shadow hard cases against
    the exact shadows, timed; writes shadows.csv/.json/.md and the plot, says what `auto` is."""
    import time

    from ..render.renderer import Renderer
    from ..scene import shadows as shadow_settings
    from ..study.accuracy import (
        QUICK_SHADOW_CASES, cheapest_shadow_setting, environment, quick_shadow_grid, run_shadow_study, shadow_grid,
        write_shadow_study,
    )
    from ..study.accuracy.shadow_sweep import STUDY_CASES
    from ..study.accuracy.progress import Progress

    plot = _check_outputs(args)
    grid, cases = (quick_shadow_grid(), QUICK_SHADOW_CASES) if args.quick else (shadow_grid(), STUDY_CASES)
    size = (128, 128) if args.quick else (256, 256)
    frames = args.frames if args.frames is not None else (2 if args.quick else 3)
    command = "wgpu-shading bench accuracy --shadows" + (" --quick" if args.quick else "") + (" --no-plot" if args.no_plot else "")
    command += (f" --frames {args.frames}" if args.frames is not None else "") + f" --out {args.out}"
    command += f" --markdown {args.markdown}" if args.markdown else ""
    renderer = Renderer(adapter=args.adapter)
    env = environment(renderer)
    total = len(grid) * len(cases)
    if not args.quiet:
        print(f"shadow study: {total} points ({len(grid)} settings × {len(cases)} cases, {size[0]}² images)", file=sys.stderr)
    progress = None if args.quiet else Progress(total)
    start = time.perf_counter()
    points = run_shadow_study(renderer, grid, cases, size=size, frames=frames,
                              progress=None if progress is None else (lambda done, _: progress.advance(1, f"{done}/{total}")))
    seconds = time.perf_counter() - start
    written = write_shadow_study(points, args.out, markdown=args.markdown, plot=plot, command=command, seconds=seconds, environment=env)
    if not args.quiet:
        chosen = cheapest_shadow_setting(points)
        current = (shadow_settings.AUTO_MAP_SIZE, shadow_settings.AUTO_FILTER, shadow_settings.AUTO_BIAS)
        if chosen is None:
            print("no setting met the budget on every case")
        else:
            found = (chosen.map_size, chosen.filter, chosen.bias)
            same = "the renderer's auto already" if found == current else f"the renderer's auto is {current}; set scene/shadows.py's AUTO_* to"
            print(f"auto: {found} ({same} this)")
        print(f"wrote {', '.join(str(p) for p in written)} in {seconds:.0f} s")
    return 0


def add_bench(commands, gpu: argparse.ArgumentParser) -> None:
    bench = commands.add_parser("bench", help="benchmarks (accuracy)", description="Benchmarks.")
    benches = bench.add_subparsers(dest="bench", metavar="BENCHMARK")
    benches.required = True
    accuracy = benches.add_parser(
        "accuracy", parents=[gpu], help="the accuracy/time study",
        description="Sweep shading frequency × reflection model × tessellation × image size on a sphere; "
        "measure frame time and error against the exact sphere and the same-mesh float64 reference.",
    )
    accuracy.add_argument("--quick", action="store_true", help="a small sweep (3 tessellations, 128², 2 reflection models)")
    accuracy.add_argument("--shadows", action="store_true",
                          help="the shadow study instead: shadow-map size × filter × bias on the shadow hard cases, against the exact shadows")
    accuracy.add_argument("--out", default="accuracy", metavar="DIR", help="folder for results.csv/.json, table.md and the images (default: accuracy)")
    accuracy.add_argument("--markdown", metavar="FILE", help="also fill the generated blocks of this Markdown file (docs/accuracy.md)")
    accuracy.add_argument("--triangles", type=int, nargs="+", metavar="N", help="tessellations (triangle counts) to sweep")
    accuracy.add_argument("--sizes", type=int, nargs="+", metavar="PIXELS", help="square image sizes to sweep")
    accuracy.add_argument("--frames", type=int, help="timed frames per point (default 5; 2 with --quick)")
    accuracy.add_argument("--no-same-mesh", action="store_true", help="skip the same-mesh float64 reference")
    accuracy.add_argument("--no-plot", action="store_true", help="skip the Pareto plot (which needs matplotlib)")
    accuracy.add_argument("-q", "--quiet", action="store_true", help="no progress, print nothing on success")
    accuracy.set_defaults(handler=command_bench_accuracy)
