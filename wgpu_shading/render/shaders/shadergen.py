"""Feature set → WGSL source, from the files in `wgsl/` (preprocess.py: #include, #if and
the named points chunks put their code at).

An entry shader per frequency (`flat.wgsl`, `gouraud.wgsl`, `phong.wgsl`) and per pass
(`extra_outputs.wgsl`) reads as the list of the chunks it includes, one per effect
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

from ..features import FeatureSet
from .bindings import BindingPlan, binding_plan, extra_outputs_plan
from .preprocess import preprocess, read_source

ENTRY_FILES = {"flat": "flat.wgsl", "gouraud": "gouraud.wgsl", "phong": "phong.wgsl"}
GENERATED_BINDINGS = "bindings.wgsl"


def sources_for(features: FeatureSet | None) -> Callable[[str], str]:
    """The reader `preprocess` uses for `features` (None: the extra outputs pass): files of
    `wgsl/`, and the generated binding declarations under the name "bindings.wgsl"."""
    plan: BindingPlan = extra_outputs_plan() if features is None else binding_plan(features)

    def reader(name: str) -> str:
        return plan.wgsl() if name == GENERATED_BINDINGS else read_source(name)

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
    body = preprocess(ENTRY_FILES[features.frequency], features.defines(), sources_for(features))
    return _tidy("\n".join(header) + "\n\n" + body)


@lru_cache(maxsize=1)
def generate_extra_outputs_wgsl() -> str:
    """The normals-and-ids shader (wgsl/extra_outputs.wgsl with its generated bindings)."""
    return _tidy(preprocess("extra_outputs.wgsl", {}, sources_for(None)))
