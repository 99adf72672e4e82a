"""Markdown tables and plots of the benchmark results."""

from __future__ import annotations

import statistics
from pathlib import Path

MiB = 2**20


def _ms(value: float) -> str:
    return f"{value:,.1f}" if value < 100 else f"{value:,.0f}"


def _ratio(value: float) -> str:
    return f"{value:.2f}×"


def _mark(ok: bool) -> str:
    return "met" if ok else "**missed**"


def _median(timings: dict, name: str) -> float:
    """A contender's median ms; NaN when it did not run (a peer left out: no [bench] extra)."""
    return timings[name].median_ms if name in timings else float("nan")


def _count(n: int) -> str:
    """1,299,600 → 1.3M; 1,980 → 2K."""
    if n >= 1_000_000:
        return f"{n / 1e6:.1f}M"
    return f"{n / 1e3:.0f}K" if n >= 1_000 else str(n)


def warm_table(rows) -> str:
    names = list(rows[0].timings)
    lines = [
        "## Warm frame (render + readback to numpy), median ms per frame",
        "",
        "limit = the same geometry with trivial shaders, every triangle drawn (as moderngl and pygfx draw them); "
        "wgpu-shading culls the triangles a closed surface seen from outside turns away (the torus; "
        "docs/conventions.md, \"Closed surfaces\") and leaves out the clusters the 1.3M sphere turns away.",
        "",
        "| scene | size | " + " | ".join(names) + " | ours ÷ moderngl (≤ 1.0) | ours ÷ pygfx (≤ 0.1) | ours ÷ pygfx lean | ours ÷ limit | CPU: ours ÷ moderngl |",
        "|---|---|" + "---:|" * len(names) + "---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        cells = [_ms(row.timings[n].median_ms) for n in names]
        pygfx = row.ratio("wgpu-shading", "pygfx") if "pygfx" in row.timings else float("nan")
        lean = row.ratio("wgpu-shading", "pygfx lean") if "pygfx lean" in row.timings else float("nan")
        moderngl = row.ratio("wgpu-shading", "moderngl") if "moderngl" in row.timings else float("nan")
        cpu = (
            row.timings["wgpu-shading"].cpu_median_ms / row.timings["moderngl"].cpu_median_ms
            if "moderngl" in row.timings
            else float("nan")
        )
        lines.append(
            f"| {row.scene} | {row.size}² | " + " | ".join(cells)
            + f" | {_ratio(moderngl)} {'✓' if moderngl <= 1.0 else '✗'} | {_ratio(pygfx)} {'✓' if pygfx <= 0.1 else '✗'}"
            + f" | {_ratio(lean)} | {_ratio(row.ratio('wgpu-shading', 'limit'))} | {_ratio(cpu)} |"
        )
    lines.append("")
    lines.append("Interquartile ranges (ms) of the wall times, to show the noise: " + "; ".join(
        f"{row.scene} {row.size}²: " + ", ".join(f"{n} {row.timings[n].spread}" for n in names if row.timings[n].spread)
        for row in rows[:2]
    ) + " …")
    return "\n".join(lines) + "\n"


def breakdown_table(rows) -> str:
    names = list(rows[0].timings)
    lines = [
        f"## Where our frame goes ({rows[0].size}², median ms per frame)",
        "",
        "floor = clear + copy + readback without any draw; limit = same geometry with trivial shaders, every "
        "triangle drawn (gouraud and phong cull the triangles the torus turns away, and leave out the sphere's clusters turned away); "
        "gouraud / phong = wgpu-shading's per-vertex / per-fragment lighting; seed WGSL = the seed's GLSL "
        "Phong shader ported literally to WGSL on our device (moderngl runs the GLSL itself).",
        "",
        "| scene | " + " | ".join(names) + " | geometry (limit − floor) | lighting (phong − limit) | phong ÷ seed WGSL | seed WGSL ÷ moderngl |",
        "|---|" + "---:|" * len(names) + "---:|---:|---:|---:|",
    ]
    for row in rows:
        t = {n: row.timings[n].median_ms for n in names}
        lines.append(
            f"| {row.scene} | " + " | ".join(_ms(t[n]) for n in names)
            + f" | {_ms(t['limit'] - t['floor'])} | {_ms(t['phong'] - t['limit'])}"
            + f" | {_ratio(t['phong'] / t['seed WGSL'])} | {_ratio(t['seed WGSL'] / _median(row.timings, 'moderngl'))} |"
        )
    lines += ["", "CPU ms per frame by thread (all threads of the process; moderngl runs its driver on the main thread):", ""]
    roles = sorted({role for row in rows for per in row.threads.values() for role in per})
    lines.append("| scene | renderer | " + " | ".join(roles) + " | total |")
    lines.append("|---|---|" + "---:|" * len(roles) + "---:|")
    for row in rows:
        for name, per in row.threads.items():
            lines.append(
                f"| {row.scene} | {name} | " + " | ".join(_ms(per.get(role, 0.0)) for role in roles)
                + f" | {_ms(sum(per.values()))} |"
            )
    return "\n".join(lines) + "\n"


def cold_table(cold) -> str:
    reference = cold.median("moderngl script") if "moderngl script" in cold.runs else float("nan")
    reference_cpu = cold.cpu_median("moderngl script") if "moderngl script" in cold.runs else float("nan")
    lines = [
        "## Cold start: process start to PNG on disk (`wgpu-shading render builtin:torus -o t.png`)",
        "",
        "Every variant with Python's bytecode cached (as an installed package has it); CPU = user + system "
        "time of the process, far less disturbed by other processes than wall time.",
        "",
        "| variant | median s | min–max s | ÷ moderngl script | CPU median s | CPU ÷ moderngl script |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name, runs in cold.runs.items():
        cpu = cold.cpu_median(name)
        lines.append(
            f"| {name} | {statistics.median(runs):.3f} | {min(runs):.3f}–{max(runs):.3f} | {_ratio(statistics.median(runs) / reference)} "
            f"| {cpu:.3f} | {_ratio(cpu / reference_cpu)} |"
        )
    cli = cold.median("wgpu-shading CLI")
    same_threads = next((name for name in cold.runs if name.startswith("moderngl script, one BLAS thread")), None)
    lines += [
        "",
        f"Target ≤ 1.0 s: {_mark(cli <= 1.0)} ({cli:.3f} s). Ratio to the minimal moderngl script: {_ratio(cli / reference)} "
        f"wall, {_ratio(cold.cpu_median('wgpu-shading CLI') / reference_cpu)} CPU"
        + (
            f"; to the script given the CLI's one BLAS thread: {_ratio(cli / cold.median(same_threads))} wall, "
            f"{_ratio(cold.cpu_median('wgpu-shading CLI') / cold.cpu_median(same_threads))} CPU."
            if same_threads else "."
        ),
        "",
        "Phases of a cold render (medians, ms; each step as the CLI does it):",
        "",
        "| phase | now | CPU now | prebuilt FFI off (≈ before) |",
        "|---|---:|---:|---:|",
    ]
    for name, seconds in cold.phases.items():
        before = cold.phases_without_ffi.get(name)
        cpu = cold.phases_cpu.get(name, float("nan"))
        lines.append(f"| {name} | {seconds * 1000:.0f} | {cpu * 1000:.0f} | {before * 1000:.0f} |" if before is not None
                     else f"| {name} | {seconds * 1000:.0f} | {cpu * 1000:.0f} | |")
    lines.append(
        f"| **sum** | **{sum(cold.phases.values()) * 1000:.0f}** | **{sum(cold.phases_cpu.values()) * 1000:.0f}** "
        f"| **{sum(cold.phases_without_ffi.values()) * 1000:.0f}** |"
    )
    return "\n".join(lines) + "\n"


def batch_table(batch) -> str:
    naive, many = batch.fps("naive"), batch.fps("render_many")
    speedup = many / naive
    labels = {
        "naive": "naive loop: render() and wait",
        "render_many, one device": "render_many(parallel=1): pipelined",
        "render_many": "render_many(): pipelined, 2 devices (default)",
    }
    lines = [
        f"## Batch: {batch.frames}-view turntable of the {batch.scene} at {batch.size}²",
        "",
        "| mode | frames/s (median pass) | ÷ naive | passes (s) | cores we used | cores idle (whole machine) |",
        "|---|---:|---:|---|---:|---:|",
    ]
    for mode in batch.seconds:
        lines.append(
            f"| {labels.get(mode, mode)} | {batch.fps(mode):.1f} | {_ratio(batch.fps(mode) / naive)} | "
            f"{', '.join(f'{s:.1f}' for s in batch.seconds[mode])} | {batch.cores_used(mode):.2f} | {batch.idle_cores(mode):.2f} |"
        )
    lines += [
        "",
        f"Speed-up {_ratio(speedup)} (target ≥ 2×: {_mark(speedup >= 2.0)}); frames identical to render(): {batch.identical}.",
        "",
        "CPU ms per naive frame by thread: " + ", ".join(f"{k} {v:.1f}" for k, v in batch.threads.items())
        + f" (total {sum(batch.threads.values()):.1f}).",
        f"Ceiling for any overlap on this machine (naive serial chain ÷ (total CPU ÷ cores)): {_ratio(batch.overlap_ceiling)}.",
    ]
    if batch.cli_seconds is not None:
        lines.append(
            f"`wgpu-shading turntable {batch.scene.split()[0]} -o spin.gif --frames {batch.frames} --size {batch.size}` end to end "
            f"(incl. loading the OBJ and GIF encoding): {batch.cli_seconds:.1f} s, {batch.cli_frames_written} frames written, "
            f"{batch.cli_frames_written / batch.cli_seconds:.1f} frames/s."
        )
    return "\n".join(lines) + "\n"


def memory_table(rows, size: int = 512) -> str:
    lines = [
        f"## Memory: peak RSS rendering the {_count(rows[0].triangles)}-triangle sphere at {size}²",
        "",
        "| variant | triangles | mesh arrays MiB | baseline MiB | peak − baseline MiB | ÷ mesh arrays (< 3) "
        "| each run ÷ mesh arrays | ours (mesh + GPU copy) ÷ mesh arrays |",
        "|---|---:|---:|---:|---:|---:|---|---:|",
    ]
    for row in rows:
        ratio = row.peak_over_baseline_in_meshes
        runs = ", ".join(f"{(peak - row.baseline) / row.mesh_bytes:.2f}" for peak in row.peaks)
        lines.append(
            f"| {row.label} | {row.triangles:,} | {row.mesh_bytes / MiB:.1f} | {row.baseline / MiB:.0f} | "
            f"{(row.peak - row.baseline) / MiB:.0f} | {_ratio(ratio)} {'✓' if ratio < 3 else '✗'} | {runs} | "
            f"{_ratio(row.ours_in_meshes)} |"
        )
    return "\n".join(lines) + "\n"


def file_memory_table(rows) -> str:
    """benchmarks/memory.py's large mesh files: load, then load and render, in mesh arrays."""
    from .memory import FILE_FORMATS

    rows = rows if isinstance(rows, list) else [rows]  # (results of runs before the PLY row: one STL row)
    lines = [
        f"## Memory: a {_count(rows[0].triangles)}-triangle mesh file loaded and rendered",
        "",
        "Peak RSS above the baseline (start-up, device and a small render), in the mesh's arrays "
        "(positions + normals + indices); wall / CPU seconds of each step.",
        "",
        "| file | MiB | triangles | vertices | mesh arrays MiB | baseline MiB | load peak ÷ mesh arrays "
        "| load + render peak ÷ mesh arrays (< 3) | load s (CPU) | render s (CPU) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        load, both = row.in_meshes(row.load_peak), row.in_meshes(row.peak)
        what = FILE_FORMATS[getattr(row, "file_format", "stl")][0]
        lines.append(
            f"| {what} | {row.file_bytes / MiB:,.0f} | {row.triangles:,} | {row.vertices:,} | {row.mesh_bytes / MiB:.0f} "
            f"| {row.baseline / MiB:.0f} | {_ratio(load)} | {_ratio(both)} {'✓' if both < 3 else '✗'} "
            f"| {row.load_seconds:.1f} ({row.load_cpu_seconds:.1f}) | {row.render_seconds:.1f} ({row.render_cpu_seconds:.1f}) |"
        )
    return "\n".join(lines + [""])


def scaling_table(scaling, sphere_size: int = 512, torus: str = "10K") -> str:
    lines = ["## Scaling (median ms per frame)", ""]
    for key, unit in (("triangles", f"triangles (sphere, {sphere_size}²)"), ("pixels", f"pixels (torus {torus})")):
        points = scaling[key]
        names = list(points[0].timings)
        lines += [f"| {unit} | " + " | ".join(names) + " | ours ÷ moderngl | CPU: ours ÷ moderngl |", "|---:|" + "---:|" * (len(names) + 2)]
        for point in points:
            t = {n: point.timings[n].median_ms for n in names}
            ratio = t["wgpu-shading"] / _median(point.timings, "moderngl")
            cpu = (
                point.timings["wgpu-shading"].cpu_median_ms / point.timings["moderngl"].cpu_median_ms
                if "moderngl" in point.timings else float("nan")
            )
            lines.append(f"| {point.x:,} | " + " | ".join(_ms(t[n]) for n in names) + f" | {_ratio(ratio)} | {_ratio(cpu)} |")
        lines.append("")
    return "\n".join(lines)


def plot_scaling(scaling, folder: Path) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # the [bench] extra brings matplotlib; without it, tables only
        return
    for key, label, name in (
        ("triangles", "triangles (UV sphere, 512×512)", "scaling_triangles.png"),
        ("pixels", "pixels (10K-triangle torus, square images)", "scaling_pixels.png"),
    ):
        points = scaling[key]
        figure, axes = plt.subplots(figsize=(6.4, 4.2), dpi=110)
        for peer, style in (("wgpu-shading", "o-"), ("moderngl", "s--"), ("limit", "^:")):
            if peer not in points[0].timings:
                continue
            axes.plot([p.x for p in points], [p.timings[peer].median_ms for p in points], style, label=peer)
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_xlabel(label)
        axes.set_ylabel("warm frame, ms (median)")
        axes.grid(True, which="both", alpha=0.3)
        axes.legend()
        axes.set_title(f"Frame time vs {key}: render + readback on lavapipe / llvmpipe")
        figure.tight_layout()
        figure.savefig(folder / name)
        plt.close(figure)


def everything(results: dict) -> str:
    parts = [f"command: `{results['command']}`", f"machine: {results['machine']}", ""]
    if "warm" in results:
        parts.append(warm_table(results["warm"]))
    if "depth" in results:
        from .depth import depth_table

        parts.append(depth_table(results["depth"]))
    if "breakdown" in results:
        parts.append(breakdown_table(results["breakdown"]))
    if "cold" in results:
        parts.append(cold_table(results["cold"]))
    if "batch" in results:
        parts.append(batch_table(results["batch"]))
    labels = results.get("table_labels", {})  # the smoke run's sizes; the full run's are the defaults
    if "memory" in results:
        parts.append(memory_table(results["memory"], **labels.get("memory", {})))
    if "file_memory" in results:
        parts.append(file_memory_table(results["file_memory"]))
    if "scaling" in results:
        parts.append(scaling_table(results["scaling"], **labels.get("scaling", {})))
    if "dataset" in results:
        from .dataset import table as dataset_table

        parts.append(dataset_table(results["dataset"]))
    if "shadows" in results:
        from .shadows import shadows_table

        parts.append(shadows_table(results["shadows"]))
    if "callgrind" in results:
        from .callgrind import callgrind_table

        parts.append(callgrind_table(results["callgrind"]))
    for text in results.get("scripts", {}).values():  # the standalone benchmarks' own tables
        parts.append(text)
    loads = results.get("section_loads", {})
    if loads:
        parts += [
            "Load average (1 min) over each section, and its wall and CPU time (this process; the "
            "fresh processes and Dask workers a section starts are not in it):",
            "",
            "| section | load at start | load at end | wall s | CPU s |",
            "|---|---:|---:|---:|---:|",
            *(f"| {name} | {start:.1f} | {end:.1f} | {wall:.0f} | {cpu:.0f} |" for name, (start, end, wall, cpu) in loads.items()),
            "",
        ]
    parts.append(
        f"Run time {results['seconds'] / 60:.1f} min; load average (1, 5, 15 min) at start "
        f"{tuple(round(x, 2) for x in results['load_average_at_start'])}, at end "
        f"{tuple(round(x, 2) for x in results['load_average_at_end'])}."
    )
    return "\n".join(parts) + "\n"
