"""Measure what the golden-image tolerance has to absorb, and what it catches.

    python benchmarks/golden_noise.py                 # both parts, Markdown tables on stdout
    python benchmarks/golden_noise.py --noise         # only part 1
    python benchmarks/golden_noise.py --defects       # only part 2
    python benchmarks/golden_noise.py --smoke         # does it still run? seconds, numbers mean nothing

Part 1, noise: renders every case of the golden suite (tests/golden) in fresh processes
under settings that change lavapipe's generated code the way another machine or Mesa
build would, and compares each image with its reference:

    run-to-run            the same settings again (3 processes)
    LP_NUM_THREADS=1 / 0  one rasterizer thread / rasterize in the calling thread
    LP_NATIVE_VECTOR_WIDTH=128                  SSE-width vectors instead of AVX2's 256
    GALLIUM_OVERRIDE_CPU_CAPS=sse4.1 / sse2     a CPU without AVX/AVX2/FMA/F16C; an SSE2-only one
    GALLIVM_PERF=brilinear / rho_approx / no_quad_lod / no_aos_sampling
                          texture-sampling shortcuts (older Mesa releases had some on by
                          default): stand-ins for a Mesa release that samples differently
    GALLIVM_PERF=nopt     LLVM without optimization passes
    all at once           sse2 CPU caps with both texture shortcuts

Only one Mesa (the machine's) can be installed here, so a different Mesa release is
emulated by these switches, not measured.

Part 2, defects: for a few golden cases, changes the scene by a growing amount (moves the
light, dims the specular color, changes the light color, shininess or ambient, moves the
object by a fraction of a pixel) and reports the smallest amount the default tolerance
catches, with the metrics at that amount.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "golden"))

from golden_cases import cases  # noqa: E402

from wgpu_shading.testing.golden import Tolerance, compare, flip_mean, read_image  # noqa: E402

VARIANTS: list[tuple[str, dict[str, str]]] = [
    ("run-to-run #1", {}),
    ("run-to-run #2", {}),
    ("run-to-run #3", {}),
    ("LP_NUM_THREADS=1", {"LP_NUM_THREADS": "1"}),
    ("LP_NUM_THREADS=0", {"LP_NUM_THREADS": "0"}),
    ("LP_NATIVE_VECTOR_WIDTH=128", {"LP_NATIVE_VECTOR_WIDTH": "128"}),
    ("CPU caps sse4.1 (no AVX, FMA)", {"GALLIUM_OVERRIDE_CPU_CAPS": "sse4.1"}),
    ("CPU caps sse2", {"GALLIUM_OVERRIDE_CPU_CAPS": "sse2"}),
    ("GALLIVM_PERF=brilinear", {"GALLIVM_PERF": "brilinear"}),
    ("GALLIVM_PERF=rho_approx", {"GALLIVM_PERF": "rho_approx"}),
    ("GALLIVM_PERF=no_quad_lod", {"GALLIVM_PERF": "no_quad_lod"}),
    ("GALLIVM_PERF=no_aos_sampling", {"GALLIVM_PERF": "no_aos_sampling"}),
    ("GALLIVM_PERF=nopt", {"GALLIVM_PERF": "nopt"}),
    ("all at once: sse2, brilinear, rho_approx", {"GALLIUM_OVERRIDE_CPU_CAPS": "sse2", "GALLIVM_PERF": "brilinear,rho_approx"}),
]
_ENV_KEYS = ("LP_NUM_THREADS", "LP_NATIVE_VECTOR_WIDTH", "GALLIUM_OVERRIDE_CPU_CAPS", "GALLIVM_PERF")


# --------------------------------------------------------------------------- part 1: noise


# --smoke: one noise setting over two cases (one textured), and every defect at its
# largest amount on one case: every code path once, in seconds.
SMOKE_CASES = ["gold_torus_phong", "checker_sphere_modulate"]


def chosen_cases(names: list[str] | None = None):
    """The golden cases, or those named (in the order given)."""
    by_name = {case.name: case for case in cases()}
    if names is None:
        return list(by_name.values())
    unknown = [name for name in names if name not in by_name]
    if unknown:
        raise SystemExit(f"unknown golden cases: {', '.join(unknown)} (see tests/golden/cases.toml)")
    return [by_name[name] for name in names]


def render_all(folder: Path, names: list[str] | None = None) -> None:
    """(Subprocess) render every case (or those named) into folder/NAME.npy, and the adapter's name."""
    from wgpu_shading import Renderer

    renderer = Renderer()
    (folder / "adapter.txt").write_text(renderer.device.adapter.info.get("device", "?"))
    for case in chosen_cases(names):
        np.save(folder / f"{case.name}.npy", renderer.render(case.load()))


