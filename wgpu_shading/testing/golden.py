"""Golden-image comparison: is a rendered image the same as a stored reference, within a
tolerance that absorbs lavapipe's differences between Mesa versions and CPUs but not a
real change to the picture?

    from wgpu_shading.testing.golden import Tolerance, compare, check_image

    result = compare(actual, expected)                 # two (H, W, 3|4) uint8 arrays
    assert result.passed, result.message               # names what failed

    outcome = check_image(actual, "golden.png")        # reads the PNG; on failure writes
    print(outcome.report())                            # golden.actual/expected/diff.png

The metric (docs/golden-tests.md has the measurements behind the defaults): per channel
absolute difference in units of 1/255. A pixel *differs* when any channel differs by more
than `Tolerance.threshold`; the images match when at most `Tolerance.max_fraction` of the
pixels differ (and, optionally, no channel differs by more than `max_difference`, and the
mean NVIDIA FLIP error is at most `flip_mean`). Every comparison also reports the maximum
difference and where it is, and the 99.9th percentile of the per-pixel difference.

This is the public module: it holds the check against a reference file (`check_image`,
and the images a failure leaves behind) and re-exports the rest, which lives in

    tolerance.py    Tolerance, GoldenError
    images.py       as_rgba8, read_image, write_image, diff_image
    comparison.py   compare → Comparison; flip_mean, flip_error_map
    diagnosis.py    what a difference looks like (shift, swapped channels, highlight, ...)

Pure numpy; imports nothing from the GPU side.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from .comparison import Comparison, compare, flip_error_map, flip_mean
from .diagnosis import CHANNELS
from .images import (
    DEFAULT_AMPLIFICATION,
    as_rgba8,
    diff_image,
    diff_scale_text,
    read_image,
    read_reference,
    with_scale_legend,
    write_image,
)
from .tolerance import GoldenError, Tolerance


# --------------------------------------------------------------------------- check against a file


@dataclass(frozen=True)
class CheckResult:
    """The outcome of `check_image`.

    status: "passed" (matches the reference), "failed" (differs; images written),
            "created" (no reference existed; written with update=True),
            "updated" (differed; rewritten with update=True)
    """

    status: str
    reference: Path
    comparison: Comparison | None = None
    written: tuple[Path, ...] = ()
    diff_scale: str = ""  # how the written diff image maps differences to brightness

    @property
    def passed(self) -> bool:
        return self.status != "failed"

    def report(self) -> str:
        """What a person needs: the verdict, the metrics, what failed, the files written."""
        ref = str(self.reference)
        if self.status == "created":
            return f"created reference {ref}"
        lines = []
        if self.status == "updated" and self.comparison is None:
            lines.append(f"updated reference {ref} (the old one could not be used)")
        elif self.status == "updated":
            lines.append(f"updated reference {ref} (it differed: {self.comparison.summary()})")
        elif self.status == "passed":
            lines.append(f"PASS {ref}: {self.comparison.summary()}")
        else:
            lines.append(f"FAIL {ref}: {self.comparison.summary()}")
            lines += [f"  failed: {f}" for f in self.comparison.failures if not self.comparison.size_mismatch]
            lines += [f"  looks like: {note}" for note in self.comparison.diagnosis]
            if self.written:
                lines.append("  wrote " + ", ".join(str(p) for p in self.written))
            if self.diff_scale:
                lines.append(f"  diff image: {self.diff_scale}")
        return "\n".join(lines)


def failure_paths(reference: str | os.PathLike[str], output_dir: str | os.PathLike[str] | None = None) -> dict[str, Path]:
    """Where `check_image` writes the images of a failure: NAME.actual.png, NAME.expected.png
    and NAME.diff.png next to the reference, or in output_dir."""
    reference = Path(reference)
    folder = Path(output_dir) if output_dir is not None else reference.parent
    stem = reference.stem
    return {kind: folder / f"{stem}.{kind}.png" for kind in ("actual", "expected", "diff")}


def remove_failure_images(reference, output_dir=None) -> None:
    """Delete the images an earlier failure left for this reference (exactly those names)."""
    paths = failure_paths(reference, output_dir)
    flip_path = paths["diff"].with_name(paths["diff"].name.replace(".diff.png", ".flip.png"))
    for path in (*paths.values(), flip_path):
        if path.is_file():
            path.unlink()


def write_failure_images(
    actual, expected, reference, output_dir=None, amplification: float | None = DEFAULT_AMPLIFICATION, flip: bool = False
) -> tuple[Path, ...]:
    """Write actual, expected (when there is one) and the diff (same sizes only; log scale
    unless a linear amplification is given); with flip=True also FLIP's error map as
    NAME.flip.png."""
    paths = failure_paths(reference, output_dir)
    remove_failure_images(reference, output_dir)  # no stale diff from an earlier run
    written = [write_image(paths["actual"], actual)]
    if expected is not None:
        written.append(write_image(paths["expected"], expected))
        if as_rgba8(actual).shape == as_rgba8(expected).shape:
            written.append(
                write_image(
                    paths["diff"],
                    with_scale_legend(diff_image(actual, expected, amplification), amplification),
                    note=diff_scale_text(amplification),
                )
            )
            if flip:
                flip_path = paths["diff"].with_name(paths["diff"].name.replace(".diff.png", ".flip.png"))
                written.append(write_image(flip_path, flip_error_map(actual, expected)))
    return tuple(written)


def check_image(
    actual,
    reference: str | os.PathLike[str],
    tolerance: Tolerance | None = None,
    *,
    update: bool = False,
    output_dir: str | os.PathLike[str] | None = None,
    amplification: float | None = DEFAULT_AMPLIFICATION,
) -> CheckResult:
    """Compare an image with a reference PNG.

    Missing reference: written when update=True, else GoldenError. Mismatch: with
    update=True the reference is rewritten; otherwise NAME.actual.png, NAME.expected.png and
    NAME.diff.png are written next to the reference (or in output_dir) and the result says
    "failed". A reference that matches within the tolerance is never rewritten, so updating
    does not churn files with noise.
    """
    reference = Path(reference)
    actual = as_rgba8(actual, "actual image")
    if reference.suffix.lower() != ".png":
        # Never PNG bytes under a .jpg name, and never a lossy reference.
        raise GoldenError(f"reference {str(reference)!r}: references are 8-bit PNG files; name it .png")
    if not reference.exists():
        if update:
            write_image(reference, actual)
            return CheckResult("created", reference, written=(reference,))
        raise GoldenError(f"reference {str(reference)!r} does not exist; create it with --update (CLI) or --update-golden (pytest)")
    try:
        expected, has_alpha = read_reference(reference)
    except GoldenError:
        if not update:
            raise
        # --update replaces what cannot be compared with (16-bit, JPEG data, damaged).
        remove_failure_images(reference, output_dir)
        write_image(reference, actual)
        return CheckResult("updated", reference, written=(reference,))
    if not has_alpha:
        # An RGB reference says nothing about alpha: compare colour only (a translucent
        # material's alpha would otherwise fail against the file's implied 255).
        actual = actual.copy()
        actual[:, :, 3] = 255
    comparison = compare(actual, expected, tolerance)
    if comparison.passed:
        remove_failure_images(reference, output_dir)
        return CheckResult("passed", reference, comparison)
    if update:
        remove_failure_images(reference, output_dir)
        write_image(reference, actual)
        return CheckResult("updated", reference, comparison, written=(reference,))
    written = write_failure_images(
        actual, expected, reference, output_dir, amplification, flip=comparison.flip_mean is not None
    )
    scale = diff_scale_text(amplification) if any(p.name.endswith(".diff.png") for p in written) else ""
    return CheckResult("failed", reference, comparison, written=written, diff_scale=scale)


__all__: Sequence[str] = (
    "CHANNELS",
    "CheckResult",
    "DEFAULT_AMPLIFICATION",
    "Comparison",
    "GoldenError",
    "Tolerance",
    "as_rgba8",
    "check_image",
    "compare",
    "diff_image",
    "failure_paths",
    "flip_error_map",
    "flip_mean",
    "read_image",
    "read_reference",
    "remove_failure_images",
    "write_failure_images",
    "write_image",
)
