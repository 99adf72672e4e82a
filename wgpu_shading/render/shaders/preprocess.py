"""The WGSL preprocessor: a few directives, deliberately fewer than C's.

    #include "chunks/maps/occlusion_map.wgsl"   paste a file once (later includes of it are skipped)
    #if SPOT_LIGHTS and not ATTENUATION
    #elif ... / #else / #endif                  keep or drop lines
    #hook lighting.light_diffuse  // what     a named point of the shader (and what goes there)
    #at lighting.light_diffuse [more.points]    the lines up to #end go to those points
    #end
    #for LIGHT < SHADOW_LIGHTS                  the lines up to #endfor, once per LIGHT = 0, 1, …
    #endfor                                     with {{LIGHT}}, {{6 + 4 * LIGHT}} written out

An entry shader (wgsl/phong.wgsl) reads as the list of the chunks it includes, one per
effect (wgsl/chunks/). A chunk declares what it needs (functions, private variables) where
it is included, and puts its code at the named points (`#hook`) of the entry shader and of
the shared parts (lighting.wgsl, output.wgsl): what every chunk puts `#at` one point is
pasted at its `#hook`, in the order the chunks are included, wherever the `#hook` is
(before or after the include). A point may appear once; lines put at a point the shader
does not have are dropped (a chunk serves several entry shaders, each with its own
points; tests/test_shadergen.py checks that every `#at` names a `#hook` of some file).
Points may hold points of their own.

`#for` repeats what one light (or one of any counted thing) needs where WGSL cannot index:
interstage variables are one per location, so the shadow chunks write one per casting light.
The loop is unrolled before anything else, so its body may hold `#if`s; a `{{…}}` in it is an
integer expression of the loop's name (`+`, `-`, `*`), written out for each pass; loops do
not nest.

`#if` expressions use Python's syntax restricted to names, integers, `and`, `or`, `not`
and comparisons; every name must be one of `FeatureSet.defines()` (a typo is an error,
not a silently false branch).
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Callable, Mapping

from ...assets.files import installed_folder

_DIRECTIVE = re.compile(r"^\s*#(include|if|elif|else|endif|hook|at|end)\b(.*)$")
_FOR = re.compile(r"^\s*#for\s+([A-Z_][A-Z0-9_]*)\s*<\s*([A-Z_][A-Z0-9_]*)\s*$")
_ENDFOR = re.compile(r"^\s*#endfor\s*$")
_SUBSTITUTION = re.compile(r"\{\{([^{}]*)\}\}")
_INCLUDE = re.compile(r'^\s*"([\w.\-/]+)"\s*$')
_POINT = re.compile(r"^[A-Za-z_][\w.]*$")


class ShaderSourceError(Exception):
    """A malformed directive in a WGSL source file (a bug in the package, not user input)."""


@lru_cache(maxsize=None)
def read_source(name: str) -> str:
    """A file from the installed `wgsl/` folder, by its path there (files never change while running)."""
    return (installed_folder("wgpu_shading.wgsl") / name).read_text(encoding="utf-8")


@lru_cache(maxsize=1024)  # the #if lines of the wgsl/ files: a fixed set, parsed once a process
def _parsed_condition(expression: str) -> ast.Expression | None:
    try:
        return ast.parse(expression.strip(), mode="eval")
    except SyntaxError:
        return None


def _evaluate(expression: str, defines: Mapping[str, int | bool], where: str) -> bool:
    tree = _parsed_condition(expression)
    if tree is None:
        raise ShaderSourceError(f"{where}: cannot parse #if expression {expression.strip()!r}")

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


def _arithmetic(expression: str, name: str, value: int, where: str) -> int:
    """`{{6 + 4 * LIGHT}}`'s integer, for LIGHT = value."""
    try:
        tree = ast.parse(expression.strip(), mode="eval").body
    except SyntaxError:
        tree = None

    def evaluate(node: ast.AST | None) -> int:
        if isinstance(node, ast.Name) and node.id == name:
            return value
        if isinstance(node, ast.Constant) and type(node.value) is int:
            return node.value
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult)):
            left, right = evaluate(node.left), evaluate(node.right)
            return left + right if isinstance(node.op, ast.Add) else left - right if isinstance(node.op, ast.Sub) else left * right
        raise ShaderSourceError(f"{where}: expected an integer expression of {name} in {{{{{expression}}}}}")

    return evaluate(tree)


def _unroll(source: str, defines: Mapping[str, int | bool], name: str) -> list[tuple[int, str]]:
    """The numbered lines of `source` with each `#for NAME < COUNT` … `#endfor` written out
    COUNT times (a written-out line keeps its number in the file, for error messages)."""
    output: list[tuple[int, str]] = []
    loop: tuple[str, int, list[tuple[int, str]], str] | None = None  # (loop name, count, body, where)
    for number, line in enumerate(source.splitlines(), start=1):
        where = f"{name}:{number}"
        start, end = _FOR.match(line), _ENDFOR.match(line)
        if start:
            if loop is not None:
                raise ShaderSourceError(f"{where}: #for inside a #for")
            if start.group(2) not in defines:
                raise ShaderSourceError(f"{where}: unknown feature name {start.group(2)!r} in #for")
            loop = (start.group(1), int(defines[start.group(2)]), [], where)
        elif end:
            if loop is None:
                raise ShaderSourceError(f"{where}: #endfor without #for")
            variable, count, body, loop_where = loop
            for index in range(count):
                output.extend(
                    (line_number, _SUBSTITUTION.sub(lambda m: str(_arithmetic(m.group(1), variable, index, loop_where)), text))
                    for line_number, text in body
                )
            loop = None
        elif loop is not None:
            loop[2].append((number, line))
        else:
            output.append((number, line))
    if loop is not None:
        raise ShaderSourceError(f"{loop[3]}: #for not closed with #endfor")
    return output


