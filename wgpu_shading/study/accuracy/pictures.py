"""The accuracy study's pictures: the labelled `contact_sheet` (also used by docs/make_images.py),
the seed figure (flat / Gouraud / Phong at three face counts), the error maps with their
log-scale colour bar, and the Pareto plot of error against frame time (matplotlib, optional)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...scene import FREQUENCIES
from .config import AccuracyError
from .results import Study, pareto_front
from .tables import format_number


def require_matplotlib():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        from ...errors import install_hint

        raise AccuracyError(f"the Pareto plot needs matplotlib; {install_hint('plots')} (or pass --no-plot)") from None
    return plt


# Anchors of matplotlib's "inferno" colour map (perceptually uniform, dark = small).
_INFERNO = np.array(
    [
        (0, 0, 4), (40, 11, 84), (101, 21, 110), (159, 42, 99),
        (212, 72, 66), (245, 125, 21), (250, 193, 39), (252, 255, 164),
    ],
    dtype=np.float64,
)
HEAT_RANGE = (0.1, 100.0)  # 1/255 units shown by the error maps (log scale)


def heat_colors(values: np.ndarray, low: float = HEAT_RANGE[0], high: float = HEAT_RANGE[1]) -> np.ndarray:
    """uint8 RGB for errors on a log scale from `low` (black) to `high` (pale yellow)."""
    position = (np.log10(np.clip(values, low, high)) - math.log10(low)) / (math.log10(high) - math.log10(low))
    scaled = position * (len(_INFERNO) - 1)
    index = np.minimum(scaled.astype(int), len(_INFERNO) - 2)
    fraction = (scaled - index)[..., None]
    return np.round(_INFERNO[index] * (1 - fraction) + _INFERNO[index + 1] * fraction).astype(np.uint8)


def contact_sheet(panels: list[list[tuple[str, np.ndarray]]], footer: np.ndarray | None = None) -> np.ndarray:
    """A grid of RGB(A) panels (rows of (label, image), labels may have several lines), each
    labelled underneath, with an optional footer image (a color bar, say)."""
    from PIL import Image, ImageDraw, ImageFont

    height, width = panels[0][0][1].shape[:2]
    lines = max(label.count("\n") + 1 for row in panels for label, _ in row)
    font_size = max(8, min(24, width // 18))  # 14 px under the study's 256-px panels
    line_height = font_size + 3
    label_height = 6 + line_height * lines
    columns = max(len(row) for row in panels)
    footer_height = 0 if footer is None else footer.shape[0] + 8
    sheet = Image.new("RGB", (columns * width, len(panels) * (height + label_height) + footer_height), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    font = ImageFont.load_default(size=font_size)
    for r, row in enumerate(panels):
        for c, (label, image) in enumerate(row):
            x, y = c * width, r * (height + label_height)
            sheet.paste(Image.fromarray(np.ascontiguousarray(image[:, :, :3])), (x, y))
            for k, text in enumerate(label.split("\n")):
                text_width = draw.textlength(text, font=font)
                draw.text((x + (width - text_width) / 2, y + height + 3 + line_height * k), text, fill=(0, 0, 0), font=font)
    if footer is not None:
        sheet.paste(Image.fromarray(footer), ((columns * width - footer.shape[1]) // 2, len(panels) * (height + label_height) + 4))
    return np.asarray(sheet)


def seed_figure(study: Study) -> np.ndarray:
    """The classic 3×3 figure (docs/conventions.md#the-classic-scenes): flat → Gouraud → Phong (rows) at three face counts (columns)."""
    triangles = {r["requested"]: r["triangles"] for r in study.rows}
    points = [n for n in study.config.figure_points if any(key[0] == n for key in study.frames)]
    rows = []
    for frequency in FREQUENCIES:
        rows.append([(f"{frequency}\n{triangles[n]:,} triangles", study.frames[n, frequency]) for n in points if (n, frequency) in study.frames])
    return contact_sheet([row for row in rows if row])


def _color_bar(width: int) -> np.ndarray:
    """A horizontal legend for heat_colors with ticks at the powers of ten."""
    from PIL import Image, ImageDraw, ImageFont

    low, high = HEAT_RANGE
    bar_width, bar_height = min(width - 40, 420), 14
    values = 10 ** np.linspace(math.log10(low), math.log10(high), bar_width)
    image = Image.new("RGB", (bar_width + 40, bar_height + 22), (255, 255, 255))
    image.paste(Image.fromarray(np.repeat(heat_colors(values)[None], bar_height, axis=0)), (20, 0))
    draw = ImageDraw.Draw(image)
    font = ImageFont.load_default(size=12)
    for exponent in range(int(math.log10(low)), int(math.log10(high)) + 1):
        x = 20 + (exponent - math.log10(low)) / (math.log10(high) - math.log10(low)) * (bar_width - 1)
        label = f"{10.0**exponent:g}/255"
        draw.line([(x, bar_height), (x, bar_height + 3)], fill=(0, 0, 0))
        draw.text((x - draw.textlength(label, font=font) / 2, bar_height + 5), label, fill=(0, 0, 0), font=font)
    return np.asarray(image)


def error_map_sheet(study: Study) -> np.ndarray:
    """Per-pixel error against the exact sphere, same grid as the seed figure; pixels left
    out of the comparison (outside the mesh or the silhouette band) are grey."""
    triangles = {r["requested"]: r["triangles"] for r in study.rows}
    points = [n for n in study.config.figure_points if any(key[0] == n for key in study.error_maps)]
    rows = []
    for frequency in FREQUENCIES:
        row = []
        for n in points:
            if (n, frequency) not in study.error_maps:
                continue
            errors, mask = study.error_maps[n, frequency]
            image = heat_colors(errors)
            image[~mask] = (128, 128, 128)
            p999 = np.percentile(errors[mask], 99.9) if mask.any() else float("nan")
            row.append((f"{frequency}, {triangles[n]:,} triangles\np99.9 {format_number(p999, 1)}/255", image))
        if row:
            rows.append(row)
    width = rows[0][0][1].shape[1] * max(len(r) for r in rows)
    return contact_sheet(rows, footer=_color_bar(width))


_FREQUENCY_MARKERS = {"flat": "s", "gouraud": "^", "phong": "o"}
_FREQUENCY_COLORS = {"flat": "tab:blue", "gouraud": "tab:orange", "phong": "tab:green"}


def pareto_plot(study: Study, path: Path) -> Path:
    """Error (p99.9 against the analytic truth of the variant's own reflection model) against
    median frame time, log axes, one panel per size; lines join the tessellations of one
    variant; the black steps are the Pareto front of the Phong-reflection points."""
    plt = require_matplotlib()
    sizes = sorted(study.config.sizes)
    figure, axes = plt.subplots(1, len(sizes), figsize=(max(5.2 * len(sizes), 8.0), 5.0), squeeze=False, sharey=True)
    shown_models = [("phong", "")] + [("blinn-phong", k) for m, k in study.config.reflections if m == "blinn-phong"][-1:]
    for axis, size in zip(axes[0], sizes):
        for model, k in shown_models:
            for frequency in study.config.frequencies:
                chosen = [r for r in study.rows if r["size"] == size and r["frequency"] == frequency and r["reflection"] == model and (model == "phong" or r["k_blinn"] == k)]
                if not chosen:
                    continue
                x = [r["time_ms"] for r in chosen]
                y = [max(r["p999"], 1e-3) for r in chosen]
                label = f"{frequency} / {'phong' if model == 'phong' else f'blinn k={k:g}'}"
                axis.plot(
                    x, y, linestyle="-" if model == "phong" else ":", marker=_FREQUENCY_MARKERS.get(frequency, "o"),
                    color=_FREQUENCY_COLORS.get(frequency), alpha=1.0 if model == "phong" else 0.55, markersize=5, label=label,
                )
                if model == "phong":
                    for r, xi, yi in zip(chosen, x, y):
                        if r["requested"] in (study.config.triangles[0], study.config.triangles[-1]) or r is chosen[len(chosen) // 2]:
                            axis.annotate(f"{r['triangles']:,}", (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7, color=_FREQUENCY_COLORS.get(frequency))
        phong_rows = [r for r in study.rows if r["size"] == size and r["reflection"] == "phong"]
        points = [(r["time_ms"], max(r["p999"], 1e-3)) for r in phong_rows]
        front = [points[i] for i in pareto_front(points)]
        if front:
            axis.step([p[0] for p in front], [p[1] for p in front], where="post", color="black", linewidth=1, alpha=0.6, label="Pareto front (phong refl.)")
        axis.axhline(1.0, color="red", linewidth=0.8, linestyle="--", label="1/255")
        axis.set_xscale("log")
        axis.set_yscale("log")
        plain = plt.FuncFormatter(lambda value, _: f"{value:g}")
        for which in (axis.xaxis, axis.yaxis):
            which.set_major_formatter(plain)
            which.set_minor_formatter(plt.FuncFormatter(lambda value, _: f"{value:g}" if f"{value:.0e}"[0] in "25" else ""))
        axis.set_xlabel("median frame time, ms (RGBA8, render + readback)")
        axis.set_title(f"{size}×{size}")
        axis.grid(True, which="major", alpha=0.3)
    axes[0][0].set_ylabel("p99.9 error vs exact sphere (1/255)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="lower center", ncol=5, fontsize=8, frameon=False)
    figure.tight_layout(rect=(0, 0.12, 1, 1))
    from ...assets.atomic import atomic_path

    with atomic_path(path) as temporary:
        figure.savefig(temporary, dpi=90, format="png")
    plt.close(figure)
    return path
