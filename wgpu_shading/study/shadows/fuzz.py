"""Random shadowed scenes held to the exact shadows (docs/shadows.md#random-scenes).

`try_scene(renderer, scene)` renders a scene with and without its shadows and measures the
pair against the float64 ray-cast answer (check.py); `minimise(renderer, scene)` shrinks a
failing scene — fewer lights and objects, scale 1, Phong shading, a perspective camera,
nearest filtering, a smaller image — while it keeps failing, so what is left is the cause.

    python -m wgpu_shading.study.shadows.fuzz --seeds 0:300 --out out/shadow-fuzz

runs seeds 0–299 (random_scenes.py), writes each failure's picture (GPU | exact |
disagreement) and its minimised scene's picture into --out, and a JSON report with every
scene's classes and numbers; it prints the counts by class and exits 1 if a scene failed.
The scenes keep the default (auto) shadow settings, which the guarantees are about;
--map-size and --filter override them for a study.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...scene import Scene, has_shadows
from .check import ShadowReference, ShadowReport, failure_picture, measure_shadows
from .random_scenes import random_shadow_scene


def without_shadows(scene: Scene) -> Scene:
    return replace(scene, lights=tuple(replace(light, shadows=False) for light in scene.lights))


@dataclass(frozen=True)
class Trial:
    """A scene tried: its report, and the images it was measured from."""

    scene: Scene
    report: ShadowReport
    reference: ShadowReference
    image: np.ndarray
    shadowless: np.ndarray

    @property
    def passed(self) -> bool:
        return self.report.passed

    @property
    def worst(self) -> str:
        """The gravest guarantee broken: "wrong far" (a wrong state > 2 px from the exact
        boundary: acne or a leak), "colour", "boundary" (displaced, p99), or "" (none)."""
        report = self.report
        if any(light.wrong_far for light in report.lights):
            return "wrong far"
        if any("colour" in failure for failure in report.failures):
            return "colour"
        return "boundary" if report.failures else ""

    def picture(self) -> np.ndarray:
        return failure_picture(self.reference, self.image, self.shadowless)


def try_scene(renderer, scene: Scene, name: str = "") -> Trial:
    """The scene's GPU shadows measured against the exact ones."""
    image = renderer.render_frame(scene, float32=True).color
    shadowless = renderer.render_frame(without_shadows(scene), float32=True).color
    reference = ShadowReference(scene)
    return Trial(scene, measure_shadows(reference, image, shadowless, name=name), reference, image, shadowless)


def _simpler(scene: Scene):
    """Candidate simplifications of a scene, simplest-making first."""
    for index in range(len(scene.lights)):
        lights = scene.lights[:index] + scene.lights[index + 1:]
        if any(light.shadows for light in lights):
            yield f"without light {index}", replace(scene, lights=lights)
    for index, light in enumerate(scene.lights):
        if light.shadows and sum(l.shadows for l in scene.lights) > 1:
            yield f"light {index} casts none", replace(scene, lights=scene.lights[:index] + (replace(light, shadows=False),) + scene.lights[index + 1:])
    for index in range(len(scene.objects)):
        objects = scene.objects[:index] + scene.objects[index + 1:]
        if objects:
            yield f"without object {index}", replace(scene, objects=objects)
    if scene.shading.frequency != "phong":
        yield "phong shading", replace(scene, shading=replace(scene.shading, frequency="phong"))
    if scene.camera.orthographic:
        yield "perspective camera", replace(scene, camera=replace(scene.camera, projection="perspective", ortho_height=None))
    settings = scene.shadows.resolved()
    if settings.filter != "nearest":
        yield "nearest filter", replace(scene, shadows=replace(scene.shadows, filter="nearest"))
    width, height = scene.size
    if max(width, height) > 128:
        shrink = 128.0 / max(width, height)
        yield "128 px", replace(scene, size=(max(16, round(width * shrink)), max(16, round(height * shrink))))


def _normalised(scene: Scene) -> Scene:
    """The scene at scale 1 when it was scaled (the generator's scales are powers of ten or not)."""
    from .cases import scaled_scene

    extent = max(float(np.abs(np.asarray(o.translate)).max()) for o in scene.objects) or 1.0
    lengths = [float(np.abs(np.asarray(o.scale)).max()) for o in scene.objects]
    scale = float(np.median(lengths)) if lengths else 1.0
    if 0.5 < scale < 2.0 and extent < 1e3:
        return scene
    return scaled_scene(scene, 1.0 / scale)


