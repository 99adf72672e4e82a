"""What accuracy costs in time: the accuracy/time study (`wgpu-shading bench accuracy`,
docs/accuracy.md).

    from wgpu_shading.study import accuracy
    study = accuracy.run_study(accuracy.QUICK)
    accuracy.write_study(study, "accuracy-out")

The modules, in the order the study runs:

    config.py     the study's scene, the StudyConfig grid of shading Variants, QUICK
    metrics.py    what "error" means against the analytic truth (silhouette band, specular
                  peak, highlight); the per-pixel measure itself is render/image_error.py
    sweep.py      run_study: render, measure and time every variant; Blinn-Phong k; environment
    progress.py   the progress line of a long sweep
    results.py    Study (the rows) and what follows from them: cheapest, pareto_front
    tables.py     Markdown tables and the headline sentence
    pictures.py   contact sheets, seed figure, error maps, the Pareto plot
    write.py      write_study: CSV, JSON, table.md, pictures, docs/accuracy.md blocks
    shadow_sweep.py   shadows: map size × filter × bias against the exact shadows, timed
    shadow_choice.py  the rule `auto` follows for shadows: the cheapest setting within the budget
    shadow_write.py   shadows.csv/.json/.md, the error-against-cost plot, docs/accuracy.md's shadows blocks

Errors are in units of 1/255 against float64 references (`study/reference/`); frame times
are medians of warm RGBA8 frames (see sweep.py). The automatic shading choice that uses
the same error measure is a renderer feature: `wgpu_shading.auto_shading`
(render/auto_shading.py).
"""

from __future__ import annotations

from ...errors import AccuracyError
from ...render.auto_shading import Variant
from .config import QUICK, STUDY_MATERIAL, StudyConfig, study_scene
from .pictures import require_matplotlib
from .results import Study
from .shadow_choice import ShadowBudget, cases_over_budget, cheapest_shadow_setting, qualifying_settings
from .shadow_sweep import (
    QUICK_SHADOW_CASES, ShadowPoint, ShadowSetting, gpu_draws_shadows, quick_shadow_grid, run_shadow_study, shadow_grid,
    shadow_table,
)
from .shadow_write import load_shadow_points, write_shadow_study
from .sweep import environment, run_study
from .tables import headline
from .write import update_markdown, write_study

__all__ = [
    "ShadowBudget", "ShadowPoint", "ShadowSetting", "cases_over_budget", "cheapest_shadow_setting", "gpu_draws_shadows", "qualifying_settings",
    "run_shadow_study", "shadow_grid", "shadow_table", "QUICK_SHADOW_CASES", "quick_shadow_grid", "load_shadow_points",
    "write_shadow_study", "environment",
    "AccuracyError",
    "QUICK",
    "STUDY_MATERIAL",
    "Study",
    "StudyConfig",
    "Variant",
    "headline",
    "require_matplotlib",
    "run_study",
    "study_scene",
    "update_markdown",
    "write_study",
]
