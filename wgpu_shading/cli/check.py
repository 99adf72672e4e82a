"""`check`: render and compare with a reference image (golden-image test)."""

from __future__ import annotations

import argparse
from pathlib import Path

from .arguments import add_scene_arguments, fraction, scene_from_args, level_255

EXIT_MISMATCH = 1


def command_check(args: argparse.Namespace) -> int:
    """Render, compare with the reference and print the metrics: exit 0 on a match, 1 on a
    mismatch (actual, expected and diff images written), 2 on a usage error."""
    from ..testing.golden import GoldenError, Tolerance, check_image
    from ..render.renderer import Renderer

    reference = Path(args.ref)
    if reference.suffix.lower() != ".png":
        raise GoldenError(f"--ref {args.ref!r}: the reference must be a .png file")
    if args.output_dir is not None and not Path(args.output_dir).is_dir():
        raise GoldenError(f"--output-dir {args.output_dir!r} is not an existing folder")
    if args.update and not reference.parent.exists():
        raise GoldenError(f"--ref {args.ref!r}: folder {str(reference.parent)!r} does not exist")
    from ..assets.image_writers import check_folder_writable

    # Where this run may write (the reference with --update, the failure images), before rendering.
    failure_folder = Path(args.output_dir) if args.output_dir is not None else reference.parent
    if failure_folder.is_dir():
        check_folder_writable(failure_folder, "--output-dir" if args.output_dir is not None else "--ref folder")
    if args.report is not None:
        from ..assets.atomic import check_target

        if Path(args.report).suffix.lower() not in (".html", ".htm"):
            raise GoldenError(f"--report {args.report!r}: the report is an HTML page; name it .html")
        check_target(args.report, "--report", GoldenError)
    tolerance = Tolerance(
        threshold=args.threshold,
        max_fraction=args.max_fraction,
        max_difference=args.max_difference,
        flip_mean=args.flip,
    )
    scene = scene_from_args(args)
    if not args.update and not reference.exists():
        raise GoldenError(f"reference {args.ref!r} does not exist; run again with --update to create it")
    image = Renderer(adapter=args.adapter).render(scene)
    result = check_image(
        image, reference, tolerance, update=args.update, output_dir=args.output_dir, amplification=args.amplify
    )
    if not args.quiet or not result.passed:
        print(result.report())
    if args.report is not None:
        write_check_report(args, result)
        if not args.quiet or not result.passed:
            print(f"report: {args.report}")
    return 0 if result.passed else EXIT_MISMATCH


def write_check_report(args: argparse.Namespace, result) -> None:
    """The golden report page of this one check; its accept command is this command line
    with --update (the reference file is rewritten by it)."""
    import shlex

    from ..testing.report import entry_for_result, write_report

    typed = ["wgpu-shading", *args.command_line]
    accept = shlex.join(typed if "--update" in typed else [*typed, "--update"])
    entry = entry_for_result(f"check {args.input}", result, accept)
    write_report(args.report, [entry], title="Golden-image check", context=shlex.join(typed))



def add_check(commands, gpu: argparse.ArgumentParser) -> None:
    check = commands.add_parser(
        "check",
        parents=[gpu],
        help="render and compare with a reference image (golden-image test)",
        description=(
            "Render a scene and compare it with a reference PNG. Prints the metrics; exits 0 when they "
            "match, 1 when they differ (writes NAME.actual.png, NAME.expected.png and NAME.diff.png next "
            "to the reference or in --output-dir), 2 on a usage error. --update writes a missing or "
            "differing reference. "
            "How it compares: a pixel differs when one of its channels differs by more than --threshold/255 "
            "(lavapipe and GPUs round a few values differently, so 0 is too strict); the images match when "
            "at most --max-fraction of the pixels differ, no channel by more than --max-difference (if given) "
            "and the mean FLIP error is at most --flip (if given). The diff image shows where they differ. "
            "In pytest the same check is the assert_golden fixture of the wgpu-shading plugin "
            "(`pytest --update-golden` writes references)."
        ),
    )
    if not isinstance(check, argparse.ArgumentParser):
        return  # another command runs: `check` is registered by name only (main.build_parser)
    # The defaults only; the comparison code (numpy image metrics, diagnosis) is imported
    # by `check` alone, when it runs.
    from ..testing.images import DEFAULT_AMPLIFICATION
    from ..testing.tolerance import Tolerance

    defaults = Tolerance()
    add_scene_arguments(check)
    check.add_argument("--ref", required=True, metavar="REFERENCE.png", help="the reference image")
    check.add_argument("--update", action="store_true", help="write the reference when it is missing or differs")
    check.add_argument(
        "--threshold", type=level_255, default=defaults.threshold, metavar="N",
        help=f"a pixel differs when a channel differs by more than N/255 (default {defaults.threshold})",
    )
    check.add_argument(
        "--max-fraction", type=fraction, default=defaults.max_fraction, metavar="F",
        help=f"fraction of pixels allowed to differ, e.g. 0.001 or 0.1%% (default {defaults.max_fraction:g})",
    )
    check.add_argument("--max-difference", type=level_255, metavar="N", help="also fail when any channel differs by more than N/255")
    check.add_argument(
        "--flip", type=float, metavar="MEAN", help="also fail when the mean NVIDIA FLIP error exceeds MEAN (needs flip-evaluator)"
    )
    check.add_argument("--output-dir", metavar="DIR", help="where to write the images of a failure (default: next to the reference)")
    check.add_argument(
        "--amplify", type=float, default=DEFAULT_AMPLIFICATION, metavar="K",
        help="the diff image shows |actual − expected| × K (linear) instead of the default log scale "
        "(1/255 → 32, 8/255 → 101, 64/255 → 192, 255/255 → 255)",
    )
    check.add_argument(
        "--report", metavar="FILE.html",
        help="also write one self-contained HTML page of the result: expected | actual | diff, a slider and blink "
        "comparison, zoom, the metrics against the tolerance, the diagnosis and the command that accepts the image",
    )
    check.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    check.set_defaults(handler=command_check)
