"""The accuracy study's results as Markdown: the number format, the tables (every point, the
grid per size, the cheapest settings, Blinn-Phong against Phong, GPU against the same-mesh
reference) and the `headline` sentence the docs lead with."""

from __future__ import annotations

import math
from typing import Iterable, Sequence

import numpy as np

from .results import Study, cheapest


def format_number(value, digits: int = 2) -> str:
    if value == "" or value is None:
        return ""
    if isinstance(value, (int, np.integer)):
        return f"{value:,}"
    if not math.isfinite(value):
        return "–"
    if value == 0:
        return "0"
    if abs(value) < 0.01:
        return f"{value:.1g}"
    if abs(value) >= 100:
        return f"{value:,.0f}"
    if abs(value) >= 10:
        return f"{value:.1f}"
    return f"{value:.{digits}f}"


def _row_model(row: dict) -> str:
    return "phong" if row["reflection"] == "phong" else f"blinn-phong k={row['k_blinn']:g}"


def markdown_full_table(rows: Sequence[dict]) -> str:
    """Every row of the sweep (what `bench accuracy` writes to table.md)."""
    header = (
        "| size | triangles | frequency | reflection | frame ms | RMSE | p99.9 | max | peak | highlight | covered | vs Phong p99.9 | same-mesh p99.9 | same-mesh ≤ 1/255 |\n"
        "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    )
    lines = []
    for r in rows:
        within = "–" if not math.isfinite(r["same_within"]) else f"{r['same_within']:.2%}"
        lines.append(
            f"| {r['size']} | {r['triangles']:,} | {r['frequency']} | {_row_model(r)} | {format_number(r['time_ms'])} | "
            f"{format_number(r['rmse'])} | {format_number(r['p999'])} | {format_number(r['max'])} | {format_number(r['peak'])} | {format_number(r['highlight'])} | {r['coverage']:.1%} | "
            f"{format_number(r['phong_p999'])} | {format_number(r['same_p999'])} | {within} |"
        )
    return header + "\n".join(lines) + "\n"


def markdown_grid(rows: Sequence[dict], size: int, reflection: str = "phong", k_blinn="") -> str:
    """One line per tessellation, frame time and errors (vs the analytic truth) per frequency."""
    chosen = [r for r in rows if r["size"] == size and r["reflection"] == reflection and (reflection == "phong" or r["k_blinn"] == k_blinn)]
    frequencies = list(dict.fromkeys(r["frequency"] for r in chosen))
    header = "| triangles | " + " | ".join(f"{f} ms | RMSE | p99.9 | max | peak" for f in frequencies) + " |\n"
    header += "|---:|" + "---:|" * (5 * len(frequencies)) + "\n"
    lines = []
    for requested in dict.fromkeys(r["requested"] for r in chosen):
        cells = []
        triangles = None
        for f in frequencies:
            match = [r for r in chosen if r["requested"] == requested and r["frequency"] == f]
            if not match:
                cells += [""] * 5
                continue
            r = match[0]
            triangles = r["triangles"]
            cells += [format_number(r["time_ms"]), format_number(r["rmse"]), format_number(r["p999"]), format_number(r["max"]), format_number(r["peak"])]
        lines.append(f"| {triangles:,} | " + " | ".join(cells) + " |")
    return header + "\n".join(lines) + "\n"


def markdown_cheapest(rows: Sequence[dict], sizes: Iterable[int], budgets=(0.5, 1.0, 2.0, 4.0, 8.0)) -> str:
    header = "| size | budget (p99.9 vs Phong truth) | cheapest setting | triangles | frame ms | p99.9 | peak | next cheapest |\n|---:|---:|---|---:|---:|---:|---:|---|\n"
    lines = []
    for size in sizes:
        for budget in budgets:
            best = cheapest(rows, size, budget)
            if best is None:
                lines.append(f"| {size} | {budget:g}/255 | none in the sweep | | | | | |")
                continue
            others = [r for r in rows if r["size"] == size and r["phong_p999"] <= budget and r is not best and math.isfinite(r["time_ms"])]
            runner = min(others, key=lambda r: r["time_ms"]) if others else None
            runner_text = f"{runner['frequency']} / {_row_model(runner)}, {runner['triangles']:,} tri, {format_number(runner['time_ms'])} ms" if runner else ""
            lines.append(
                f"| {size} | {budget:g}/255 | **{best['frequency']} / {_row_model(best)}** | {best['triangles']:,} | "
                f"{format_number(best['time_ms'])} | {format_number(best['phong_p999'])} | {format_number(best['phong_peak'])} | {runner_text} |"
            )
    return header + "\n".join(lines) + "\n"


def markdown_blinn(blinn: Sequence[dict], frequencies: Sequence[str]) -> str:
    header = (
        "| k_blinn | RMSE | p99.9 | max | at Phong's peak | "
        + " | ".join(f"time Blinn/Phong ({f})" for f in frequencies)
        + " |\n|---:|---:|---:|---:|---:|" + "---:|" * len(frequencies) + "\n"
    )
    lines = []
    best = [b for b in blinn if b.get("best")]
    for b in (b for b in blinn if not b.get("best")):
        ratios = " | ".join(f"{b[f'time_ratio_{f}']:.2f}" if math.isfinite(b[f"time_ratio_{f}"]) else "–" for f in frequencies)
        lines.append(f"| {b['k_blinn']:g} | {format_number(b['rmse'])} | {format_number(b['p999'])} | {format_number(b['max'])} | {format_number(b['peak'])} | {ratios} |")
    text = header + "\n".join(lines) + "\n"
    for b in best:
        text += (
            f"\nThe k_blinn closest to Phong reflection in this scene (least RMSE on the exact sphere, "
            f"{b['size']}×{b['size']}) is **{b['k_blinn']:.2f}**, with RMSE {format_number(b['rmse'])}/255.\n"
        )
    return text


def markdown_same_mesh(rows: Sequence[dict]) -> str:
    """Per frequency, the worst agreement of the GPU with the same-mesh float64 reference."""
    header = "| frequency | points | worst p99.9 | worst max | worst share ≤ 1/255 | all ≥ 99.9 % |\n|---|---:|---:|---:|---:|---|\n"
    lines = []
    for f in dict.fromkeys(r["frequency"] for r in rows):
        chosen = [r for r in rows if r["frequency"] == f and r["same_pixels"] > 0]
        if not chosen:
            continue
        worst_within = min(r["same_within"] for r in chosen)
        lines.append(
            f"| {f} | {len(chosen)} | {format_number(max(r['same_p999'] for r in chosen))} | {format_number(max(r['same_max'] for r in chosen))} | "
            f"{worst_within:.3%} | {'yes' if worst_within >= 0.999 else '**no**'} |"
        )
    return header + "\n".join(lines) + "\n"


def headline(study: Study, budget: float = 1.0) -> str:
    """The sentence the docs lead with: the cheapest setting for the budget at the largest size."""
    size = max(study.config.sizes)
    best = cheapest(study.rows, size, budget)
    if best is None:
        return f"For an error budget of {budget:g}/255 at {size}×{size}, no setting in the sweep is good enough."
    phong_same = [r for r in study.rows if r["size"] == size and r["requested"] == best["requested"] and r["frequency"] == "phong" and r["reflection"] == "phong"]
    fastest_phong = cheapest([r for r in study.rows if r["frequency"] == "phong" and r["reflection"] == "phong"], size, budget)
    text = (
        f"For an error budget of {budget:g}/255 (99.9 % of the pixels) at {size}×{size}, the cheapest setting measured is "
        f"**{best['frequency']} shading with {_row_model(best)} reflection on {best['triangles']:,} triangles**: "
        f"{format_number(best['time_ms'])} ms per frame, p99.9 error {format_number(best['phong_p999'])}/255"
    )
    if phong_same and phong_same[0] is not best:
        text += f" (Phong shading of the same mesh: {format_number(phong_same[0]['time_ms'])} ms)"
    if fastest_phong and fastest_phong is not best:
        text += f"; the cheapest Phong-shading setting within budget is {fastest_phong['triangles']:,} triangles at {format_number(fastest_phong['time_ms'])} ms"
    others = []
    for frequency in study.config.frequencies:
        if frequency == best["frequency"]:
            continue
        own = cheapest([r for r in study.rows if r["frequency"] == frequency and r["reflection"] == "phong"], size, budget)
        if own is None:
            others.append(f"{frequency} shading does not get there even with {max(r['triangles'] for r in study.rows):,} triangles")
        else:
            others.append(f"{frequency} shading needs {own['triangles']:,} triangles ({format_number(own['time_ms'])} ms)")
    if others:
        text += ". With Phong reflection, " + "; ".join(others)
    return text + "."
