"""What accuracy costs in time: the accuracy/time study and the automatic shading choice.

This module gathers the study's public names in one namespace (the CLI and
`from wgpu_shading.study import accuracy as acc`); the code lives in

    accuracy_config    the study's scene, the shading Variants, the StudyConfig grid, AccuracyError
    accuracy_metrics   what "error" means (per-pixel, RMSE, p99.9, peak, highlight) and the analytic truth
    accuracy_sweep     run_study: render, measure and time every variant; Blinn-Phong k; environment
    accuracy_progress  the progress line of a long sweep
    accuracy_results   Study (the rows) and what follows from them: cheapest, pareto_front
    accuracy_tables    Markdown tables and the headline sentence
    accuracy_pictures  contact sheets, seed figure, error maps, the Pareto plot
    accuracy_write     write_study: CSV, JSON, table.md, pictures, docs/accuracy.md blocks
    accuracy_auto      `--shading auto`: auto_shading and AutoChoice

Errors are in units of 1/255 against float64 references (see accuracy_metrics for the
exact definitions); frame times are medians of warm RGBA8 frames (see accuracy_sweep).

Public API:

    run_study(config=StudyConfig(), renderer=None, progress=None) -> Study
    write_study(study, out_dir, markdown=None) -> list of written paths
    auto_shading(scene, max_error=1.0, renderer=None) -> AutoChoice
    pixel_error(image, reference) -> per-pixel error in 1/255
"""

from __future__ import annotations

from .accuracy_auto import TIE_FRACTION, AutoChoice, Candidate, auto_candidates, auto_shading
from .accuracy_config import (
    BLINN_KS,
    FULL_TRIANGLES,
    QUICK,
    STUDY_CAMERA,
    STUDY_LIGHT,
    STUDY_MATERIAL,
    STUDY_ROTATION,
    AccuracyError,
    StudyConfig,
    Variant,
    study_scene,
)
from .accuracy_metrics import (
    EDGE_BAND,
    ERROR_UNIT,
    PEAK_WINDOW,
    SILHOUETTE_BAND,
    ErrorStats,
    Truth,
    analytic_truth,
    highlight_error,
    peak_error,
    pixel_error,
    specular_peak,
)
from .accuracy_pictures import HEAT_RANGE, contact_sheet, error_map_sheet, heat_colors, pareto_plot, require_matplotlib, seed_figure
from .accuracy_progress import Progress
from .accuracy_results import ROW_FIELDS, Study, cheapest, pareto_front
from .accuracy_sweep import best_blinn_k, blinn_comparison, environment, run_study
from .accuracy_tables import (
    headline,
    markdown_blinn,
    markdown_cheapest,
    markdown_full_table,
    markdown_grid,
    markdown_same_mesh,
)
from .accuracy_write import generated_blocks, update_markdown, write_csv, write_study

__all__ = [
    "AccuracyError",
    "AutoChoice",
    "BLINN_KS",
    "Candidate",
    "EDGE_BAND",
    "ERROR_UNIT",
    "ErrorStats",
    "FULL_TRIANGLES",
    "HEAT_RANGE",
    "PEAK_WINDOW",
    "Progress",
    "QUICK",
    "ROW_FIELDS",
    "SILHOUETTE_BAND",
    "STUDY_CAMERA",
    "STUDY_LIGHT",
    "STUDY_MATERIAL",
    "STUDY_ROTATION",
    "Study",
    "StudyConfig",
    "TIE_FRACTION",
    "Truth",
    "Variant",
    "analytic_truth",
    "auto_candidates",
    "auto_shading",
    "best_blinn_k",
    "blinn_comparison",
    "cheapest",
    "contact_sheet",
    "environment",
    "error_map_sheet",
    "generated_blocks",
    "headline",
    "heat_colors",
    "highlight_error",
    "markdown_blinn",
    "markdown_cheapest",
    "markdown_full_table",
    "markdown_grid",
    "markdown_same_mesh",
    "pareto_front",
    "pareto_plot",
    "peak_error",
    "pixel_error",
    "require_matplotlib",
    "run_study",
    "seed_figure",
    "specular_peak",
    "study_scene",
    "update_markdown",
    "write_csv",
    "write_study",
]
