"""Feature set → WGSL source, from the files in `wgsl/`.

The mechanism is a tiny preprocessor, deliberately smaller than C's:

    #include "lighting.wgsl"     paste a file once (later includes of it are skipped)
    #if SPOT_LIGHTS and not ATTENUATION
    #elif ... / #else / #endif   keep or drop lines

`#if` expressions use Python's syntax restricted to names, integers, `and`, `or`,
`not` and comparisons; every name must be one of `FeatureSet.defines()` (a typo is an
error, not a silently false branch). The generated module starts with a comment naming
the feature set and `const` declarations for the light counts.

One included file is generated, not read: "bindings.wgsl" is the binding plan's
declarations for the feature set (bind group entries and the vertex input struct; see
bindings.py), so the WGSL cannot disagree with the pipeline layout or the render pass.
"""

from __future__ import annotations

import ast
import re
from functools import lru_cache
from importlib.resources import files
from typing import Callable, Mapping

from .bindings import BindingPlan, binding_plan, extra_outputs_plan, shadow_map_plan
import numpy as np

from ..features import FeatureSet, shadow_view_capacity
from .layout import layouts_for

_DIRECTIVE = re.compile(r"^\s*#(include|if|elif|else|endif)\b(.*)$")
_INCLUDE = re.compile(r'^\s*"([\w.\-/]+)"\s*$')

ENTRY_FILES = {"flat": "flat.wgsl", "gouraud": "gouraud.wgsl", "phong": "phong.wgsl"}
GENERATED_BINDINGS = "bindings.wgsl"


class ShaderSourceError(Exception):
    """A malformed directive in a WGSL source file (a bug in the package, not user input)."""


@lru_cache(maxsize=None)
def read_source(name: str) -> str:
    """A file from the installed `wgsl/` folder (files never change while running)."""
    return (files("wgpu_shading.wgsl") / name).read_text(encoding="utf-8")


def sources_for(features: FeatureSet | None, plan: BindingPlan | None = None) -> Callable[[str], str]:
    """The reader `preprocess` uses for `features` (None: the extra outputs pass; or the
    `plan` given): files of `wgsl/`, and the generated binding declarations under the name
    "bindings.wgsl"."""
    if plan is None:
        plan = extra_outputs_plan() if features is None else binding_plan(features)

    def reader(name: str) -> str:
        return plan.wgsl() if name == GENERATED_BINDINGS else read_source(name)

    return reader


def _evaluate(expression: str, defines: Mapping[str, int | bool], where: str) -> bool:
    try:
        tree = ast.parse(expression.strip(), mode="eval")
    except SyntaxError:
        raise ShaderSourceError(f"{where}: cannot parse #if expression {expression.strip()!r}") from None

    def value(node: ast.AST) -> int | bool:
        if isinstance(node, ast.Expression):
            return value(node.body)
        if isinstance(node, ast.Name):
            if node.id not in defines:
                raise ShaderSourceError(f"{where}: unknown feature name {node.id!r} in #if")
            return defines[node.id]
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, bool)):
            return node.value
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            return not value(node.operand)
        if isinstance(node, ast.BoolOp):
            results = [bool(value(v)) for v in node.values]
            return all(results) if isinstance(node.op, ast.And) else any(results)
        if isinstance(node, ast.Compare) and len(node.ops) == 1:
            left, right = value(node.left), value(node.comparators[0])
            operations: dict[type, Callable[[int, int], bool]] = {
                ast.Eq: lambda a, b: a == b,
                ast.NotEq: lambda a, b: a != b,
                ast.Lt: lambda a, b: a < b,
                ast.LtE: lambda a, b: a <= b,
                ast.Gt: lambda a, b: a > b,
                ast.GtE: lambda a, b: a >= b,
            }
            for kind, operation in operations.items():
                if isinstance(node.ops[0], kind):
                    return operation(int(left), int(right))
        raise ShaderSourceError(f"{where}: unsupported #if expression {expression.strip()!r}")

    return bool(value(tree))


