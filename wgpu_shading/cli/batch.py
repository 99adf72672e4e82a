"""`batch`: a manifest, or meshes × views, to a dataset folder (docs/datasets.md)."""

from __future__ import annotations

import argparse
import sys

from dataclasses import replace

from ..assets.image_writers import PNG_LEVEL
from ..errors import UsageError
from ..scene.view.options import OPTIONS_BY_NAME, ViewOptions
from .viewer_options import add_view_arguments, view_options_from_args


def _columns(options: ViewOptions) -> dict:
    """The options as manifest columns (the defaults of every row)."""
    return {OPTIONS_BY_NAME[name].column: value for name, value in options.given().items()}


def command_batch(args: argparse.Namespace) -> int:
    from ..dataset import Outputs, mesh_jobs, read_manifest, render_dataset, sphere_views, turntable_views

    if (args.manifest is None) == (not args.meshes):
        raise UsageError("batch: give a MANIFEST (.csv or .jsonl) or --meshes PATTERN, not both")
    if args.workers < 1:
        raise UsageError(f"--workers must be at least 1, got {args.workers}")
    if args.workers != 1 and args.scheduler:
        raise UsageError("--workers starts a local cluster, --scheduler uses an existing one: give one of them")
    if args.chunk < 1:
        raise UsageError(f"--chunk must be at least 1, got {args.chunk}")
    outputs = Outputs(
        color=args.color, depth=args.depth, normals=args.normals, ids=args.ids, compress_level=args.compression
    )
    options = view_options_from_args(args)
    if args.manifest is not None:
        if args.views is not None or args.layout is not None or args.elevation is not None:
            raise UsageError("--views, --layout and --elevation go with --meshes; a manifest gives each job's view")
        # The flags are defaults: a manifest row's own columns win.
        jobs = read_manifest(args.manifest, outputs, _columns(options))
    else:
        count = 24 if args.views is None else args.views
        if args.elevation is not None and options.camera_elevation is not None:
            raise UsageError("--elevation and --camera-elevation-angle say the same; give one")
        elevation = args.elevation if args.elevation is not None else options.camera_elevation
        if args.layout == "sphere":
            if args.elevation is not None:
                raise UsageError("--elevation goes with --layout turntable")
            views = sphere_views(count)
        else:
            views = turntable_views(count, elevation)
        # Every view turns on from the flags' camera: --camera-azimuth-angle 30 --views 4 is
        # 30°, 120°, 210°, 300°, each the picture of `render --camera-azimuth-angle A`.
        for view in views:
            view["azimuth"] += options.camera_azimuth or 0.0
            if args.layout == "sphere" and options.camera_elevation:
                view["elevation"] += options.camera_elevation
        defaults = _columns(replace(options, camera_azimuth=None, camera_elevation=None))
        jobs = mesh_jobs(args.meshes, views, outputs, defaults)
    show_progress = not args.quiet and sys.stderr.isatty()
    if args.scheduler:
        # This process is ours: Dask's client-side warnings (a worker lost, keys rescheduled)
        # would break the progress bar; what matters reaches report.json and the summary.
        import logging

        logging.getLogger("distributed").setLevel(logging.CRITICAL)
    result = render_dataset(
        jobs,
        args.output,
        workers=args.workers,
        scheduler=args.scheduler,
        chunk_size=args.chunk,
        progress=show_progress,
        adapter=args.adapter,
    )
    if result.failed:
        for job_id, error in list(result.failed.items())[:10]:
            print(f"wgpu-shading: failed {job_id}: {error}", file=sys.stderr)
        more = len(result.failed) - 10
        print(
            f"wgpu-shading: {len(result.failed)} job(s) failed{f' ({more} more not shown)' if more > 0 else ''}; "
            f"all are listed in {args.output}/report.json",
            file=sys.stderr,
        )
    if not args.quiet:
        print(f"{result.summary()} → {args.output}")
    return 1 if result.failed else 0

def add_batch(commands, gpu: argparse.ArgumentParser) -> None:
    batch = commands.add_parser(
        "batch",
        parents=[gpu],
        help="render many meshes × views to a dataset folder (resumable; Dask for more workers)",
        description="Render a manifest (CSV or JSON Lines, one job a row) or --meshes × --views into OUTPUT, "
        "one folder per mesh, with cameras.json and report.json. A rerun skips jobs whose outputs exist "
        "and match their row. Exit status 1 when some jobs failed (see report.json).",
    )
    batch.add_argument("manifest", nargs="?", help="a .csv or .jsonl manifest: a header row (CSV) or one object a line (JSON); one job a row: "
                       "mesh (a file, builtin:NAME or a scene .toml), optional folder, name, id, and any view option's "
                       "column (size, material, up, eye, azimuth, elevation, lights, ...: the view flags below without "
                       "the dashes, camera keys as in a scene file)")
    batch.add_argument("-o", "--output", required=True, help="output folder (created)")
    batch.add_argument("--meshes", action="append", metavar="PATTERN", help="mesh files (a glob such as 'dir/*.obj', or builtin:NAME); repeatable")
    batch.add_argument("--views", type=int, help="views per mesh with --meshes (default: 24)")
    batch.add_argument("--layout", choices=["turntable", "sphere"], help="turntable (default): azimuths around the up axis; sphere: spread evenly over the sphere")
    batch.add_argument("--elevation", type=float, help="turntable: turn every view up by DEG, as render's --camera-elevation (default 0: the framed view, 19.3° above the horizon)")
    batch.add_argument("--color", choices=["png", "png16", "none"], default="png", help="colour image: 8-bit PNG (default), 16-bit PNG or none")
    batch.add_argument("--depth", choices=["none", "npy", "png16"], default="none", help="depth: float32 .npy (eye-space Z, inf = background) or 16-bit PNG (0 = background, 1..65535 = near..far)")
    batch.add_argument("--normals", choices=["none", "eye", "world"], default="none", help="surface normals as float32 .npy in eye or world space")
    batch.add_argument("--ids", action="store_true", help="segmentation mask as a 16-bit PNG: 0 = background, k = the k-th (object, part) in scene order (legend in cameras.json)")
    batch.add_argument(
        "--compression", type=int, default=PNG_LEVEL, choices=range(10), metavar="0-9",
        help=f"PNG zlib level (default {PNG_LEVEL}, as render's: a 512² render encodes in ~0.5 ms instead of ~11 ms "
        "at zlib's usual 6, files about a third larger)",
    )
    batch.add_argument("--workers", type=int, default=1, help="1 (default): this process, pipelined; N: a local Dask cluster of N processes")
    batch.add_argument("--scheduler", metavar="ADDRESS", help="run on an existing Dask cluster: tcp://host:port or a scheduler file")
    batch.add_argument("--chunk", type=int, default=16, help="views of one mesh per task (default 16)")
    batch.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no summary")
    add_view_arguments(batch)  # every view option `render` takes: defaults for every job
    batch.set_defaults(handler=command_batch)