def minimise(renderer, scene: Scene, *, budget: int = 40, log=None) -> tuple[Scene, list[str]]:
    """The simplest scene found from `scene` that still breaks its gravest guarantee (a
    simpler scene failing otherwise is another story), and the steps taken."""
    steps = []
    kind = try_scene(renderer, scene).worst

    def fails(candidate: Scene) -> bool:
        return try_scene(renderer, candidate).worst == kind

    unscaled = _normalised(scene)
    if unscaled is not scene and fails(unscaled):
        scene, steps = unscaled, ["scale 1"]
    tries = 0
    changed = True
    while changed and tries < budget:
        changed = False
        for what, simpler in _simpler(scene):
            tries += 1
            if not has_shadows(simpler):
                continue
            if fails(simpler):
                scene, changed = simpler, True
                steps.append(what)
                if log:
                    log(f"  minimise: {what}")
                break
            if tries >= budget:
                break
    return scene, steps


def _summary(labels: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in labels.items())


def count_by_class(records: list[dict]) -> dict[str, dict[str, list[int]]]:
    """For each class and value: [scenes tried, scenes failed]."""
    counts: dict[str, dict[str, list[int]]] = {}
    for record in records:
        for key, value in record["labels"].items():
            values = value if isinstance(value, (list, tuple)) else [value]
            for v in set(str(x).split(" ")[0] for x in values):
                entry = counts.setdefault(key, {}).setdefault(v, [0, 0])
                entry[0] += 1
                entry[1] += 0 if record["passed"] else 1
    return counts


def run(renderer, seeds, out: Path, *, minimise_failures: bool = True, settings: dict | None = None, models: bool = True,
        log=print) -> list[dict]:
    """Try every seed's scene (its shadow settings replaced by `settings`' fields when given);
    write failures' pictures and the report into `out`."""
    from ...assets.atomic import atomic_write
    from ...assets.image_writers import write_image

    out.mkdir(parents=True, exist_ok=True)
    records = []
    for seed in seeds:
        drawn = random_shadow_scene(seed, models=models)
        if settings:
            scene = replace(drawn.scene, shadows=replace(drawn.scene.shadows, **settings))
            drawn = replace(drawn, scene=scene, labels={**drawn.labels, **{k.replace("_", " "): str(v) for k, v in settings.items()}})
        trial = try_scene(renderer, drawn.scene, drawn.name)
        record = {"seed": seed, "labels": drawn.labels, "passed": trial.passed, "summary": trial.report.summary(),
                  "failures": trial.report.failures}
        log(("ok  " if trial.passed else "FAIL") + f" {seed}: {trial.report.summary()}")
        if not trial.passed:
            log("     " + _summary(drawn.labels))
            for failure in trial.report.failures:
                log("     " + failure)
            write_image(out / f"{drawn.name}.shadows.png", trial.picture())
            if minimise_failures:
                small, steps = minimise(renderer, drawn.scene, log=log)
                smallest = try_scene(renderer, small, drawn.name + "-min")
                record["minimised"] = {"steps": steps, "summary": smallest.report.summary(), "failures": smallest.report.failures,
                                       "scene": repr(small)}
                write_image(out / f"{drawn.name}-min.shadows.png", smallest.picture())
        records.append(record)
        atomic_write(out / "report.json", json.dumps(records, indent=1, default=str).encode(), "fuzz report")
    return records


def _seeds(text: str) -> range:
    first, _, last = text.partition(":")
    return range(int(first), int(last)) if last else range(int(first), int(first) + 1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Random shadowed scenes against the exact shadows (docs/shadows.md#random-scenes)")
    parser.add_argument("--seeds", default="0:100", help="FIRST:END (END excluded) or one SEED")
    parser.add_argument("--out", default="out/shadow-fuzz", type=Path)
    parser.add_argument("--no-minimise", action="store_true")
    parser.add_argument("--map-size", help="override every scene's shadow-map size (N or auto)")
    parser.add_argument("--filter", help="override every scene's filter")
    parser.add_argument("--no-models", action="store_true", help="draw no real mesh of ../shared/models (a torus instead)")
    args = parser.parse_args(argv)
    from ...render.renderer import Renderer

    renderer = Renderer()
    settings = {}
    if args.map_size:
        settings["map_size"] = args.map_size if args.map_size == "auto" else int(args.map_size)
    if args.filter:
        settings["filter"] = args.filter
    records = run(renderer, _seeds(args.seeds), args.out, minimise_failures=not args.no_minimise, settings=settings,
                  models=not args.no_models)
    failed = [r["seed"] for r in records if not r["passed"]]
    print(f"{len(records)} scenes, {len(failed)} failed: {failed}")
    for key, values in count_by_class(records).items():
        print(f"  {key}: " + ", ".join(f"{v} {n[0]}/{n[1]} failed" for v, n in sorted(values.items())))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
