"""Feature set → WGSL source, from the files in `wgsl/` (preprocess.py: #include, #if and
the named points chunks put their code at).

An entry shader per frequency (`flat.wgsl`, `gouraud.wgsl`, `phong.wgsl`), per primitive
(`points.wgsl`, `lines.wgsl`) and per pass (`shadow_map.wgsl`, `extra_outputs.wgsl`, …:
`generate_pass_wgsl`) reads as the list of the chunks it includes, one per effect
(`wgsl/chunks/`); the feature set's defines keep the code of the effects a draw uses and
drop the rest. The generated module starts with a comment naming the feature set and
`const` declarations for the light counts.

One included file is generated, not read: "bindings.wgsl" is the binding plan's
declarations for the feature set (bind group entries and the vertex input struct; see
bindings.py), so the WGSL cannot disagree with the pipeline layout or the render pass.
"""

from __future__ import annotations

import re
from functools import lru_cache
from typing import Callable

import numpy as np

from ..features import FeatureSet
from .bindings import BindingPlan, binding_plan
from .layout import layouts_for
from .preprocess import preprocess, read_source

ENTRY_FILES = {"flat": "flat.wgsl", "gouraud": "gouraud.wgsl", "phong": "phong.wgsl"}  # triangles, by frequency
STROKE_ENTRY_FILES = {"points": "points.wgsl", "lines": "lines.wgsl"}  # docs/primitives.md
GENERATED_BINDINGS = "bindings.wgsl"
UV_SETS_TEMPLATE = "chunks/surface/uv_sets.wgsl"
# Set k's varying is at location k + 4, after every other varying of the entry shaders; with
# shadows, whose varyings take locations 5..25 (chunks/shadows/), at k + 25.
UV_SET_LOCATION_BEFORE, UV_SET_LOCATION_BEFORE_WITH_SHADOWS = 4, 25


def sources_for(features: FeatureSet | None, plan: BindingPlan | None = None) -> Callable[[str], str]:
    """The reader `preprocess` uses for `features` (its binding plan, or the `plan` given:
    a pass's own, whose features may be None): files of `wgsl/`, the generated binding declarations under the name
    "bindings.wgsl", and the template of the other texture coordinate sets written once per
    set the draw reads."""
    if plan is None:
        plan = binding_plan(features)

    def reader(name: str) -> str:
        if name == GENERATED_BINDINGS:
            return plan.wgsl()
        if name == UV_SETS_TEMPLATE:
            template = read_source(name)
            sets = () if features is None else features.extra_uv_sets
            before = UV_SET_LOCATION_BEFORE_WITH_SHADOWS if features is not None and features.shadow_lights else UV_SET_LOCATION_BEFORE
            return "\n".join(template.replace("%SET%", str(k)).replace("%LOCATION%", str(before + k)) for k in sets)
        return read_source(name)

    return reader


def _tidy(source: str) -> str:
    """Collapse the blank lines that removed blocks leave behind."""
    return re.sub(r"\n\s*\n(\s*\n)+", "\n\n", source).strip() + "\n"


@lru_cache(maxsize=256)
def generate_wgsl(features: FeatureSet) -> str:
    """The complete WGSL module (vertex and fragment entry points) for a feature set."""
    header = [f"// wgpu-shading generated shader: {features.describe()}"]
    for count, constant in (
        (features.directional_lights, "DIRECTIONAL_LIGHT_COUNT"),
        (features.positional_lights, "POSITIONAL_LIGHT_COUNT"),
        (features.spot_lights, "SPOT_LIGHT_COUNT"),
    ):
        if count:
            header.append(f"const {constant}: u32 = {count}u;")
    # The texture coordinate set each sampled texture reads (surface_uv_of, chunks/surface/uvs.wgsl).
    header += [f"const {texture.name.upper()}_UV_SET: u32 = {features.uv_set(texture.name)}u;" for texture in binding_plan(features).textures]
    header += _shadow_constants(features)
    entry = STROKE_ENTRY_FILES.get(features.primitive) or ENTRY_FILES[features.frequency]
    body = preprocess(entry, features.defines(), sources_for(features))
    return _tidy("\n".join(header) + "\n\n" + body)


def _shadow_constants(features: FeatureSet) -> list[str]:
    """The shadow lookup's sizes (wgsl/structs.wgsl ShadowUniforms, the chunks' loops)."""
    if not features.shadow_lights:
        return []
    return [
        f"const SHADOW_LIGHT_COUNT: u32 = {features.shadow_lights}u;",
        f"const DIRECTIONAL_SHADOW_COUNT: u32 = {features.directional_shadows}u;",
        f"const SPOT_SHADOW_COUNT: u32 = {features.spot_shadows}u;",
        f"const POSITIONAL_SHADOW_COUNT: u32 = {features.positional_shadows}u;",
        f"const SHADOW_FILTER_RADIUS: i32 = {SHADOW_FILTER_RADIUS[features.shadow_filter]};",
    ]


# The bilinear taps of a PCF filter on each side of the centre one (0: one tap, or nearest).
SHADOW_FILTER_RADIUS = {"nearest": 0, "bilinear": 0, "pcf3": 1, "pcf5": 2}


@lru_cache(maxsize=32)
def shadow_uniforms_dtype(lights: int) -> np.dtype:
    """The ShadowUniforms block of every shader that looks up `lights` casting lights
    (wgsl/structs.wgsl, the one declaration), for the shadow pass to fill."""
    features = FeatureSet(positional_shadows=lights, shadow_filter="nearest")
    source = "\n".join(_shadow_constants(features)) + "\n" + preprocess("structs.wgsl", features.defines())
    return layouts_for(source).dtype("ShadowUniforms")


@lru_cache(maxsize=16)
def generate_pass_wgsl(entry: str, plan: BindingPlan) -> str:
    """The shader of a pass that draws with its own entry file in `wgsl/` (the shadow maps'
    `shadow_map.wgsl`, the extra outputs' `extra_outputs.wgsl`, …): the file with the plan's
    generated bindings, under the defines of the plan's feature set (None: every define
    false). A new pass names its entry file and plan here; it adds no function."""
    return _tidy(preprocess(entry, (plan.features or FeatureSet()).defines(), sources_for(plan.features, plan)))