def preprocess(
    name: str,
    defines: Mapping[str, int | bool],
    reader: Callable[[str], str] = read_source,
    _included: set[str] | None = None,
) -> str:
    """Expand includes and conditionals of file `name` for the given defines."""
    included = set() if _included is None else _included
    if name in included:
        return ""
    included.add(name)
    output: list[str] = []
    # Each open #if: [enclosing block active, this branch active, some branch already taken]
    stack: list[list[bool]] = []
    active = True
    for number, line in enumerate(reader(name).splitlines(), start=1):
        where = f"{name}:{number}"
        match = _DIRECTIVE.match(line)
        if not match:
            if active:
                output.append(line)
            continue
        keyword, argument = match.group(1), match.group(2)
        if keyword == "include":
            if active:
                target = _INCLUDE.match(argument)
                if not target:
                    raise ShaderSourceError(f'{where}: expected #include "file.wgsl"')
                output.append(preprocess(target.group(1), defines, reader, included))
        elif keyword == "if":
            taken = active and _evaluate(argument, defines, where)
            stack.append([active, taken, taken])
            active = taken
        elif keyword == "elif":
            if not stack:
                raise ShaderSourceError(f"{where}: #elif without #if")
            enclosing, _, already = stack[-1]
            taken = enclosing and not already and _evaluate(argument, defines, where)
            stack[-1] = [enclosing, taken, already or taken]
            active = taken
        elif keyword == "else":
            if not stack:
                raise ShaderSourceError(f"{where}: #else without #if")
            enclosing, _, already = stack[-1]
            stack[-1] = [enclosing, enclosing and not already, True]
            active = enclosing and not already
        else:  # endif
            if not stack:
                raise ShaderSourceError(f"{where}: #endif without #if")
            active = stack.pop()[0]
    if stack:
        raise ShaderSourceError(f"{name}: {len(stack)} #if block(s) not closed")
    return "\n".join(output)


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
    header += _shadow_constants(features)
    body = preprocess(ENTRY_FILES[features.frequency], features.defines(), sources_for(features))
    return _tidy("\n".join(header) + "\n\n" + body)


def _shadow_constants(features: FeatureSet) -> list[str]:
    """The shadow lookup's sizes (wgsl/structs.wgsl ShadowUniforms, the chunk's loops)."""
    if not features.shadow_lights:
        return []
    point_like = features.spot_shadows + features.positional_shadows
    return [
        f"const SHADOW_LIGHT_COUNT: u32 = {features.shadow_lights}u;",
        f"const DIRECTIONAL_SHADOW_COUNT: u32 = {features.directional_shadows}u;",
        f"const SPOT_SHADOW_COUNT: u32 = {features.spot_shadows}u;",
        f"const POSITIONAL_SHADOW_COUNT: u32 = {features.positional_shadows}u;",
        f"const SHADOW_VIEW_CAPACITY: u32 = {shadow_view_capacity(features.directional_shadows, point_like)}u;",
        f"const SHADOW_FILTER_RADIUS: i32 = {SHADOW_FILTER_RADIUS[features.shadow_filter]};",
    ]


# The bilinear taps of a PCF filter on each side of the centre one (0: one tap, or nearest).
SHADOW_FILTER_RADIUS = {"nearest": 0, "bilinear": 0, "pcf3": 1, "pcf5": 2}


@lru_cache(maxsize=32)
def shadow_uniforms_dtype(directional: int, point_like: int) -> np.dtype:
    """The ShadowUniforms block of every shader that looks up `directional` + `point_like`
    casting lights (wgsl/structs.wgsl, the one declaration), for the shadow pass to fill."""
    features = FeatureSet(directional_shadows=directional, positional_shadows=point_like, shadow_filter="nearest")
    source = "\n".join(_shadow_constants(features)) + "\n" + preprocess("structs.wgsl", features.defines())
    return layouts_for(source).dtype("ShadowUniforms")


@lru_cache(maxsize=1)
def generate_shadow_map_wgsl() -> str:
    """The shadow pass's depth-only shader (wgsl/shadow_map.wgsl with its generated bindings)."""
    return _tidy(preprocess("shadow_map.wgsl", {}, sources_for(None, shadow_map_plan())))


@lru_cache(maxsize=1)
def generate_extra_outputs_wgsl() -> str:
    """The normals-and-ids shader (wgsl/extra_outputs.wgsl with its generated bindings)."""
    return _tidy(preprocess("extra_outputs.wgsl", {}, sources_for(None)))