@dataclass(frozen=True)
class _Hook:
    """Where the lines put at a named point go, in the expanded source."""

    name: str
    where: str


@dataclass
class _Expansion:
    """The state of one preprocess() run: its defines, its reader, what it has included and
    the lines put #at each point so far."""

    defines: Mapping[str, int | bool]
    reader: Callable[[str], str]
    included: set[str] = field(default_factory=set)
    # point name → the lines (and nested points) put #at it, in include order
    at_points: dict[str, list[str | _Hook]] = field(default_factory=dict)

    def expand(self, name: str) -> list[str | _Hook]:
        """The lines of file `name` with its includes and conditionals resolved; its #at
        blocks are set aside in `at_points`, its #hook lines left as _Hook markers."""
        if name in self.included:
            return []
        self.included.add(name)
        output: list[str | _Hook] = []
        # Each open #if: [enclosing block active, this branch active, some branch already taken]
        stack: list[list[bool]] = []
        active = True
        block: tuple[list[str], list[str | _Hook], int, str] | None = None  # (points, lines, #if depth, where)
        for number, line in _unroll(self.reader(name), self.defines, name):
            where = f"{name}:{number}"
            match = _DIRECTIVE.match(line)
            target = output if block is None else block[1]
            if not match:
                if active:
                    target.append(line)
                continue
            keyword, argument = match.group(1), match.group(2).strip()
            if keyword == "include":
                if block is not None:
                    raise ShaderSourceError(f"{where}: #include inside an #at block")
                if active:
                    path = _INCLUDE.match(argument)
                    if not path:
                        raise ShaderSourceError(f'{where}: expected #include "file.wgsl"')
                    output.extend(self.expand(path.group(1)))
            elif keyword == "hook":
                argument = argument.split("//", 1)[0].strip()  # a comment may say what goes there
                if not _POINT.match(argument):
                    raise ShaderSourceError(f"{where}: expected #hook name.of.point")
                if active:
                    target.append(_Hook(argument, where))
            elif keyword == "at":
                if block is not None:
                    raise ShaderSourceError(f"{where}: #at inside an #at block (close it with #end)")
                points = argument.split()
                if not points or not all(_POINT.match(point) for point in points):
                    raise ShaderSourceError(f"{where}: expected #at name.of.point [more.points]")
                block = (points if active else [], [], len(stack), where)
            elif keyword == "end":
                if block is None:
                    raise ShaderSourceError(f"{where}: #end without #at")
                if len(stack) != block[2]:
                    raise ShaderSourceError(f"{where}: #end inside an #if that began in its #at block")
                for point in block[0]:
                    self.at_points.setdefault(point, []).extend(block[1])
                block = None
            elif keyword == "if":
                taken = active and _evaluate(argument, self.defines, where)
                stack.append([active, taken, taken])
                active = taken
            elif keyword in ("elif", "else"):
                if not stack:
                    raise ShaderSourceError(f"{where}: #{keyword} without #if")
                enclosing, _, already = stack[-1]
                taken = enclosing and not already and (keyword == "else" or _evaluate(argument, self.defines, where))
                stack[-1] = [enclosing, taken, already or taken]
                active = taken
            else:  # endif
                if not stack:
                    raise ShaderSourceError(f"{where}: #endif without #if")
                if block is not None and len(stack) == block[2]:
                    raise ShaderSourceError(f"{where}: #endif of an #if that began before the #at block (close it with #end first)")
                active = stack.pop()[0]
        if block is not None:
            raise ShaderSourceError(f"{block[3]}: #at block not closed with #end")
        if stack:
            raise ShaderSourceError(f"{name}: {len(stack)} #if block(s) not closed")
        return output

    def resolve(self, lines: list[str | _Hook], placed: set[str]) -> list[str]:
        """The lines with every #hook replaced by what was put at its point."""
        output: list[str] = []
        for line in lines:
            if isinstance(line, str):
                output.append(line)
                continue
            if line.name in placed:
                raise ShaderSourceError(f"{line.where}: the point {line.name} appears twice in this shader")
            placed.add(line.name)
            output.extend(self.resolve(self.at_points.get(line.name, []), placed))
        return output


def preprocess(name: str, defines: Mapping[str, int | bool], reader: Callable[[str], str] = read_source) -> str:
    """File `name` with its includes, conditionals and named points resolved for `defines`."""
    expansion = _Expansion(defines, reader)
    return "\n".join(expansion.resolve(expansion.expand(name), set()))
