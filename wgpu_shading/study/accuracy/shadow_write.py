"""Writing the shadow study (docs/accuracy.md#shadows): shadows.csv and shadows.json (every
point), shadows.md (the table by setting and what `auto` is), the error-against-cost plot,
and the `<!-- accuracy:shadows-NAME -->` blocks of a Markdown document.

`load_shadow_points` reads shadows.json back: tests/test_shadow_study.py checks that the
renderer's `auto` (scene/shadows.py AUTO_*) is still the rule's answer for the stored points."""

from __future__ import annotations

import csv
import json
import os
import statistics
from dataclasses import asdict, fields
from pathlib import Path
from typing import Iterable

from ...assets.atomic import atomic_path, atomic_write
from .pictures import require_matplotlib
from .progress import format_duration
from .shadow_choice import ShadowBudget, cases_over_budget, cheapest_shadow_setting, qualifying_settings
from .shadow_sweep import ShadowPoint, ShadowSetting, shadow_table
from .write import update_markdown

POINT_FIELDS = [f.name for f in fields(ShadowPoint) if f.name != "setting"]


def _row(point: ShadowPoint) -> dict:
    row = {name: getattr(point, name) for name in POINT_FIELDS}
    return {**row, **asdict(point.setting)}


def load_shadow_points(path: str | os.PathLike) -> tuple[ShadowPoint, ...]:
    """The points of a shadows.json written by write_shadow_study."""
    document = json.loads(Path(path).read_text(encoding="utf-8"))
    names = {f.name for f in fields(ShadowSetting)}
    return tuple(
        ShadowPoint(setting=ShadowSetting(**{k: row[k] for k in names}), **{k: row[k] for k in POINT_FIELDS})
        for row in document["points"]
    )


def auto_text(points: Iterable[ShadowPoint], budget: ShadowBudget = ShadowBudget()) -> str:
    """Markdown: the setting `auto` is, and how many settings met the budget on every case."""
    points = tuple(points)
    qualifying = qualifying_settings(points, budget)
    chosen = cheapest_shadow_setting(points, budget)
    settings = {p.setting for p in points}
    if chosen is None:
        return "No points.\n"
    over = cases_over_budget(points, budget)[chosen]
    every = ("every case" if not over else
             f"every case but {len(over)} ({', '.join(over)}), the fewest any setting leaves over the budget (open work, docs/shadows.md#auto)")
    return (
        f"**auto = {chosen.map_size} texels, {chosen.filter}, bias {chosen.bias:g} texels**: the cheapest of the "
        f"{len(qualifying)} settings (of {len(settings)}) that met the budget on {every} — no wrong pixel beyond "
        f"2 px of the exact boundary, the boundary within {budget.displacement_p99:g} px (p99), the colour within "
        f"{budget.color_error:g}/255 elsewhere — at a median {qualifying[chosen]:.1f} ms of CPU per frame.\n"
    )