def noise(variants: list[tuple[str, dict[str, str]]] = VARIANTS, names: list[str] | None = None) -> str:
    tolerance = Tolerance()
    all_cases = chosen_cases(names)
    rows = []
    textured = {c.name for c in all_cases if "texture" in c.name or "checker" in c.name}
    only = ["--cases", ",".join(names)] if names is not None else []
    with tempfile.TemporaryDirectory() as tmp:
        for label, env in variants:
            folder = Path(tmp) / str(len(rows))
            folder.mkdir()
            environment = {k: v for k, v in os.environ.items() if k not in _ENV_KEYS} | env
            crashes = 0
            # LP_NATIVE_VECTOR_WIDTH=128 on an AVX2 CPU sometimes aborts inside Mesa 22.3.6
            # ("malloc(): invalid next size"): count such crashes and try again.
            while subprocess.run(
                [sys.executable, __file__, "--render-to", str(folder), *only], env=environment,
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            ).returncode != 0:
                crashes += 1
                if crashes == 5:
                    raise RuntimeError(f"{label}: the renderer crashed 5 times")
            if crashes:
                label += f" ({crashes} crash{'es' if crashes > 1 else ''} retried)"
            worst = {"max": 0, "p999": 0, "fraction": 0.0, "over4": 0, "flip": 0.0}
            differing, failing, worst_case = 0, [], "-"
            for case in all_cases:
                actual = np.load(folder / f"{case.name}.npy")
                expected = read_image(case.reference)
                result = compare(actual, expected, tolerance)
                delta = np.abs(actual.astype(int) - expected.astype(int)).max(axis=2)
                if result.max_difference:
                    differing += 1
                if result.max_difference > worst["max"]:
                    worst_case = case.name
                worst["max"] = max(worst["max"], result.max_difference)
                worst["p999"] = max(worst["p999"], result.percentile)
                worst["fraction"] = max(worst["fraction"], result.over_fraction)
                worst["over4"] = max(worst["over4"], int((delta > 4).sum()))
                if result.max_difference:
                    worst["flip"] = max(worst["flip"], flip_mean(actual, expected))
                if not result.passed:
                    failing.append(case.name)
            adapter = (folder / "adapter.txt").read_text()
            rows.append(
                f"| {label} | {adapter.split('(')[-1].rstrip(')')} | {differing}/{len(all_cases)} | {worst['max']} ({worst_case}) "
                f"| {worst['p999']} | {worst['over4']} | {100 * worst['fraction']:.3f} % | "
                f"{worst['flip']:.5f} | {', '.join(failing) if failing else 'none'} |"
            )
            print(f"  measured {label}", file=sys.stderr)
    header = (
        f"Noise: {len(all_cases)} golden cases against their references ({len(textured)} textured)\n\n"
        "| setting | vectors | cases not bit-identical | max difference /255 (case) | worst 99.9th percentile | "
        "most pixels > 4/255 in one case | worst fraction > 8/255 | worst FLIP mean | cases failing the defaults |\n"
        "|---|---|---|---|---|---|---|---|---|"
    )
    return header + "\n" + "\n".join(rows)


# --------------------------------------------------------------------------- part 2: defects


def _rotate_y(vector, degrees: float, about=(0.0, 0.0, 0.0)):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    x, y, z = (vector[i] - about[i] for i in range(3))
    return (c * x + s * z + about[0], y + about[1], -s * x + c * z + about[2])


def _light(scene, **changes):
    return replace(scene, lights=(replace(scene.lights[0], **changes),) + tuple(scene.lights[1:]))


def _materials(scene, change):
    return replace(scene, objects=tuple(replace(o, material=change(o.material)) for o in scene.objects))


def _move_light(scene, degrees):
    light = scene.lights[0]
    target = scene.camera.target
    if hasattr(light, "position"):
        return _light(scene, position=_rotate_y(light.position, degrees, target))
    return _light(scene, direction=_rotate_y(light.direction, degrees))


def _pixel_world(scene) -> float:
    """World size of one pixel at the camera's target distance."""
    camera = scene.camera
    distance = float(np.linalg.norm(np.subtract(camera.eye, camera.target)))
    return 2.0 * distance * math.tan(math.radians(camera.fov_y) / 2.0) / scene.size[1]


def _shift_objects(scene, pixels: float):
    step = pixels * _pixel_world(scene)
    camera = scene.camera
    forward = np.subtract(camera.target, camera.eye)
    right = np.cross(forward, camera.up)
    right = right / np.linalg.norm(right) * step
    return replace(
        scene, objects=tuple(replace(o, translate=tuple(np.add(o.translate, right))) for o in scene.objects)
    )


def _clamp(values):
    return tuple(min(max(v, 0.0), 1.0) for v in values)


