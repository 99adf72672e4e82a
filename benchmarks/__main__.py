"""Run every performance benchmark of issue #7 and print a table of medians and ratios.

    pip install -e '.[bench]'          # the peers (moderngl, pygfx) and matplotlib
    python -m benchmarks               # everything, ~6-10 min on 2 cores
    python -m benchmarks --quick       # smaller and fewer, ~2 min
    python -m benchmarks --only warm,cold

Results: markdown tables on stdout, and in --out (default benchmarks/results/):
results.md, results.json, scaling_triangles.png, scaling_pixels.png.
Absolute times are specific to this machine and its load; the ratios, measured side by
side in one run, are what carries over.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

SECTIONS = ("warm", "breakdown", "cold", "batch", "memory", "scaling", "dataset")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes, fewer rounds (~2 min)")
    parser.add_argument("--only", help=f"comma-separated sections: {', '.join(SECTIONS)}")
    parser.add_argument("--no-pygfx", action="store_true", help="leave pygfx out of the warm table")
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results", help="output folder")
    args = parser.parse_args(argv)
    chosen = SECTIONS if not args.only else tuple(s.strip() for s in args.only.split(","))
    unknown = set(chosen) - set(SECTIONS)
    if unknown:
        parser.error(f"unknown sections: {', '.join(sorted(unknown))}")
    os.environ.setdefault("NODEVICE_SELECT", "1")

    from wgpu_shading import Renderer

    from . import report
    from .measure import machine_description

    renderer = Renderer()
    quick = args.quick
    started = time.perf_counter()
    results: dict[str, object] = {
        "command": "python -m benchmarks" + (" --quick" if quick else "") + (f" --only {args.only}" if args.only else ""),
        "machine": machine_description(),
        "load_average_at_start": os.getloadavg(),
    }
    print(f"# wgpu-shading performance\n\nmachine: {results['machine']}\n", flush=True)

    if "warm" in chosen:
        from .warm import run_warm

        sizes = (512,) if quick else (512, 1024)
        rows = run_warm(renderer, sizes, rounds=2 if quick else 7, frames=2 if quick else 3, pygfx=not args.no_pygfx)
        results["warm"] = rows
        print(report.warm_table(rows), flush=True)
    if "breakdown" in chosen:
        from .warm import run_breakdown

        rows = run_breakdown(renderer, 512, rounds=2 if quick else 8, frames=2 if quick else 3)
        results["breakdown"] = rows
        print(report.breakdown_table(rows), flush=True)
    if "cold" in chosen:
        from .cold import run_cold

        cold = run_cold(rounds=4 if quick else 10)
        results["cold"] = cold
        print(report.cold_table(cold), flush=True)
    if "batch" in chosen:
        from .batch import run_batch

        batch = run_batch(renderer, frames=60 if quick else 360, size=512, passes=2)
        results["batch"] = batch
        print(report.batch_table(batch), flush=True)
    if "memory" in chosen:
        from .memory import run_memory

        memory = run_memory(1_300_000, 512, runs=1 if quick else 3)
        results["memory"] = memory
        print(report.memory_table(memory), flush=True)
    if "scaling" in chosen:
        from .scaling import pixel_curve, triangle_curve

        counts = (10_000, 100_000, 1_000_000) if quick else (10_000, 30_000, 100_000, 300_000, 1_000_000, 3_000_000)
        sides = (256, 512, 1024) if quick else (128, 256, 512, 1024, 2048)
        rounds, frames = (2, 1) if quick else (4, 2)
        results["scaling"] = {
            "triangles": triangle_curve(renderer, counts, rounds=rounds, frames=frames),
            "pixels": pixel_curve(renderer, sides, rounds=rounds, frames=frames),
        }
        print(report.scaling_table(results["scaling"]), flush=True)

    if "dataset" in chosen:
        from .dataset import default_meshes, run_dataset_benchmark, table

        views, sizes = (12, (256,)) if quick else (48, (256, 512))
        dataset = run_dataset_benchmark(renderer, default_meshes(), views, sizes, passes=1 if quick else 3)
        results["dataset"] = dataset
        print("\n## Dataset rendering (benchmarks/dataset.py)\n\n" + table(dataset), flush=True)

    elapsed = time.perf_counter() - started
    results["seconds"] = elapsed
    results["load_average_at_end"] = os.getloadavg()
    args.out.mkdir(parents=True, exist_ok=True)
    markdown = report.everything(results)
    (args.out / "results.md").write_text(markdown)
    (args.out / "results.json").write_text(json.dumps(_plain(results), indent=1))
    if "scaling" in results:
        report.plot_scaling(results["scaling"], args.out)
    print(f"\n{elapsed / 60:.1f} min; load average {results['load_average_at_start']} → "
          f"{results['load_average_at_end']}; written to {args.out}", file=sys.stderr)
    return 0


def _plain(value: object) -> object:
    """Dataclasses and tuples to JSON-friendly values."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


if __name__ == "__main__":
    sys.exit(main())