def shadow_plot(points: Iterable[ShadowPoint], path: Path, budget: ShadowBudget = ShadowBudget()) -> Path:
    """Per setting: its worst case's boundary error (p99 px) and its wrong pixels beyond 2 px,
    against its median CPU time per frame; colour the filter, size the map; the settings
    within the budget filled, `auto` ringed."""
    plt = require_matplotlib()
    points = tuple(points)
    by_setting: dict[ShadowSetting, list[ShadowPoint]] = {}
    for point in points:
        by_setting.setdefault(point.setting, []).append(point)
    qualifying = qualifying_settings(points, budget)
    chosen = cheapest_shadow_setting(points, budget)
    colors = {"nearest": "#1f77b4", "bilinear": "#2ca02c", "pcf3": "#ff7f0e", "pcf5": "#d62728"}
    sizes = sorted({s.map_size for s in by_setting})
    figure, axes = plt.subplots(1, 2, figsize=(11.0, 4.6))
    for setting, rows in by_setting.items():
        cost = statistics.median(r.cost_ms for r in rows)
        marker_size = 12 + 60 * sizes.index(setting.map_size) / max(len(sizes) - 1, 1)
        for axis, value in ((axes[0], max(r.displacement_p99 for r in rows)), (axes[1], max(r.wrong_far for r in rows) + 1)):
            axis.scatter([cost], [max(value, 0.05)], s=marker_size, color=colors.get(setting.filter, "grey"),
                         alpha=0.85 if setting in qualifying else 0.25, edgecolors="black" if setting in qualifying else "none")
            if setting == chosen:
                axis.scatter([cost], [max(value, 0.05)], s=marker_size * 3.5, facecolors="none", edgecolors="black", linewidths=1.5)
    axes[0].axhline(budget.displacement_p99, color="red", linestyle="--", linewidth=0.8)
    axes[1].axhline(budget.wrong_far + 1, color="red", linestyle="--", linewidth=0.8)
    for axis, label in ((axes[0], "boundary displacement p99, px (worst case)"), (axes[1], "wrong pixels beyond 2 px + 1 (worst case)")):
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("median CPU time per frame drawing its maps, ms")
        axis.set_ylabel(label)
        axis.grid(True, alpha=0.3)
    for name, color in colors.items():
        axes[0].scatter([], [], color=color, label=name)
    for size in sizes:
        axes[0].scatter([], [], s=12 + 60 * sizes.index(size) / max(len(sizes) - 1, 1), color="grey", label=f"{size} texels")
    axes[0].legend(fontsize=7, ncol=2)
    figure.suptitle("Shadow maps: error against cost (filled: within the budget on every case; ringed: auto)", fontsize=10)
    figure.tight_layout()
    with atomic_path(path) as temporary:
        figure.savefig(temporary, dpi=90, format="png")
    plt.close(figure)
    return path


def write_shadow_study(points: Iterable[ShadowPoint], out_dir: str | os.PathLike, *, markdown: str | os.PathLike | None = None,
                       plot: bool = True, command: str = "", seconds: float = 0.0, environment: dict | None = None) -> list[Path]:
    """shadows.csv, shadows.json, shadows.md and (with matplotlib) shadows.png in out_dir; with
    `markdown`, that file's shadows blocks too."""
    points = tuple(points)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = [_row(p) for p in points]
    with atomic_path(out / "shadows.csv") as temporary, open(temporary, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]) if rows else POINT_FIELDS)
        writer.writeheader()
        writer.writerows({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()} for row in rows)
    chosen = cheapest_shadow_setting(points)
    document = dict(command=command, seconds=seconds, environment=environment or {}, budget=asdict(ShadowBudget()),
                    auto=None if chosen is None else asdict(chosen), points=rows)
    atomic_write(out / "shadows.json", (json.dumps(document, separators=(",", ":")).replace("},{", "},\n{") + "\n").encode())
    written = [out / "shadows.csv", out / "shadows.json"]
    env = environment or {}
    run = (f"Generated by `{command or 'run_shadow_study()'}` in {format_duration(seconds)}"
           + (f" on {env['cpus']} CPU cores ({env['cpu']}), {env['device']}; load average before the run: "
              f"{env['load_before']:.2f}" if env else "") + ".\n")
    blocks = {"shadows-run": run, "shadows-auto": auto_text(points), "shadows-table": shadow_table(points) + "\n"}
    if plot:
        written.append(shadow_plot(points, out / "shadows.png"))
    atomic_write(out / "shadows.md", ("# Shadow maps: accuracy and cost\n\n" + run + "\n" + blocks["shadows-auto"] + "\n"
                                      + blocks["shadows-table"]).encode())
    written.append(out / "shadows.md")
    if markdown is not None:
        markdown = Path(markdown)
        prefix = os.path.relpath(out, markdown.parent).replace(os.sep, "/") + "/"
        blocks["shadows-plot"] = (f"![Shadow maps: error against cost]({prefix}shadows.png)\n" if plot
                                  else "(not plotted: the run had --no-plot)\n")
        update_markdown(markdown, blocks)
        written.append(markdown)
    return written