DEFECTS = [
    # (name, unit, magnitudes, scene → changed scene)
    ("light moved (rotated about the vertical axis)", "°", [0.1, 0.25, 0.5, 1, 2, 3, 5, 10],
     _move_light),
    ("specular color dimmed", "/255", [1, 2, 4, 6, 8, 12, 16, 24, 32, 64],
     lambda s, n: _materials(s, lambda m: replace(m, specular=_clamp(np.subtract(m.specular[:3], n / 255)) + (m.specular[3],)))),
    ("light's green channel dimmed (diffuse and specular)", "/255", [1, 2, 4, 6, 8, 12, 16, 24, 32, 64],
     lambda s, n: _light(s, diffuse=(s.lights[0].diffuse[0], max(s.lights[0].diffuse[1] - n / 255, 0), *s.lights[0].diffuse[2:]),
                         specular=(s.lights[0].specular[0], max(s.lights[0].specular[1] - n / 255, 0), *s.lights[0].specular[2:]))),
    ("shininess changed", "%", [1, 2, 5, 10, 20, 50],
     lambda s, p: _materials(s, lambda m: replace(m, shininess=m.shininess * (1 + p / 100)))),
    ("global ambient raised", "/255", [2, 4, 8, 16, 32, 48, 64, 96, 128],
     lambda s, n: replace(s, ambient=_clamp(np.add(s.ambient[:3], n / 255)) + (1.0,))),
    ("objects moved sideways", "px", [0.01, 0.02, 0.05, 0.1, 0.25, 0.5, 1.0],
     _shift_objects),
]
DEFECT_CASES = ["gold_torus_phong", "opengl_init_sphere", "light_positional", "checker_sphere_modulate"]


def defects(defect_cases: list[str] = DEFECT_CASES, largest_only: bool = False) -> str:
    """largest_only: try each defect at its largest amount only (the smoke run)."""
    from wgpu_shading import Renderer

    renderer = Renderer()
    tolerance = Tolerance()
    by_name = {case.name: case for case in chosen_cases(defect_cases)}
    lines = [
        "Smallest defects the default tolerance catches (threshold 8/255, 0.1 % of pixels)\n",
        "| defect | " + " | ".join(defect_cases) + " |",
        "|---|" + "---|" * len(defect_cases),
    ]
    for name, unit, magnitudes, change in DEFECTS:
        if largest_only:
            magnitudes = magnitudes[-1:]
        cells = []
        for case_name in defect_cases:
            case = by_name[case_name]
            scene = case.load()
            expected = read_image(case.reference)
            cell = f"not caught up to {magnitudes[-1]}{unit}"
            for magnitude in magnitudes:
                result = compare(renderer.render(change(scene, magnitude)), expected, tolerance)
                if not result.passed:
                    cell = f"{magnitude:g}{unit} ({result.over_count} px, max {result.max_difference})"
                    break
            cells.append(cell)
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    # Whole defects, caught or not, with their metrics.
    lines += ["", "| defect | " + " | ".join(defect_cases) + " |", "|---|" + "---|" * len(defect_cases)]
    whole = [
        ("highlight removed (specular 0)", lambda s, img: renderer.render(_materials(s, lambda m: replace(m, specular=(0, 0, 0, m.specular[3]))))),
        ("image shifted 1 px", lambda s, img: np.roll(img, 1, axis=1)),
        ("red and blue swapped", lambda s, img: img[:, :, [2, 1, 0, 3]]),
    ]
    for name, change in whole:
        cells = []
        for case_name in defect_cases:
            case = by_name[case_name]
            expected = read_image(case.reference)
            actual = change(case.load(), expected)
            result = compare(actual, expected, tolerance)
            verdict = "caught" if not result.passed else "passes"
            cells.append(
                f"{verdict}: {result.over_count} px ({100 * result.over_fraction:.2f} %), max {result.max_difference}, "
                f"FLIP {flip_mean(actual, expected):.4f}"
            )
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--noise", action="store_true", help="only part 1")
    parser.add_argument("--defects", action="store_true", help="only part 2")
    parser.add_argument(
        "--smoke", action="store_true",
        help=f"check that it still runs (seconds): one noise setting on {' and '.join(SMOKE_CASES)}, "
        f"each defect at its largest amount on {SMOKE_CASES[0]}; the numbers mean nothing",
    )
    parser.add_argument("--render-to", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--cases", help=argparse.SUPPRESS)  # with --render-to: only these (comma-separated)
    args = parser.parse_args()
    if args.render_to:
        render_all(args.render_to, args.cases.split(",") if args.cases else None)
        return 0
    both = not args.noise and not args.defects
    if args.noise or both:
        print(noise(VARIANTS[:1], SMOKE_CASES) if args.smoke else noise())
        print()
    if args.defects or both:
        print(defects(SMOKE_CASES[:1], largest_only=True) if args.smoke else defects())
    return 0


if __name__ == "__main__":
    sys.exit(main())
